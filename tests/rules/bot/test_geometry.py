"""The bot's planning geometry against the real engine: the pots it sees do drop, its chance
estimate orders pots as the engine does, and a throw-corrected heading sends the object ball
closer to its line than the plain ghost-ball aim."""

from __future__ import annotations

import math
import random

import physics
from rules.bot.candidates import Candidate, Kind, pot_speed
from rules.bot.geometry import Via, banks, best_pots, combos, pots
from rules.bot.noise import tournament
from rules.bot.search import throw_corrected
from rules.game import play, scene, shot_position
from rules.inputs import Shot, Strike
from rules.spots import POOL_TABLE
from rules.state import State

T = POOL_TABLE
NOISE = tournament(1.0)


def nineball(balls: dict) -> State:
    return State(game="nineball", balls=balls, shots=4)


def exact(state: State, pot) -> Shot:
    return Shot(strike=Strike(ball="cue", speed=pot_speed(pot), heading=pot.heading))


def test_a_straight_pot_it_sees_drops():
    state = nineball({"cue": (0.5, 1.0), "1": (0.8, 1.8), "9": (0.2, 2.2)})
    found = pots(T, state.balls["cue"], state.balls, frozenset({"1"}), NOISE)
    assert found and found[0].via == Via.DIRECT
    assert "1" in play(state, exact(state, found[0])).decision.pocketed


def test_nearer_and_straighter_pots_are_likelier():
    balls = {"cue": (0.635, 1.0), "1": (0.635, 1.6), "9": (0.2, 0.4)}
    far = {**balls, "cue": (0.635, 0.3)}
    near_cut = pots(T, balls["cue"], balls, frozenset({"1"}), NOISE)
    far_cut = pots(T, far["cue"], far, frozenset({"1"}), NOISE)
    best = {p.pocket: p.chance for p in near_cut}
    assert all(p.chance < best[p.pocket] for p in far_cut if p.pocket in best)


def test_a_combination_it_sees_drops():
    """The 1 and the 9 in line with the top-right pocket: the 1 into the 9 pots the 9."""
    pocket = next(p for p in T.pockets if p.name == "top_right")
    line = (-math.sqrt(0.5), -math.sqrt(0.5))
    nine = (pocket.center[0] + 0.25 * line[0], pocket.center[1] + 0.25 * line[1])
    one = (pocket.center[0] + 0.45 * line[0], pocket.center[1] + 0.45 * line[1])
    cue = (pocket.center[0] + 1.0 * line[0], pocket.center[1] + 1.0 * line[1] - 0.1)
    state = nineball({"cue": cue, "1": one, "9": nine})
    found = [
        p for p in combos(T, cue, state.balls, frozenset({"1"}), NOISE) if p.pocket == "top_right"
    ]
    assert found and found[0].via == Via.COMBO
    outcome = play(state, exact(state, found[0]))
    assert outcome.state.over and outcome.state.winner == 0


def test_a_bank_it_sees_drops():
    """The 1 near the left rail, the side pocket across the table: banked off the left rail
    into the right side pocket."""
    state = nineball({"cue": (0.6, 0.7), "1": (0.3, 1.0), "9": (1.0, 2.3)})
    found = [p for p in banks(T, state.balls["cue"], state.balls, frozenset({"1"}), NOISE)]
    assert found
    dropped = [p for p in found[:3] if "1" in play(state, exact(state, p)).decision.pocketed]
    assert dropped


def _direction_error(state: State, c: Candidate) -> float:
    result = physics.simulate(scene(state, c.shot, shot_position(state, c.shot)))
    seg = next(s for s in result.trajectories[c.pot.target] if s.v != (0.0, 0.0))
    at = state.balls[c.pot.target]
    want = math.atan2(at[1] - c.pot.ghost[1], at[0] - c.pot.ghost[0])
    return abs(math.remainder(math.atan2(seg.v[1], seg.v[0]) - want, math.tau))


def test_the_throw_correction_straightens_the_object_ball():
    state = nineball({"cue": (0.2, 1.6), "1": (0.8, 1.8), "9": (0.3, 2.2)})
    cut = next(
        p
        for p in pots(T, state.balls["cue"], state.balls, frozenset({"1"}), NOISE)
        if p.cos_cut < 0.9
    )
    plain = Candidate(exact(state, cut), Kind.POT, cut)
    fixed = throw_corrected(state, plain, physics.simulate)
    assert fixed.shot.strike.heading != plain.shot.strike.heading
    assert _direction_error(state, fixed) < 0.5 * _direction_error(state, plain)


def test_a_pot_the_engine_fails_on_is_kept_uncorrected():
    state = nineball({"cue": (0.2, 1.6), "1": (0.8, 1.8), "9": (0.3, 2.2)})
    cut = pots(T, state.balls["cue"], state.balls, frozenset({"1"}), NOISE)[0]
    plain = Candidate(exact(state, cut), Kind.POT, cut)

    def failing(scene):
        raise physics.BudgetExceeded("the engine gave up")

    assert throw_corrected(state, plain, failing) == plain


def test_best_pots_are_the_pots_ranked_by_worth():
    """best_pots checks paths lazily, from the best down: the same pots as every pot ranked by
    the worth given (ties likeliest first), on crowded random racks."""
    rng = random.Random(5)
    for _ in range(30):
        balls = {str(k): (rng.uniform(0.1, 1.17), rng.uniform(0.1, 2.44)) for k in range(1, 10)}
        balls["cue"] = (rng.uniform(0.1, 1.17), rng.uniform(0.1, 2.44))
        targets = frozenset(rng.sample([str(k) for k in range(1, 10)], 4))

        def worth(a) -> float:
            return a.chance * (1 + int(a.target))

        every = pots(T, balls["cue"], balls, targets, NOISE)
        for n in (1, 2):
            ranked = sorted(every, key=lambda a: -worth(a))[:n]
            assert best_pots(T, balls["cue"], balls, targets, NOISE, n, worth) == ranked

"""The bot's behaviour: inputs the referee accepts, the obvious pot, safeties, escapes,
replays, determinism and its search budget. Through the real engine unless a stand-in counts."""

from __future__ import annotations

import itertools
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

import physics
from rules.aim import snookered
from rules.bot.candidates import COARSE, FINE, Kind, candidates, kicks, spots
from rules.bot.chooser import Bot, Picker, chooser
from rules.bot.geometry import cushion_bounces
from rules.bot.levels import LEVELS, STRONGEST, level
from rules.bot.noise import draws, perturb, tournament
from rules.bot.search import EXACT, InProcess, Task, run_task, search
from rules.bot.value import KEEP_SURE
from rules.game import Setup, check, play, start
from rules.inputs import Choice, Shot, Strike
from rules.racks import Game
from rules.record import GameRecord, replay
from rules.referee import allowed, referee
from rules.spots import POOL_TABLE, SNOOKER, SNOOKER_SPOTS
from rules.state import State
from tests.rules.bot.positions import random_position

ROOT = Path(__file__).resolve().parents[3]
#: The cheapest level: enough to exercise every path of a decision.
QUICK = level(1)


@pytest.mark.parametrize("game", list(Game))
def test_there_is_always_a_candidate_the_referee_accepts(game):
    for seed in range(100):
        state = random_position(game, seed)
        if state.pending:
            continue
        found = candidates(state, STRONGEST)
        assert found, (game, seed)
        for c in found:
            check(state, c.shot)


@pytest.mark.parametrize("game", list(Game))
def test_the_bot_never_sends_a_refused_input(game):
    """Its own choice, and the same input under the arena's noise, pass the referee's check."""
    bot = Bot(QUICK, seed=7)
    R = referee(game).TABLE.R
    for seed in range(25):
        state = random_position(game, 100 + seed)
        action = bot.choose(state)
        check(state, action)
        assert isinstance(action, Choice) == bool(state.pending)
        if isinstance(action, Shot):
            for d in draws(seed, 20, "test"):
                check(state, perturb(action, tournament(3.0), d, R))


def nineball(balls: dict, **fields) -> State:
    return State(game=Game.NINEBALL, balls=balls, shots=5, **fields)


def test_it_finds_the_obvious_pot():
    """The 1 in the jaws of the top-right pocket, the cue ball straight behind it."""
    pocket = next(p for p in POOL_TABLE.pockets if p.name == "top_right")
    along = (-0.7071, -0.7071)
    one = (pocket.center[0] + 0.12 * along[0], pocket.center[1] + 0.12 * along[1])
    cue = (pocket.center[0] + 0.6 * along[0], pocket.center[1] + 0.6 * along[1])
    state = nineball({"cue": cue, "1": one, "5": (0.3, 0.5), "9": (0.4, 1.0)})
    shot = Bot(STRONGEST, seed=1).choose(state)

    def potted(played: Shot) -> bool:
        decision = play(state, played).decision
        return "1" in decision.pocketed and not decision.fouls

    # As chosen it pots; under a tournament player's noise it pots nearly always (the bot may
    # trade a sliver of certainty for the cue ball's leave, never a real chance of a miss).
    assert potted(shot)
    noisy = [perturb(shot, tournament(1.0), d, POOL_TABLE.R) for d in draws(1, 40, "pot")]
    assert sum(map(potted, noisy)) >= 36


def test_it_plays_safe_when_no_pot_is_likely():
    """The 1 frozen to the middle of the top rail, the cue ball at the other end: no pot is
    on, so the bot plays a contact that the referee rules legal."""
    R = POOL_TABLE.R
    state = nineball(
        {"cue": (0.635, 0.3), "1": (0.635, POOL_TABLE.length - R - 1e-4), "9": (0.2, 1.2)}
    )
    bot = Bot(STRONGEST, seed=1)
    shot = bot.choose(state)
    assert bot.last.kind in (Kind.CONTACT, Kind.KICK)
    outcome = play(state, shot)
    assert not outcome.decision.fouls


def test_it_escapes_a_snooker():
    """The last red up the table, hidden behind the brown just in front of the cue ball: the
    bot hits it anyway, off a cushion."""
    balls = {**SNOOKER_SPOTS, "cue": (0.9, 0.5), "brown": (0.9, 0.62), "red1": (0.4, 3.0)}
    state = State(game=Game.SNOOKER, balls=balls, shots=9, on="red")
    assert snookered("cue", {"red1"}, balls, SNOOKER.R)
    bot = Bot(STRONGEST, seed=2)
    shot = bot.choose(state)
    assert bot.last.kind == Kind.KICK
    decision = play(state, shot).decision
    assert not decision.fouls


#: Random nine-ball positions (tests.rules.bot.positions) in which the 1 can be reached by
#: no straight line and no one-cushion path, only off two cushions.
TWO_CUSHION_SNOOKERS = (53, 226, 815, 846)


@pytest.mark.parametrize("seed", TWO_CUSHION_SNOOKERS)
def test_it_escapes_a_snooker_off_two_cushions(seed):
    state = random_position(Game.NINEBALL, seed)
    spot = spots(state)[0]
    (on,) = allowed(state).targets
    assert snookered("cue", {on}, state.balls, POOL_TABLE.R)
    assert not any(
        kicks(spot, on, (b,)) for b in cushion_bounces(POOL_TABLE, spot.cue, state.balls[on])
    )
    bot = Bot(STRONGEST, seed=1)
    shot = bot.choose(state)
    assert bot.last.kind == Kind.KICK
    assert not play(state, shot).decision.fouls


def test_its_one_cushion_kick_hits_the_ball_under_the_noise():
    """A random nine-ball position (seed 333) where the 1 is hidden but open off one cushion:
    a cushion is no mirror, so a kick aimed only at the mirror heading fouled in 70% of plays
    under the tournament noise. The kick the bot chooses from its fan of headings hits the 1
    in most of them."""
    state = random_position(Game.NINEBALL, 333)
    spot = spots(state)[0]
    (on,) = allowed(state).targets
    assert snookered("cue", {on}, state.balls, POOL_TABLE.R)
    assert any(
        kicks(spot, on, (b,)) for b in cushion_bounces(POOL_TABLE, spot.cue, state.balls[on])
    )
    bot = Bot(STRONGEST, seed=7)
    shot = bot.choose(state)
    assert bot.last.kind == Kind.KICK
    noise, R = tournament(1.0), POOL_TABLE.R
    plays = [play(state, perturb(shot, noise, d, R)) for d in draws(4, 40, "kick test")]
    assert sum(bool(o.decision.fouls) for o in plays) <= 10


def test_a_game_against_the_bot_replays_from_its_record():
    setup = Setup(game=Game.NINEBALL, seed=4)
    state = start(setup)
    record = GameRecord.begin(setup, state)
    players = (Bot(QUICK, seed=3), Picker())
    for _ in range(12):
        if state.over:
            break
        action = players[state.turn].choose(state)
        state = play(state, action).state
        record = record.extend(action, state)
    again = replay(GameRecord.from_json(record.to_json()))
    assert again.steps[-1].state == state


def test_same_seed_same_input_other_seed_other_noise():
    state = random_position(Game.NINEBALL, 11).evolve(pending=())
    a = Bot(level(2), seed=5).choose(state)
    assert Bot(level(2), seed=5).choose(state) == a
    others = {Bot(level(2), seed=s).choose(state) for s in range(6, 10)}
    assert any(o != a for o in others)  # the hand noise is drawn from the seed


def test_worker_processes_decide_as_one_process_does():
    state = random_position(Game.EIGHTBALL, 3).evolve(pending=())
    alone = Bot(level(2), seed=9).choose(state)
    bot = Bot(level(2), seed=9, workers=2)
    try:
        assert bot.choose(state) == alone
    finally:
        bot.close()


class Counting:
    """The real engine, counting its calls."""

    def __init__(self) -> None:
        self.calls = 0

    def __call__(self, scene: physics.Scene) -> physics.Shot:
        self.calls += 1
        return physics.simulate(scene)


@pytest.mark.parametrize("lv", LEVELS[:3], ids=lambda lv: f"level{lv.number}")
def test_the_search_stays_within_its_simulation_budget(lv):
    for game, seed in itertools.product((Game.NINEBALL, Game.THREE_CUSHION), (1, 2)):
        state = random_position(game, seed).evolve(pending=())
        engine = Counting()
        Bot(lv, seed=1, simulate=engine).choose(state)
        assert engine.calls <= lv.budget


def test_the_wall_clock_cap_stops_the_search_between_stages():
    """A clock that jumps past the cap at every reading: only the screen runs."""
    ticks = itertools.count(step=10_000.0)
    state = random_position(Game.NINEBALL, 5).evolve(pending=())
    engine = Counting()
    _, report = search(
        state, STRONGEST, 1, tournament(1.0), InProcess(engine), engine, clock=lambda: next(ticks)
    )
    assert report.capped and report.stages == 0
    assert engine.calls == report.simulations <= 2 * STRONGEST.screen


def test_a_search_given_strokes_screens_their_variations_and_no_others():
    """`search(strokes=...)` varies the pots as told (bench/strokes.py compares sets so); given
    the level's own set it is the level's search."""
    state = random_position(Game.NINEBALL, 5).evolve(pending=())
    coarse, seen = search(state, level(2), 1, tournament(1.0), InProcess(), strokes=COARSE)
    shot, report = search(state, level(2), 1, tournament(1.0), InProcess())
    assert (coarse, seen.candidates, seen.simulations) == (
        shot,
        report.candidates,
        report.simulations,
    )
    _, fine = search(state, level(2), 1, tournament(1.0), InProcess(), strokes=FINE)
    assert fine.candidates > seen.candidates


def test_chooser_names():
    assert chooser("picker").name == "picker"
    assert chooser("bot").name == f"bot:{STRONGEST.number}"
    assert chooser("bot:2", seed=4).name == "bot:2"
    for bad in ("bot:0", "bot:x", "robot", "bot:99"):
        with pytest.raises(ValueError):
            chooser(bad)


DECIDE = """
from rules.bot.chooser import Bot
from rules.bot.levels import level
from rules.racks import Game
from tests.rules.bot.positions import random_position
for game, seed in ((Game.EIGHTBALL, 3), (Game.SNOOKER, 4), (Game.THREE_CUSHION, 5)):
    state = random_position(game, seed).evolve(pending=())
    print(Bot(level(2), seed=9).choose(state).model_dump_json())
"""


def test_a_decision_does_not_depend_on_the_interpreter_run():
    """Two interpreters with different string-hash seeds (set orders) decide alike."""
    runs = [
        subprocess.run(
            [sys.executable, "-c", DECIDE],
            capture_output=True,
            text=True,
            check=True,
            cwd=ROOT,
            env={**os.environ, "PYTHONHASHSEED": str(h)},
        ).stdout
        for h in (1, 2)
    ]
    assert runs[0] == runs[1] and runs[0].count("\n") == 3


def ringed_one() -> dict:
    """The 1 ringed by six balls 1 mm apart: no stroke can reach it."""
    centre, d = (0.635, 1.27), 2 * POOL_TABLE.R + 0.001
    ring = {
        str(n): (
            centre[0] + d * math.cos(k * math.pi / 3),
            centre[1] + d * math.sin(k * math.pi / 3),
        )
        for k, n in enumerate(range(2, 8))
    }
    return {"1": centre, **ring, "9": (0.2, 2.3)}


def test_a_ball_in_hand_with_no_pot_open_still_gives_a_shot():
    """The 1 ringed by six balls, the cue ball in hand: no pot is open, the bot still plays
    a legal input (from a place on the grid over the table)."""
    state = nineball(ringed_one(), ball_in_hand="anywhere")
    assert not candidates_with_pots(state)
    action = Bot(QUICK, seed=1).choose(state)
    check(state, action)
    assert action.place is not None


def candidates_with_pots(state: State) -> list:
    return [c for c in candidates(state, STRONGEST) if c.pot is not None]


def test_it_pushes_out_after_the_break_when_the_table_offers_nothing():
    """The shot after the break with the 1 out of reach: any stroke fouls (ball in hand for
    the opponent), so the bot pushes out, which the referee rules no foul and which leaves
    the opponent the choice; later in the rack the push-out is not offered, and not tried."""
    balls = {**ringed_one(), "cue": (0.3, 0.4)}
    state = State(game=Game.NINEBALL, balls=balls, shots=1)
    bot = Bot(STRONGEST, seed=3)
    shot = bot.choose(state)
    assert shot.push_out and bot.last.kind == Kind.PUSH_OUT
    outcome = play(state, shot)
    assert not outcome.decision.fouls and set(outcome.state.pending) == {"play_on", "play_again"}
    later = state.evolve(shots=5)
    assert not any(c.shot.push_out for c in candidates(later, STRONGEST))
    assert not Bot(QUICK, seed=3).choose(later).push_out


@pytest.mark.parametrize("lv", LEVELS[1:], ids=lambda lv: f"level{lv.number}")
def test_every_level_but_the_first_screens_a_safety(lv):
    """However many pots the table offers, a contact or a kick is among the candidates a
    level screens (its strokes are set so that the pots' variations leave room for them)."""
    for game in (Game.NINEBALL, Game.EIGHTBALL, Game.SNOOKER):
        for seed in range(30):
            state = random_position(game, seed)
            if state.pending:
                continue
            found = candidates(state, lv)
            safe = [c.kind in (Kind.CONTACT, Kind.KICK) for c in found]
            assert any(safe[: lv.screen]) == any(safe), (game, seed)


def test_a_shot_that_hands_the_table_over_costs_less_against_a_weaker_rival():
    """The 9 alone and a stroke sent away from it: a foul, ball in hand to the opponent. The
    search's task values it through the rival it carries (the strongest level's own)."""
    state = State(game=Game.NINEBALL, balls={"cue": (0.6, 0.6), "9": (0.6, 2.0)}, shots=5)
    miss = Shot(strike=Strike(ball="cue", speed=1.0, heading=-90.0))
    noise = tournament(1.0)
    (equal,) = run_task(Task(state, miss, (EXACT,), noise))
    (weaker,) = run_task(Task(state, miss, (EXACT,), noise, STRONGEST.rival))
    assert STRONGEST.rival < KEEP_SURE
    assert -1.0 < equal < weaker < 0.0

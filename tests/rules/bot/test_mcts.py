"""The search baseline (rules.bot.mcts): accepted inputs, its budget, determinism, the reward,
and the obvious pot found."""

from __future__ import annotations

import pytest

from rules.bot.chooser import chooser
from rules.bot.mcts import ACTIONS, PLAYOUTS, Mcts, reward
from rules.game import check, play
from rules.inputs import Choice, Shot, Strike
from rules.racks import Game
from rules.spots import POOL_TABLE
from rules.state import State
from tests.rules.bot.positions import random_position


@pytest.mark.parametrize("game", list(Game))
def test_it_sends_inputs_the_referee_accepts_within_its_budget(game):
    mcts = Mcts(seed=3)
    for seed in range(8):
        state = random_position(game, 300 + seed)
        action = mcts.choose(state)
        check(state, action)
        assert isinstance(action, Choice) == bool(state.pending)
        if isinstance(action, Shot) and mcts.last is not None:
            assert mcts.last.simulations == PLAYOUTS
            assert mcts.last.screened <= ACTIONS


def test_same_seed_same_shot():
    state = random_position(Game.EIGHTBALL, 41).evolve(pending=())
    assert Mcts(seed=5).choose(state) == Mcts(seed=5).choose(state)
    assert chooser("mcts", seed=5).choose(state) == Mcts(seed=5).choose(state)


def test_it_finds_the_obvious_pot():
    """The 1 in the jaws of a corner pocket, the cue ball straight behind it."""
    pocket = next(p for p in POOL_TABLE.pockets if p.name == "top_right")
    along = (-0.7071, -0.7071)
    one = (pocket.center[0] + 0.12 * along[0], pocket.center[1] + 0.12 * along[1])
    cue = (pocket.center[0] + 0.6 * along[0], pocket.center[1] + 0.6 * along[1])
    state = State(
        game=Game.NINEBALL, balls={"cue": cue, "1": one, "5": (0.3, 0.5), "9": (0.4, 1.0)}, shots=5
    )
    decision = play(state, Mcts(seed=1).choose(state)).decision
    assert "1" in decision.pocketed and not decision.fouls


def stroke(heading: float, speed: float = 2.0) -> Shot:
    return Shot(strike=Strike(ball="cue", speed=speed, heading=heading, b=-0.3))


def test_the_reward_orders_win_pot_miss_foul_loss():
    """Strokes fixed by hand, not the chooser's, so that only the reward is under test: the 1
    (or the 9) in the jaws of a corner pocket, the cue ball straight behind it."""
    pocket = next(p for p in POOL_TABLE.pockets if p.name == "top_right")
    along = (-0.7071, -0.7071)
    near = (pocket.center[0] + 0.12 * along[0], pocket.center[1] + 0.12 * along[1])
    cue = (pocket.center[0] + 0.6 * along[0], pocket.center[1] + 0.6 * along[1])
    scored = State(game=Game.NINEBALL, balls={"cue": cue, "1": near, "9": (0.4, 1.0)}, shots=5)
    won = State(game=Game.NINEBALL, balls={"cue": cue, "9": near}, shots=5)
    # The 9 pocketed off the 1 is a win; the same stroke at the 9 with the 1 on is a foul.
    fouled = State(game=Game.NINEBALL, balls={"cue": cue, "9": near, "1": (0.3, 0.3)}, shots=5)
    third_foul = scored.evolve(foul_streak=(2, 0))
    straight, cut_wide, scratch = stroke(45.0), stroke(49.0, speed=1.0), stroke(45.0, speed=3.5)
    outcomes = {
        "win": (won, straight),
        "pot": (scored, straight),
        "miss": (scored, cut_wide),
        "foul": (fouled, straight),
        "loss": (third_foul, scratch),
    }
    r = {name: reward(state, play(state, shot)) for name, (state, shot) in outcomes.items()}
    assert r["win"] == 1.0 and r["loss"] == 0.0
    assert r["win"] > r["pot"] > r["miss"] > r["foul"] > r["loss"]
    assert play(scored, cut_wide).decision.fouls == ()

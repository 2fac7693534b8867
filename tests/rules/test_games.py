"""Whole games between the simple pickers, through the real engine, with invariants checked
after every input, and the record replayed from its JSON to the same states bit for bit."""

from __future__ import annotations

import itertools
import math

import pytest

from rules.game import Setup
from rules.record import GameRecord, Replay, replay
from rules.referee import referee
from rules.selfplay import selfplay
from rules.snooker import value
from rules.spots import is_free, on_table
from rules.state import State

#: (game, seed, gap, target): one whole game each. Pool games are cheap, so several racks;
#: snooker with a frozen rack too, the break-off the engine once gave up on.
GAMES = [
    ("nineball", 0, 0.0002, 0),
    ("nineball", 3, 0.0, 0),
    ("nineball", 5, 0.0002, 0),
    ("eightball", 0, 0.0, 0),
    ("eightball", 4, 0.0002, 0),
    ("eightball", 8, 0.0, 0),
    ("snooker", 0, 0.0, 0),
    ("snooker", 2, 0.0002, 0),
    ("snooker", 4, 0.001, 0),
    ("three_cushion", 4, 0.0, 5),
]
MAX_INPUTS = 300


def check_table(state: State) -> None:
    """Every ball on the table, none overlapping another."""
    table = referee(state.game).TABLE
    for b, p in state.balls.items():
        assert on_table(p, table) or state.game == "three_cushion", b
    for (a, p), (b, q) in itertools.combinations(state.balls.items(), 2):
        assert math.dist(p, q) >= 2 * table.R - 1e-9, (a, b)


def check_step(prev: State, step, start: State) -> None:
    new, d = step.state, step.decision
    check_table(new)
    assert set(new.balls) <= set(start.balls)
    if d is None:  # a choice scores nothing and moves nothing, unless balls are replaced
        restored = prev.retake if step.action.option == "replace" else prev
        assert new.scores == prev.scores and new.balls == restored.balls
        return
    # Every object ball accounted for: it was on the table and stays, or dropped, or came back.
    objects = lambda s: set(s.balls) - {"cue"}  # noqa: E731
    assert objects(new) == (objects(prev) - set(d.pocketed)) | set(d.respotted)
    assert set(d.pocketed) <= objects(prev) and "cue" not in d.pocketed
    # Respots land on the table and on no other ball.
    table = referee(new.game).TABLE
    for b, p in d.respotted.items():
        others = {k: q for k, q in new.balls.items() if k != b}
        assert new.balls[b] == p and on_table(p, table) and is_free(p, others, table.R)
    # Scores add up.
    assert new.scores == (prev.scores[0] + d.points[0], prev.scores[1] + d.points[1])
    assert min(d.points) >= 0
    if new.game == "snooker":
        me = d.player
        if d.fouls:
            assert d.points[me] == 0 and 4 <= d.points[1 - me] <= 7
        else:
            assert d.points[me] == sum(value(b) for b in d.pocketed) and d.points[1 - me] == 0
        assert new.best[me] >= prev.best[me] and max(new.best) <= max(new.scores)
    if new.game == "three_cushion":
        assert d.points[d.player] in (0, 1) and d.points[1 - d.player] == 0
    if not new.over and new.game != "three_cushion":
        assert "cue" in new.balls or new.ball_in_hand is not None


def check_game(played: Replay, setup: Setup) -> None:
    prev = played.start
    for step in played.steps:
        check_step(prev, step, played.start)
        prev = step.state
    final = played.final
    assert final.over and final.winner in (0, 1)
    if setup.game in ("nineball", "eightball"):
        assert sorted(final.scores) == [0, 1] and final.scores[final.winner] == 1
    elif setup.game == "snooker":
        assert final.scores[final.winner] > final.scores[1 - final.winner]
        assert not any(b.startswith("red") for b in final.balls)
    else:
        assert final.scores[final.winner] == setup.target


@pytest.mark.parametrize(("game", "seed", "gap", "target"), GAMES)
def test_whole_game_by_the_pickers(game, seed, gap, target):
    setup = Setup(game=game, seed=seed, gap=gap, target=target)
    record, played = selfplay(setup, max_inputs=MAX_INPUTS)
    check_game(played, setup)
    again = replay(GameRecord.from_json(record.to_json()))
    assert again.start == played.start
    assert again.steps == played.steps  # every state and decision, floats bit for bit

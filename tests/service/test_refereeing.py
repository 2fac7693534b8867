"""The seam to the rules: a rack's record, built from the states the match reached, replays."""

from __future__ import annotations

import pytest

from rules.pickers import pick
from rules.record import replay
from server import refereeing
from server.refereeing import GameName


@pytest.mark.parametrize("breaker", [0, 1])
@pytest.mark.parametrize("game", [GameName.NINEBALL, GameName.SNOOKER])
def test_a_racks_record_replays_whoever_broke(game, breaker):
    """Seats are the referee's players: a rack broken by seat 1 is a record whose setup says
    so, built without simulating again, and it replays to the same states."""
    state = refereeing.new_rack(game, 11, breaker)
    assert state.turn == breaker
    played = []
    for _ in range(4):
        action = pick(state)
        result = refereeing.referee(state, action)
        assert result.void is None
        state = result.state
        played.append((action, state))
    setup = refereeing.rack_setup(game, 11, breaker)
    record = refereeing.rack_record(setup, played)
    again = replay(record)
    assert [step.state for step in again.steps] == [s for _, s in played]
    assert again.steps[0].decision.player == breaker

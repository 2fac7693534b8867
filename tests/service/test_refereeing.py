"""The seam to the rules: a rack's record, built from the states the match reached, replays."""

from __future__ import annotations

import pytest

from rules.pickers import pick
from rules.pool import POCKETS
from rules.record import replay
from server.game import refereeing, tables, visits
from server.game.refereeing import GameName
from server.game.tables import new_table
from server.game.workers import WorkerPool
from server.protocol.models import Constraints, InputKind, Mode, TableCreate
from tests.service.conftest import ADA


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
    setup = refereeing.rack_setup(game, refereeing.DEFAULT_OPTIONS, 11, breaker)
    record = refereeing.rack_record(setup, played)
    again = replay(record)
    assert [step.state for step in again.steps] == [s for _, s in played]
    assert again.steps[0].decision.player == breaker


async def test_a_racks_archive_made_by_a_worker_is_its_record_best_breaks_and_their_keys():
    """The archive a table's worker makes of a snooker rack (breaks of more than one pot)
    holds the record that replays to the rack's states, the last state's best breaks and the
    keys of the visits that made them; the same as made here (pickled both ways, unchanged)."""
    setup = refereeing.rack_setup(GameName.SNOOKER, refereeing.DEFAULT_OPTIONS, 5, 0)
    state, played = refereeing.start(setup), []
    while len(played) < 12 or max(state.best) < 2:
        action = pick(state)
        state = refereeing.referee(state, action).state
        played.append((action, state))
    pool = WorkerPool(1)
    try:
        archive = await pool.rack_archive(setup, played)
    finally:
        pool.close()
    assert archive == refereeing.rack_archive(setup, played)
    assert [step.state for step in replay(archive.record).steps] == [s for _, s in played]
    assert archive.best == state.best
    keys = visits.break_keys(GameName.SNOOKER, refereeing.start(setup), played)
    assert archive.keys == keys
    assert [key is None for key in keys] == [best == 0 for best in state.best]


def next_of(state: refereeing.State) -> Constraints:
    """The `next` field a table in `state` publishes (a bot table: seat 1 acts too)."""
    create = TableCreate(game=state.game, mode=Mode.BOT)
    record = new_table("0" * 20, create, ADA, seed=7).model_copy(update={"state": state})
    constraints = tables.constraints(record)
    assert constraints is not None
    return Constraints.model_validate_json(constraints.model_dump_json())  # as on the wire


def test_next_tells_the_breaker_where_the_cue_ball_may_go():
    after = next_of(refereeing.new_rack(GameName.NINEBALL, 3, 0))
    assert after.kinds == [InputKind.SHOT] and after.cue_ball == "cue"
    assert after.shot.place == "kitchen" and not after.shot.place_required
    assert after.shot.targets == ["1"] and not after.shot.push_out and after.shot.call == []
    foul = refereeing.new_rack(GameName.SNOOKER, 3, 0)
    in_hand = foul.evolve(balls={b: p for b, p in foul.balls.items() if b != "cue"})
    assert next_of(in_hand).shot.place == "D" and next_of(in_hand).shot.place_required


def test_next_offers_the_push_out_after_the_nine_ball_break_only():
    state = refereeing.new_rack(GameName.NINEBALL, 3, 0)
    assert next_of(state.evolve(shots=1)).shot.push_out
    assert not next_of(state.evolve(shots=2)).shot.push_out


def test_next_asks_for_a_called_pocket_on_the_eight():
    state = refereeing.new_rack(GameName.EIGHTBALL, 3, 0)
    balls = {"cue": (0.6, 0.5), "8": (0.9, 1.9), "9": (0.3, 1.6)}
    on_eight = state.evolve(balls=balls, shots=9, groups=("solids", "stripes"))
    assert next_of(on_eight).shot.targets == ["8"]
    assert sorted(next_of(on_eight).shot.call) == sorted(POCKETS)
    assert next_of(on_eight.evolve(turn=1)).shot.call == []  # stripes: not on the 8


def test_next_lists_the_nominations_and_the_choices_of_snooker():
    state = refereeing.new_rack(GameName.SNOOKER, 3, 0)
    assert next_of(state).shot.nominate == []  # on a red
    colour = next_of(state.evolve(on="colour")).shot.nominate
    assert colour == sorted(["yellow", "green", "brown", "blue", "pink", "black"])
    free = next_of(state.evolve(free_ball=True)).shot.nominate
    assert "red" not in "".join(free) and "black" in free
    chosen = next_of(state.evolve(pending=("play_on", "play_again", "replace"), retake=state))
    assert chosen.kinds == [InputKind.CHOICE] and chosen.shot is None
    assert chosen.options == ["play_on", "play_again", "replace"]


@pytest.mark.parametrize("game", list(GameName))
def test_the_choices_to_check_an_input_by_are_those_constraints_give(game):
    """`choices` (asked of every input checked) gives `constraints(state).choices` in every
    state a rack reaches, choices offered or not."""
    state = refereeing.new_rack(game, 5, 0)
    for _ in range(12):
        assert refereeing.choices(state) == refereeing.constraints(state).choices
        if state.over:
            break
        state = refereeing.referee(state, pick(state)).state
    offered = state.evolve(pending=("play_on",))
    assert refereeing.choices(offered) == refereeing.constraints(offered).choices == ("play_on",)

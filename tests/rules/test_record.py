"""Game records: compact JSON, strict validation, replays that refuse forged or illegal input."""

from __future__ import annotations

import json
import math

import pytest
from pydantic import ValidationError

from rules.game import Setup, play, start
from rules.inputs import Choice, Shot, Strike
from rules.record import GameRecord, replay
from rules.state import RuleError, State

from .script import hit, rail, scripted

BREAK = Shot(strike=Strike(ball="cue", speed=8.0, heading=90.0))


def test_record_round_trips_through_compact_json():
    record = GameRecord(
        setup=Setup(game="nineball", seed=9),
        inputs=[BREAK, Choice(option="play_on"), Shot(strike=BREAK.strike, push_out=True)],
    )
    text = record.to_json()
    assert GameRecord.from_json(text) == record
    data = json.loads(text)
    assert data["setup"] == {"game": "nineball", "seed": 9}  # defaults left out
    assert data["inputs"][0] == {"strike": {"ball": "cue", "speed": 8.0, "heading": 90.0}}
    assert data["inputs"][1] == {"option": "play_on"}


@pytest.mark.parametrize(
    "strike",
    [
        {"ball": "cue", "speed": math.nan, "heading": 90.0},
        {"ball": "cue", "speed": 13.0, "heading": 90.0},
        {"ball": "cue", "speed": 0.0, "heading": 90.0},
        {"ball": "cue", "speed": 3.0, "heading": math.inf},
        {"ball": "cue", "speed": 3.0, "heading": 90.0, "a": 0.4, "b": 0.4},
        {"ball": "cue", "speed": 3.0, "heading": 90.0, "english": 1.0},
    ],
)
def test_bad_strikes_are_refused(strike):
    with pytest.raises(ValidationError):
        Shot.model_validate({"strike": strike})


@pytest.mark.parametrize(
    "setup",
    [
        {"game": "pool", "seed": 1},
        {"game": "nineball", "seed": -1},
        {"game": "nineball", "seed": 1, "gap": 0.1},
        {"game": "three_cushion", "seed": 1, "target": -5},
    ],
)
def test_bad_setups_are_refused(setup):
    with pytest.raises(ValidationError):
        Setup.model_validate(setup)


def test_a_forged_input_stops_the_replay():
    # P2 may not choose anything after a legal break, whatever the record claims.
    record = GameRecord(setup=Setup(game="nineball", seed=1), inputs=[BREAK, BREAK])
    record.inputs[1] = Choice(option="play_again")
    with pytest.raises(RuleError, match="not an option"):
        replay(record, scripted([hit("cue", "1"), *(rail(b) for b in "2356")]))


def test_replay_with_the_same_engine_output_reproduces_every_state():
    record = GameRecord(setup=Setup(game="nineball", seed=4), inputs=[BREAK])
    sim = scripted([hit("cue", "1"), *(rail(b) for b in "2356")])
    one, two = replay(record, sim), replay(record, sim)
    assert one == two and one.final.turn == 1 and one.final.shots == 1


def test_a_refused_input_changes_nothing():
    state = start(Setup(game="snooker", seed=1))
    before = state.model_copy(deep=True)
    bad = Shot(strike=Strike(ball="cue", speed=2.0, heading=90.0), place=(0.889, 2.0))
    with pytest.raises(RuleError, match="in the D"):
        play(state, bad, scripted([]))
    assert state == before


def test_states_round_trip_through_json_exactly():
    # A foul and a miss leaves a nested retake state; the server stores states as JSON.
    state = start(Setup(game="snooker", seed=2, gap=0.0003))
    shot = Shot(strike=Strike(ball="cue", speed=2.0, heading=91.0), place=(0.95, 0.7))
    after, _ = play(state, shot, scripted([hit("cue", "pink"), rail("pink")]))
    assert after.retake is not None and "replace" in after.pending
    assert State.model_validate_json(after.model_dump_json()) == after


def test_a_record_from_another_engine_version_is_refused():
    record = GameRecord(setup=Setup(game="nineball", seed=1, engine="0"))
    with pytest.raises(RuleError, match="engine 0"):
        replay(record)

"""server.protocol.encoding: a model's JSON with fields written from JSON made elsewhere."""

from __future__ import annotations

import json

from server.game import refereeing
from server.game.tables import InputEntry, join, outcome_json, played
from server.protocol.encoding import with_encoded
from server.protocol.models import OutcomeMessage, PlayerInfo
from server.protocol.trajectories import Trajectory
from tests.service.conftest import BOB, a_table

ADA = PlayerInfo(id="p_ada", name="ada")


def test_an_encoded_field_reads_back_as_the_field() -> None:
    both = with_encoded(ADA, {"name": json.dumps("ada").encode()})
    assert PlayerInfo.model_validate_json(both) == ADA
    assert json.loads(both) == json.loads(ADA.model_dump_json())


def test_excluded_fields_are_left_out_and_an_empty_object_stays_json() -> None:
    assert json.loads(with_encoded(ADA, {}, {"name"})) == {"id": "p_ada"}
    assert json.loads(with_encoded(ADA, {}, {"id", "name"})) == {}
    assert json.loads(with_encoded(ADA, {"id": b'"p_x"'}, {"name"})) == {"id": "p_x"}


def test_a_shots_outcome_json_is_the_outcome_with_the_workers_trajectory() -> None:
    """The worker's answer carries the motion as its JSON alone; the outcome published and
    stored reads back as the outcome the table keeps (without motion) with the trajectory
    simulated, written from those bytes, not encoded again; an outcome without motion is
    whole."""
    record = join(a_table(), BOB)
    action = refereeing.bot_input(record.state, "picker")
    simulated = refereeing.referee(record.state, action)
    result = refereeing.referee_for_table(record.state, action)
    assert result.trajectory is None and result.trajectory_json is not None
    assert Trajectory.model_validate_json(result.trajectory_json) == simulated.trajectory
    assert result.state == simulated.state and result.decision == simulated.decision
    entry = InputEntry(
        shot_id="shot-0001", seat=0, input=action, version=record.version, accepted_at=0.0
    )
    _, outcome = played(record.model_copy(update={"pending": entry}), entry, result)
    assert outcome.trajectory is None
    data = outcome_json(outcome, result)
    assert result.trajectory_json in data
    whole = outcome.model_copy(update={"trajectory": simulated.trajectory})
    assert OutcomeMessage.model_validate_json(data) == whole
    still = refereeing.Refereed(result.state, None, None)
    _, quiet = played(record, entry, still)
    assert OutcomeMessage.model_validate_json(outcome_json(quiet, still)) == quiet

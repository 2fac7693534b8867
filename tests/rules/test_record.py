"""Game records: they state the engine, every state's digest and the result, and a replay
refuses any record that is not the game it states, naming the first input where it differs."""

from __future__ import annotations

import json
import random
from collections import Counter

import pytest

import physics
from physics import ENGINE_VERSION
from rules import compact
from rules.codes import Refusal, RuleError
from rules.game import Setup, play, start
from rules.inputs import Choice, Shot, Strike
from rules.record import GameRecord, link, replay
from rules.selfplay import selfplay
from rules.state import State
from rules.tamper import ALTERATIONS

from .script import hit, rail, refused, scripted

BREAK = Shot(strike=Strike(ball="cue", speed=8.0, heading=90.0))
LEGAL_BREAK = scripted([hit("cue", "1"), *(rail(b) for b in "2356")])


def recorded(setup: Setup, inputs, simulate) -> GameRecord:
    """A true record of `inputs` played from `setup` through `simulate`."""
    state = start(setup)
    record = GameRecord.begin(setup, state)
    for action in inputs:
        state = play(state, action, simulate).state
        record = record.extend(action, state)
    return record


def test_a_record_always_states_its_engine_and_result():
    record = recorded(Setup(game="nineball", seed=9), [BREAK], LEGAL_BREAK)
    data = json.loads(record.to_json())
    assert data["engine"] == ENGINE_VERSION  # stored although it is the current version
    assert data["setup"] == {"game": "nineball", "seed": 9}  # defaults left out
    assert data["inputs"] == [{"strike": {"ball": "cue", "speed": 8.0, "heading": 90.0}}]
    assert len(data["digests"]) == 1 and data["final"]["scores"] == [0, 0]
    assert GameRecord.from_json(record.to_json()) == record
    without = {k: v for k, v in data.items() if k != "engine"}
    with pytest.raises(ValueError, match="engine"):
        GameRecord.model_validate(without)


def test_a_record_needs_one_digest_per_input():
    record = recorded(Setup(game="nineball", seed=9), [BREAK], LEGAL_BREAK)
    with pytest.raises(ValueError, match="1 inputs but 0 digests"):
        GameRecord.model_validate({**record.model_dump(), "digests": []})


@pytest.mark.parametrize(
    "setup",
    [
        {"game": "pool", "seed": 1},
        {"game": "nineball", "seed": -1},
        {"game": "nineball", "seed": "1"},
        {"game": "nineball", "seed": True},
        {"game": "nineball", "seed": 1, "gap": 0.1},
        {"game": "three_cushion", "seed": 1, "target": -5},
    ],
)
def test_bad_setups_are_refused(setup):
    with pytest.raises(ValueError):
        Setup.model_validate(setup)


def test_a_forged_input_stops_the_replay_naming_it():
    # P2 may not choose anything after a legal break, whatever the record claims.
    record = recorded(Setup(game="nineball", seed=1), [BREAK], LEGAL_BREAK)
    forged = record.model_copy(
        update={"inputs": (BREAK, Choice(option="play_again")), "digests": (record.digests[0], 0)}
    )
    with refused(Refusal.NOT_AN_OPTION):
        replay(forged, LEGAL_BREAK)
    with pytest.raises(RuleError, match=r"^input #2: "):
        replay(forged, LEGAL_BREAK)


def test_a_wrong_digest_is_refused_at_its_input():
    record = recorded(Setup(game="nineball", seed=4), [BREAK, BREAK], LEGAL_BREAK)
    assert replay(record, LEGAL_BREAK).final.shots == 2
    bad = record.model_copy(update={"digests": (record.digests[0], record.digests[1] ^ 1)})
    with pytest.raises(
        RuleError, match=r"^input #2: the input or the state it led to differs"
    ) as caught:
        replay(bad, LEGAL_BREAK)
    assert caught.value.code == Refusal.REPLAY_DIFFERS


def test_a_replay_through_another_engine_output_is_refused():
    # The same inputs judged on different events are a different game: the digests say so.
    record = recorded(Setup(game="nineball", seed=4), [BREAK], LEGAL_BREAK)
    other = scripted([hit("cue", "1"), *(rail(b) for b in "2356")], moved={"4": (0.5, 1.5)})
    with refused(Refusal.REPLAY_DIFFERS):
        replay(record, other)


def test_a_refused_input_changes_nothing():
    state = start(Setup(game="snooker", seed=1))
    before = state.model_copy(deep=True)
    bad = Shot(strike=Strike(ball="cue", speed=2.0, heading=90.0), place=(0.889, 2.0))
    with refused(Refusal.OUTSIDE_REGION):
        play(state, bad, scripted([]))
    assert state == before


def test_states_round_trip_through_json_exactly():
    # A foul and a miss leaves a nested retake state; the server stores states as JSON.
    state = start(Setup(game="snooker", seed=2, gap=0.0003))
    shot = Shot(strike=Strike(ball="cue", speed=2.0, heading=91.0), place=(0.95, 0.7))
    after = play(state, shot, scripted([hit("cue", "pink"), rail("pink")])).state
    assert after.retake is not None and "replace" in after.pending
    assert State.model_validate_json(after.model_dump_json()) == after


def test_state_digests_see_every_field_and_quantise_positions():
    state = start(Setup(game="snooker", seed=2))
    base = link(b"", state)
    assert link(b"", state.evolve(visit=1)) != base
    assert link(b"", state.evolve(retake=state.evolve(turn=1))) != base
    x, y = state.balls["cue"]
    assert link(b"", state.evolve(balls={**state.balls, "cue": (x + 2e-6, y)})) != base
    assert link(b"", state.evolve(balls={**state.balls, "cue": (x + 1e-12, y)})) == base


def test_a_record_from_another_engine_version_is_refused():
    record = GameRecord.begin(Setup(game="nineball", seed=1)).model_copy(update={"engine": "0"})
    with pytest.raises(RuleError, match="engine 0") as caught:
        replay(record)
    assert caught.value.code == Refusal.ENGINE_VERSION


#: Small real games for the tamper test (the engine plays a nine-ball rack in ~25 ms).
TAMPERED_GAMES = [("nineball", 0), ("nineball", 5), ("eightball", 4), ("three_cushion", 4)]


@pytest.fixture(scope="module")
def real_records() -> list[GameRecord]:
    records = []
    for game, seed in TAMPERED_GAMES:
        record, _ = selfplay(Setup(game=game, seed=seed, gap=0.0002, target=2), max_inputs=60)
        records.append(record)
    return records


def test_every_alteration_of_a_real_record_is_refused(real_records):
    rng = random.Random(9)
    tried, refusals = Counter(), Counter()
    for record in real_records:
        assert replay(record).final.over  # the genuine record replays
        for kind, alter in ALTERATIONS.items():
            seen = [record]
            for _ in range(2):
                altered = alter(record, rng)
                if altered is None or altered in seen:
                    continue
                seen.append(altered)
                tried[kind] += 1
                with pytest.raises(RuleError, match=r"^input #\d+: ") as caught:
                    replay(altered)
                refusals[caught.value.code] += 1
    # Every kind was tried, and most alterations stay legal: only the digests catch them.
    assert set(tried) == set(ALTERATIONS)
    assert refusals[Refusal.REPLAY_DIFFERS] > sum(tried.values()) / 2


def test_an_engine_failure_names_its_input():
    def broken(scene):
        raise physics.SimulationError("event limit")

    record = recorded(Setup(game="nineball", seed=4), [BREAK], LEGAL_BREAK)
    with pytest.raises(physics.SimulationError, match=r"^input #1: event limit$"):
        replay(record, broken)


def test_the_second_player_may_break_and_the_record_says_so():
    """A match alternates the break: a rack broken by player 1 is a record of its own, which
    replays (and packs) with player 1 breaking; the same inputs from player 0's break do not
    replay as that record."""
    setup = Setup(game="nineball", seed=9, breaker=1)
    assert start(setup).turn == 1
    record = recorded(setup, [BREAK], LEGAL_BREAK)
    assert replay(record, LEGAL_BREAK).steps[0].decision.player == 1
    assert compact.decode(compact.encode(record)) == record
    as_player_0 = record.model_copy(update={"setup": setup.model_copy(update={"breaker": 0})})
    with refused(Refusal.REPLAY_DIFFERS):
        replay(as_player_0, LEGAL_BREAK)


def test_three_cushion_is_broken_by_player_0():
    with pytest.raises(ValueError, match="player 0 breaks"):
        Setup(game="three_cushion", seed=1, breaker=1)

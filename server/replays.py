"""Replays: every finished rack (frame, game) of every table, as a record anyone can replay.

A replay is the rack's game record (setup and inputs, `rules.record.GameRecord`) under an id of
96 random bits, so a private table's racks cannot be found by guessing; `/replay/{id}` is its
page in the web client and `GET /api/replays/{id}` its JSON. The record's player 0 is the
rack's breaker (`players` names who that was), so the record replays exactly as it was played.
"""

from __future__ import annotations

import secrets
import time

from rules.inputs import PlayerInput
from rules.state import Decision, State
from server import refereeing
from server.api_models import ReplayView
from server.tables import TableRecord


def new_replay_id() -> str:
    return secrets.token_hex(12)


def replay_url(replay_id: str) -> str:
    return f"/replay/{replay_id}"


def rack_replay(
    record: TableRecord,
    played: list[tuple[PlayerInput, State]],
    decisions: list[Decision | None],
) -> tuple[ReplayView, tuple[int, int]]:
    """The replay of the rack `played` (inputs and the states they led to), and each *seat's*
    best break in it."""
    best = refereeing.best_visits(record.game, decisions, played[-1][1])
    first = record.breaker
    replay_id = new_replay_id()
    view = ReplayView(
        id=replay_id,
        url=replay_url(replay_id),
        table=record.id,
        rack=record.rack,
        game=record.game,
        players=[record.seats[first], record.seats[1 - first]],
        best=(best[first], best[1 - first]),
        record=refereeing.rack_record(
            refereeing.rack_setup(record.game, record.seed + record.rack, record.breaker), played
        ),
        created=time.time(),
    )
    return view, best

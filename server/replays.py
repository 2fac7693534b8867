"""Replays: every finished rack (frame, game) of every table, as a record anyone can replay.

A replay is the rack's game record (setup and inputs, `rules.record.GameRecord`) under an id of
96 random bits, so a private table's racks cannot be found by guessing; `/replay/{id}` is its
page in the web client and `GET /api/replays/{id}` its JSON. The record's player 0 is the
rack's breaker (`players` names who that was), so the record replays exactly as it was played.
"""

from __future__ import annotations

import secrets
import time

from server import refereeing
from server.api_models import ReplayView
from server.refereeing import Decision, GameRecord, State
from server.tables import TableRecord


def new_replay_id() -> str:
    return secrets.token_hex(12)


def replay_url(replay_id: str) -> str:
    return f"/replay/{replay_id}"


def rack_replay(
    record: TableRecord,
    game_record: GameRecord,
    decisions: list[Decision | None],
    final: State,
) -> tuple[ReplayView, tuple[int, int]]:
    """The replay of a finished rack (`game_record`: its inputs as the rules record them, from
    `refereeing.rack_record`), and each *seat's* best break in it."""
    best = refereeing.best_visits(record.game, decisions, final)
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
        record=game_record,
        created=time.time(),
    )
    return view, best

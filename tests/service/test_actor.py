"""The table actor's invariants (server/game/actor.py) under random command sequences.

Two players, a spectator and the clock send random commands to one match over the API:
shots (current, stale, resent, under reserved-looking ids), heartbeats, quick messages,
claims, resignations, rematch offers and accepts in bursts, the clock running out, and
server restarts on the same storage; a finished match is followed by its rematch, if any.
After every sequence, on both storage backends: the
match has ended or the seat to act can act; every input was played at most once; the table's
versions have no holes; at most one rematch table exists; every rack played has its replay,
whose record is that rack's inputs.
"""

from __future__ import annotations

import asyncio
import itertools
import random
import time
from typing import Any

import pytest
from aiohttp.test_utils import TestClient

from server.game.tables import InputEntry
from server.protocol.models import Status
from server.storage import Storage
from tests.service.conftest import Player, StartServer, register, service_of
from tests.service.test_match import picked

SEEDS = range(4)
STEPS = 40
#: Shot ids a client may choose, some of them what the server once used for its own inputs.
SHOT_IDS = ("clock-00000003", "bot-00000001", "resent-shot-id", None, None, None)


class Match:
    """The match under test, as its players see it, across server restarts."""

    def __init__(self, start: StartServer, server: TestClient, players: list[Player]) -> None:
        self.start, self.server, self.players = start, server, players
        self.table = ""

    def at(self, view: dict[str, Any], seat: int) -> Player:
        """The player in `seat` (a rematch swaps the seats)."""
        return next(p for p in self.players if p.info["id"] == view["seats"][seat]["id"])

    def on(self, server: TestClient) -> None:
        self.server = server
        self.players = [Player(server, p.info, p.token) for p in self.players]

    async def view(self) -> dict[str, Any]:
        return await (await self.server.get(f"/api/tables/{self.table}")).json()

    async def restart(self, storage_kind: str) -> None:
        await service_of(self.server).matches.idle()
        await self.server.close()
        self.on(await self.start(**self.settings(storage_kind)))

    def settings(self, storage_kind: str) -> dict[str, Any]:
        return {"grace": 0.2} | ({"redis_url": self.redis_url} if storage_kind == "redis" else {})

    redis_url: str | None = None


async def step(match: Match, rng: random.Random, storage_kind: str) -> None:
    """One random command (or a burst of them)."""
    ada, bob, cy = match.players
    table = f"/api/tables/{match.table}"
    view = await match.view()
    if view["status"] == "over" and view["rematch_table"] is not None:
        match.table = view["rematch_table"]  # play on at the rematch
        table, view = f"/api/tables/{match.table}", await match.view()
    kind = rng.choices(
        ["shot", "heartbeat", "message", "claim", "resign", "rematch", "clock", "restart"],
        weights=[12, 3, 2, 2, 0.5, 3, 2, 1],
    )[0]
    if kind == "shot":
        seat = view["next"]["seat"] if view["next"] and rng.random() < 0.8 else rng.randrange(2)
        version = view["version"] - (1 if rng.random() < 0.15 else 0)
        shot_id = rng.choice(SHOT_IDS)
        if view["next"] and view["next"]["kinds"] == ["shot"]:
            await match.at(view, seat).shoot(match.table, version, picked(view), shot_id)
        elif view["next"]:
            choice = {"kind": "choice", "option": view["next"]["options"][0]}
            await match.at(view, seat).shoot(match.table, version, choice, shot_id)
    elif kind == "heartbeat":
        await rng.choice((ada, bob, cy)).call("POST", f"{table}/heartbeat")
    elif kind == "message":
        await rng.choice((ada, bob, cy)).call("POST", f"{table}/messages", {"message": "gg"})
    elif kind == "claim":
        await rng.choice((ada, bob)).call("POST", f"{table}/claim")
    elif kind == "resign":
        await rng.choice((ada, bob)).call("POST", f"{table}/resign")
    elif kind == "rematch":
        burst = [rng.choice((ada, bob)) for _ in range(rng.randrange(1, 6))]
        await asyncio.gather(*(p.call("POST", f"{table}/rematch") for p in burst))
    elif kind == "clock":
        storage = service_of(match.server).storage
        record = await storage.get_table(match.table)
        if record.pending is None and record.status is Status.PLAYING:
            late = {"version": record.version + 1, "deadline": time.time() - 1}
            await storage.update(record.model_copy(update=late))
    else:
        await match.restart(storage_kind)


async def check(match: Match) -> None:
    """The invariants, once the sequence is over and every queued command has run."""
    service = service_of(match.server)
    await asyncio.sleep(0.6)  # a clock tick (TICK = 0.5 s) rules a deadline that passed
    await service.matches.idle()
    view = await match.view()
    inputs = await service.storage.inputs(match.table)
    shot_ids = [entry.shot_id for entry in inputs]
    assert len(shot_ids) == len(set(shot_ids))  # every input played at most once
    for entry in inputs:  # each input moved the table exactly one version on
        assert entry.outcome is not None and entry.outcome.version == entry.version + 1
    for earlier, later in itertools.pairwise(inputs):
        assert later.version >= earlier.version + 1  # in order, none at a version twice
    assert all(entry.outcome.version <= view["version"] for entry in inputs)
    await check_replays(service.storage, view, inputs)
    if view["status"] == "playing":  # the seat to act can act: its input is accepted
        seat = view["next"]["seat"]
        if view["next"]["kinds"] == ["shot"]:
            action = picked(view)
        else:
            action = {"kind": "choice", "option": view["next"]["options"][0]}
        status, answer = await match.at(view, seat).shoot(match.table, view["version"], action)
        assert status == 202, (answer, view)
    else:
        assert view["status"] == "over"
    # A rematch table exists only once its match is over: one table at most is playing.
    playing = [r.id for r in await service.storage.listed_tables(100)]
    assert len(playing) <= 1
    if view["rematch_table"] is not None:
        assert playing == [view["rematch_table"]]


async def check_replays(storage: Storage, view: dict[str, Any], inputs: list[InputEntry]) -> None:
    """Every rack played at the table has its replay, rack by rack: the racks before the
    current one (finished), and the current one once the match is over if an input was
    played in it; each replay's record is its rack's inputs played (void ones left out)."""
    played: dict[int, list[Any]] = {}
    for entry in inputs:
        if entry.outcome is not None and entry.outcome.void is None:
            played.setdefault(entry.rack, []).append(entry.input)
    racks = range(1, view["rack"] + (1 if view["status"] == "over" else 0))
    expected = [(rack, played[rack]) for rack in racks if rack in played]
    assert len(view["replays"]) == len(expected)
    for replay_id, (rack, rack_inputs) in zip(view["replays"], expected, strict=True):
        replay = await storage.get_replay(replay_id)
        assert replay is not None and (replay.table, replay.rack) == (view["id"], rack)
        assert list(replay.record.inputs) == rack_inputs


@pytest.mark.parametrize("seed", SEEDS)
async def test_random_commands_keep_the_tables_invariants(
    start_server: StartServer, storage_kind: str, seed: int, request: pytest.FixtureRequest
) -> None:
    redis_url = request.getfixturevalue("redis_url") if storage_kind == "redis" else None
    match = Match(start_server, None, [])  # type: ignore[arg-type]
    match.redis_url = redis_url
    server = await start_server(**match.settings(storage_kind))
    ada, bob, cy = [await register(server, name) for name in ("Ada", "Bob", "Cy")]
    match.on(server)
    match.players = [ada, bob, cy]
    table = await ada.create("nineball", shot_clock=60)
    await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    match.table = table["id"]
    rng = random.Random(seed)
    for _ in range(STEPS):
        await step(match, rng, storage_kind)
    await check(match)

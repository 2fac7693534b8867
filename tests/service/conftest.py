"""Fixtures of the game service's tests: storage on each backend, tables to store.

Every test that uses `storage` runs twice: on SQLite (a file in a temporary directory) and on
Redis (a real redis-server per test, tests/redis_server.py). Nothing is mocked, nothing skips.
"""

from __future__ import annotations

import asyncio
import json
import uuid
from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import aiohttp
import pytest
from aiohttp.test_utils import TestClient, TestServer

from server.game.service import SERVICE_KEY, Service
from server.game.tables import TableRecord, new_table
from server.http.app import AppSettings, create_app, relay_settings
from server.protocol.models import Mode, PlayerInfo, TableCreate
from server.storage import Storage
from server.storage.redis import RedisStorage
from server.storage.sqlite import SqliteStorage

OpenStorage = Callable[[], Awaitable[Storage]]


@pytest.fixture(params=["sqlite", "redis"])
def storage_kind(request: pytest.FixtureRequest) -> str:
    return request.param


@pytest.fixture
async def open_storage(
    storage_kind: str, tmp_path: Path, request: pytest.FixtureRequest
) -> AsyncIterator[OpenStorage]:
    """Open (and reopen, as after a restart) storage on one database; all closed at the end."""
    opened: list[Storage] = []
    url = request.getfixturevalue("redis_url") if storage_kind == "redis" else None

    async def open_() -> Storage:
        if url is None:
            storage: Storage = await SqliteStorage.open(tmp_path / "game.sqlite")
        else:
            storage = await RedisStorage.open(url)
        opened.append(storage)
        return storage

    yield open_
    for storage in opened:
        await storage.close()


@pytest.fixture
async def storage(open_storage: OpenStorage) -> Storage:
    return await open_storage()


ADA = PlayerInfo(id="p_ada", name="Ada")
BOB = PlayerInfo(id="p_bob", name="Bob")


def a_table(
    table_id: str = "0" * 20, mode: Mode = Mode.MATCH, private: bool = False
) -> TableRecord:
    """A fresh nine-ball table created by Ada."""
    create = TableCreate(game="nineball", mode=mode, private=private)
    return new_table(table_id, create, ADA, seed=7)


class Ticks:
    """A clock that moves one second each time it is read: what is timed with it took 1 s."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        self.now += 1.0
        return self.now


# ----- a running server and clients of its API ------------------------------------------------
SECRET = "service-test-secret-0123456789abcdef"
WAIT_S = 30.0  # bound on waits for outcomes on a loaded machine; no test asserts on time


@dataclass
class Player:
    """One client of the API: its token and shortcuts for the requests it makes."""

    http: TestClient
    info: dict[str, Any]
    token: str

    @property
    def auth(self) -> dict[str, str]:
        return {"Authorization": f"Bearer {self.token}"}

    async def call(
        self, method: str, path: str, body: Any = None, expect: int | None = None
    ) -> tuple[int, Any]:
        response = await self.http.request(method, path, json=body, headers=self.auth)
        payload = await response.json()
        if expect is not None:
            assert response.status == expect, payload
        return response.status, payload

    async def create(self, game: str = "nineball", **options: Any) -> dict[str, Any]:
        return (await self.call("POST", "/api/tables", {"game": game, **options}, 201))[1]

    async def shoot(
        self, table: str, version: int, action: Any, shot_id: str | None = None
    ) -> tuple[int, Any]:
        body = {"version": version, "shot_id": shot_id or uuid.uuid4().hex, "input": action}
        return await self.call("POST", f"/api/tables/{table}/intents", body)


async def register(http: TestClient, name: str) -> Player:
    response = await http.post("/api/players", json={"name": name})
    body = await response.json()
    assert response.status == 201, body
    return Player(http=http, info=body["player"], token=body["token"])


class Watcher:
    """A relay subscriber of one channel (ws+meta.nchan), collecting its JSON messages."""

    def __init__(self, ws: aiohttp.ClientWebSocketResponse) -> None:
        self.ws = ws
        self.last_id: str | None = None

    async def next(self) -> dict[str, Any]:
        frame = await asyncio.wait_for(self.ws.receive(), WAIT_S)
        assert frame.type in (aiohttp.WSMsgType.TEXT, aiohttp.WSMsgType.BINARY), frame
        raw = frame.data if isinstance(frame.data, bytes) else frame.data.encode()
        header, _, data = raw.partition(b"\n\n")
        fields = dict(line.split(": ", 1) for line in header.decode().split("\n"))
        self.last_id = fields["id"]
        return json.loads(data)

    async def next_kind(self, kind: str) -> dict[str, Any]:
        while True:
            message = await self.next()
            if message["kind"] == kind:
                return message


async def watch(http: TestClient, channel: str, last_id: str | None = None) -> Watcher:
    query = f"?last_event_id={last_id}" if last_id else ""
    ws = await http.ws_connect(f"/sub/{channel}{query}", protocols=("ws+meta.nchan",))
    return Watcher(ws)


StartServer = Callable[..., Awaitable[TestClient]]


@pytest.fixture
async def start_server(tmp_path: Path) -> AsyncIterator[StartServer]:
    """Start game servers (SQLite in `tmp_path` by default); all are stopped at the end."""
    clients: list[TestClient] = []

    async def start(**overrides: Any) -> TestClient:
        settings = {
            "relay": relay_settings(auth_secret=SECRET),
            "database": str(tmp_path / "game.sqlite"),
            "workers": 2,
            **overrides,
        }
        client = TestClient(TestServer(create_app(AppSettings(**settings))))
        await client.start_server()
        clients.append(client)
        return client

    yield start
    for client in clients:
        await client.close()


@pytest.fixture
async def server(start_server: StartServer) -> TestClient:
    return await start_server()


def service_of(http: TestClient) -> Service:
    return http.server.app[SERVICE_KEY]


def up_a_while(http: TestClient) -> None:
    """Let the server count heartbeats as a service that has run a while does: a test that
    stores an old heartbeat means a player gone that long, which a service whose run has just
    begun would count from its start (`MatchContext.up_since`, storage invariant 16)."""
    service_of(http).matches.context.up_since = 0.0


# ----- deployments: one SQLite server, or two replicas sharing a Redis -----------------------
Deploy = Callable[..., Awaitable[list[TestClient]]]


@pytest.fixture
def deploy(storage_kind: str, start_server: StartServer, request: pytest.FixtureRequest) -> Deploy:
    """Start the deployment under test: one SQLite server, or two replicas sharing a Redis."""

    async def start(**settings: Any) -> list[TestClient]:
        if storage_kind == "sqlite":
            return [await start_server(**settings)]
        redis_url = request.getfixturevalue("redis_url")
        return [await start_server(redis_url=redis_url, **settings) for _ in range(2)]

    return start


def on(replicas: list[TestClient], player: Player, n: int) -> Player:
    """`player` talking to replica n (round robin)."""
    return Player(http=replicas[n % len(replicas)], info=player.info, token=player.token)

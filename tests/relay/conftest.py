"""Fixtures for the relay's HTTP/WebSocket tests: a running app on each backend.

Every test that uses `relay` or `start_relay` runs twice, on the memory backend and on the
Redis backend (a real redis-server per test, from `tests/redis_server.py`). Nothing is mocked
and nothing skips: a missing redis-server fails the Redis half loudly.
"""

from __future__ import annotations

import asyncio
import json
from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import dataclass
from typing import Any

import aiohttp
import msgpack
import pytest
from aiohttp.test_utils import TestClient, TestServer

from server.http.app import AppSettings, create_app
from server.relay.backend import BackendConfig
from server.relay.http import RELAY_KEY
from server.relay.relay import Relay
from server.relay.settings import RelaySettings

SECRET = "test-secret-" + "0123456789" * 6  # long enough for HS512 forgeries too
WAIT_S = 10.0  # bound on waits for delivery on a loaded machine; no test asserts on time


@dataclass
class RelayHarness:
    """A running relay app and shortcuts to talk to it like a client."""

    client: TestClient
    relay: Relay

    def token(self, *channels: str, server: bool = False, ttl: float = 60.0) -> str:
        return self.relay.authority.issue("tester", list(channels), ttl, server=server)

    def auth(self, *channels: str, server: bool = False) -> dict[str, str]:
        return {"Authorization": f"Bearer {self.token(*channels, server=server)}"}

    async def publish(
        self, channel: str, value: Any, *, as_msgpack: bool = False, token: str | None = None
    ) -> aiohttp.ClientResponse:
        """POST one message (JSON by default) with a token for `channel`."""
        if as_msgpack:
            body, content_type = msgpack.packb(value), "application/msgpack"
        else:
            body, content_type = json.dumps(value).encode(), "application/json"
        token = token if token is not None else self.token(channel)
        headers = {"Content-Type": content_type, "Authorization": f"Bearer {token}"}
        response = await self.client.post(f"/pub/{channel}", data=body, headers=headers)
        await response.read()
        return response

    async def publish_ok(self, channel: str, value: Any, **kwargs: Any) -> str:
        """Publish and return the new message's id (from the channel info)."""
        response = await self.publish(channel, value, **kwargs)
        assert response.status in (201, 202), await response.text()
        info = await self.info(channel)
        assert info is not None
        return info["last_message_id"]

    async def info(self, channel: str) -> dict[str, Any] | None:
        response = await self.client.get(f"/pub/{channel}", headers={"Accept": "application/json"})
        if response.status == 404:
            return None
        assert response.status == 200
        assert response.headers["Content-Type"] == "text/json"  # as nchan answers
        return json.loads(await response.text())

    async def ws(self, path: str, *, meta: bool = True) -> aiohttp.ClientWebSocketResponse:
        protocols = ("ws+meta.nchan",) if meta else ()
        return await self.client.ws_connect(path, protocols=protocols)


StartRelay = Callable[..., Awaitable[RelayHarness]]


@pytest.fixture(params=["memory", "redis"])
def redis_url_or_none(request: pytest.FixtureRequest) -> str | None:
    """None for the memory backend, a fresh real Redis for the Redis backend."""
    if request.param == "memory":
        return None
    return request.getfixturevalue("redis_url")


@pytest.fixture
async def start_relay(redis_url_or_none: str | None) -> AsyncIterator[StartRelay]:
    """Start relay apps with settings overrides (`buffer_length`, `buffer_bytes`,
    `message_ttl`, or any `RelaySettings` field); all are stopped at the end."""
    clients: list[TestClient] = []

    async def start(**overrides: Any) -> RelayHarness:
        buffer = {
            key: overrides.pop(key)
            for key in ("buffer_length", "buffer_bytes", "message_ttl", "last_value")
            if key in overrides
        }
        relay_settings = RelaySettings(
            auth_secret=SECRET, buffer=BackendConfig(**buffer), **overrides
        )
        app = create_app(AppSettings(relay=relay_settings, redis_url=redis_url_or_none))
        client = TestClient(TestServer(app))
        await client.start_server()
        clients.append(client)
        return RelayHarness(client=client, relay=app[RELAY_KEY])

    yield start
    for client in clients:
        await client.close()


@pytest.fixture
async def relay(start_relay: StartRelay) -> RelayHarness:
    """A relay with default settings."""
    return await start_relay()


async def receive(ws: aiohttp.ClientWebSocketResponse) -> aiohttp.WSMessage:
    """The next frame, failing (not hanging) if none comes."""
    return await asyncio.wait_for(ws.receive(), WAIT_S)


def parse_meta(frame: aiohttp.WSMessage) -> tuple[str, str, bytes]:
    """(id, content type, data) of a `ws+meta.nchan` frame."""
    raw = frame.data if isinstance(frame.data, bytes) else frame.data.encode()
    header, _, data = raw.partition(b"\n\n")
    fields = dict(line.split(": ", 1) for line in header.decode().split("\n"))
    return fields["id"], fields["content-type"], data


async def receive_meta(ws: aiohttp.ClientWebSocketResponse) -> tuple[str, str, bytes]:
    frame = await receive(ws)
    assert frame.type in (aiohttp.WSMsgType.TEXT, aiohttp.WSMsgType.BINARY), frame
    return parse_meta(frame)


async def wait_subscribers(harness: RelayHarness, channel: str, count: int) -> None:
    """Wait until the relay counts `count` subscribers on `channel` (they registered)."""

    async def poll() -> None:
        while True:
            info = await harness.info(channel)
            if info is not None and info["subscribers"] == count:
                return
            await asyncio.sleep(0.01)

    await asyncio.wait_for(poll(), WAIT_S)

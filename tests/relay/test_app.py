"""The application wiring: backend choice, OpenAPI document, the `serve` subcommand."""

from __future__ import annotations

import argparse
import asyncio
import importlib.util

import pytest
from aiohttp.test_utils import TestClient, TestServer

from server.http.app import AppSettings, create_app, make_backend
from server.http.serve import new_event_loop, register
from server.relay.http import RELAY_KEY
from server.relay.memory import MemoryBackend
from server.relay.settings import RelaySettings
from tests.relay.conftest import SECRET, WAIT_S

JSON = {"Accept": "application/json"}


def test_memory_backend_without_redis_url_and_redis_with_one() -> None:
    assert isinstance(make_backend(AppSettings()), MemoryBackend)
    backend = make_backend(AppSettings(redis_url="redis://127.0.0.1:1/0"))
    assert type(backend).__name__ == "RedisBackend"  # imported only when asked for


async def test_openapi_document_describes_the_http_endpoints() -> None:
    async with TestClient(TestServer(create_app())) as client:
        response = await client.get("/openapi.json")
        document = await response.json()
    assert document["openapi"].startswith("3.")
    publisher = document["paths"]["/pub/{channel}"]
    assert set(publisher) >= {"post", "get", "delete"}
    assert {"201", "202", "413", "429"} <= set(publisher["post"]["responses"])
    assert "404" in publisher["get"]["responses"]
    info_schema = document["components"]["schemas"]["ChannelInfo"]
    assert set(info_schema["properties"]) == {
        "messages",
        "requested",
        "subscribers",
        "last_message_id",
    }


def test_serve_subcommand_parses_host_port_and_redis() -> None:
    parser = argparse.ArgumentParser()
    register(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["serve", "--port", "9001", "--redis", "redis://h:6379/0"])
    assert (args.host, args.port, args.redis) == ("127.0.0.1", 9001, "redis://h:6379/0")
    assert parser.parse_args(["serve"]).redis is None


def test_serve_subcommand_takes_uvloop() -> None:
    parser = argparse.ArgumentParser()
    register(parser.add_subparsers(dest="command"))
    assert parser.parse_args(["serve", "--uvloop"]).uvloop
    assert not parser.parse_args(["serve"]).uvloop


async def _fan_out_once() -> list[str]:
    """Three WebSocket subscribers of one channel, one publish: what each received."""
    app = create_app(AppSettings(relay=RelaySettings(auth_secret=SECRET)))
    async with TestClient(TestServer(app)) as client:
        sockets = [await client.ws_connect("/sub/game1") for _ in range(3)]
        token = app[RELAY_KEY].authority.issue("tester", ["game1"], 60)
        while (await (await client.get("/pub/game1", headers=JSON)).json())["subscribers"] < 3:
            await asyncio.sleep(0.01)
        headers = {"Authorization": f"Bearer {token}", **JSON, "Content-Type": "application/json"}
        await client.post("/pub/game1", data=b'{"shot": 1}', headers=headers)
        received = [(await ws.receive(timeout=WAIT_S)).data for ws in sockets]
        for ws in sockets:
            await ws.close()
    return received


def test_uvloop_runs_the_relay_or_is_refused_clearly() -> None:
    """With uvloop installed the relay fans out on its loop (its transports take the direct
    writes); without it, asking for it names the fix instead of silently using asyncio."""
    if importlib.util.find_spec("uvloop") is None:
        with pytest.raises(SystemExit, match="pip install uvloop"):
            new_event_loop(True)
        return
    loop = new_event_loop(True)
    try:
        assert type(loop).__module__.startswith("uvloop")
        assert loop.run_until_complete(_fan_out_once()) == ['{"shot": 1}'] * 3
    finally:
        loop.close()

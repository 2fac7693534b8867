"""The application wiring: backend choice, OpenAPI document, the `serve` subcommand."""

from __future__ import annotations

import argparse

from aiohttp.test_utils import TestClient, TestServer

from server.http.app import AppSettings, create_app, make_backend
from server.http.serve import register
from server.relay.memory import MemoryBackend


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

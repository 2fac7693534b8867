"""What a hostile client tries, answered with a clear refusal that changes nothing.

Deeply nested bodies, channel ids with a trailing newline, bare carriage returns in EventSource
data, publishing while Redis is down, and the game service's own publishers, who must not be
throttled like a client.
"""

from __future__ import annotations

import asyncio
import json

import aiohttp
import pytest
from aiohttp.test_utils import TestClient, TestServer

from server.http.app import AppSettings, create_app
from server.relay.http import RELAY_KEY
from server.relay.payloads import MAX_DEPTH
from server.relay.settings import RelaySettings
from tests.redis_server import RedisServer
from tests.relay.conftest import (
    SECRET,
    RelayHarness,
    StartRelay,
    receive,
    wait_subscribers,
)
from tests.relay.test_eventsource import SSE

DEEP_JSON = {
    "array": b"[" * 30_000 + b"]" * 30_000,
    "object": b'{"a":' * 10_000 + b"1" + b"}" * 10_000,
}


async def _post(relay: RelayHarness, channel: str, body: bytes, content_type: str, token: str):
    headers = {"Content-Type": content_type, "Authorization": f"Bearer {token}"}
    response = await relay.client.post(f"/pub/{channel}", data=body, headers=headers)
    text = await response.text()
    return response.status, json.loads(text) if response.status >= 400 else text


@pytest.mark.parametrize("shape", sorted(DEEP_JSON))
async def test_deeply_nested_json_is_400(relay: RelayHarness, shape: str) -> None:
    status, body = await _post(
        relay, "game1", DEEP_JSON[shape], "application/json", relay.token("game1")
    )
    assert (status, body["status"]) == (400, 400)
    assert f"deeper than {MAX_DEPTH}" in body["error"]
    assert await relay.info("game1") is None


async def test_deeply_nested_msgpack_is_400(relay: RelayHarness) -> None:
    for depth in (MAX_DEPTH + 1, 60_000):  # within msgpack's own stack limit, and beyond it
        body = b"\x91" * depth + b"\x01"
        status, answer = await _post(
            relay, "game1", body, "application/msgpack", relay.token("game1")
        )
        assert status == 400 and f"deeper than {MAX_DEPTH}" in answer["error"]
    assert await relay.info("game1") is None


async def test_nesting_up_to_the_limit_is_published(relay: RelayHarness) -> None:
    body = b"[" * MAX_DEPTH + b"]" * MAX_DEPTH
    status, _ = await _post(relay, "game1", body, "application/json", relay.token("game1"))
    assert status == 202


async def test_a_deep_frame_on_a_subscribers_websocket_is_refused_not_a_crash(
    relay: RelayHarness,
) -> None:
    ws = await relay.ws(f"/sub/game1?token={relay.token('game1')}")
    await ws.send_str(DEEP_JSON["array"].decode())
    closing = await receive(ws)
    assert closing.type == aiohttp.WSMsgType.CLOSE
    assert closing.data == 4400  # the publish's 400, not 1006
    assert "deeper than" in closing.extra
    info = await relay.info("game1")
    assert info is None or info["messages"] == 0


@pytest.mark.parametrize("server", [False, True], ids=["client-token", "server-token"])
async def test_channel_id_with_a_trailing_newline_is_400_and_stores_nothing(
    relay: RelayHarness, server: bool
) -> None:
    token = relay.token("game1", server=server)
    for path in ("/pub/game1%0A", "/pub/game1%0D%0A", "/pub/%0Agame1"):
        status, body = await _post(
            relay, path.removeprefix("/pub/"), b"1", "application/json", token
        )
        assert status == 400, (path, body)
        response = await relay.client.get(path)
        assert response.status == 400
    assert await relay.info("game1") is None
    response = await relay.client.get("/sub/game1%0A", headers=SSE)
    assert response.status == 400


async def test_bare_carriage_returns_split_eventsource_data_lines(relay: RelayHarness) -> None:
    """The EventSource specification ends a line at CRLF, CR or LF: a conforming parser must
    get the whole body back, its line ends made LF, never a truncated `{"move":`."""
    headers = {"Content-Type": "application/json", **relay.auth("game1")}
    await relay.client.post("/pub/game1", data=b'{"move":\r\r"x",\r\n"n":\n1}', headers=headers)
    async with relay.client.get("/sub/game1", headers=SSE) as response:
        raw = await asyncio.wait_for(response.content.readuntil(b"1}\n\n"), 10)
    data = _conforming_parse(raw)
    assert json.loads(data) == {"move": "x", "n": 1}
    assert data == '{"move":\n\n"x",\n"n":\n1}'


def _conforming_parse(stream: bytes) -> str:
    """The data of the first message event, parsed as the EventSource specification says."""
    text = stream.decode()
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    data: list[str] = []
    for line in lines:
        if line == "" and data:
            return "\n".join(data)
        if line.startswith("data:"):
            data.append(line[5:].removeprefix(" "))
    raise AssertionError(f"no event in {stream!r}")


async def test_a_redis_outage_answers_503_json_with_retry_after(
    redis_server: RedisServer,
) -> None:
    settings = AppSettings(relay=RelaySettings(auth_secret=SECRET), redis_url=redis_server.url)
    app = create_app(settings)
    async with TestClient(TestServer(app)) as client:
        await _outage(RelayHarness(client=client, relay=app[RELAY_KEY]), redis_server)


async def _outage(relay: RelayHarness, redis_server: RedisServer) -> None:
    await relay.publish_ok("game1", 1)
    await asyncio.to_thread(redis_server.stop)
    try:
        response = await relay.publish("game1", 2)
        assert response.status == 503
        assert response.content_type == "application/json"
        assert int(response.headers["Retry-After"]) >= 1
        assert (await response.json())["status"] == 503
        info = await relay.client.get("/pub/game1", headers={"Accept": "text/json"})
        assert info.status == 503
        gone = await relay.client.delete("/pub/game1", headers=relay.auth("game1"))
        assert gone.status == 503
        poll = await relay.client.get("/sub/game1")
        assert poll.status == 503 and "Retry-After" in poll.headers
    finally:
        await asyncio.to_thread(redis_server.start)
    # Nothing refused was stored, and publishing works again once Redis is back.
    await relay.publish_ok("game1", 3)
    response = await relay.client.get("/sub/game1?last_event_id=0:0")
    assert json.loads(await response.text()) == 1
    info = await relay.info("game1")
    assert info is not None and info["messages"] == 2


async def test_server_tokens_have_their_own_rate_limit(start_relay: StartRelay) -> None:
    relay = await start_relay(
        publish_rate=0.001, publish_burst=2, server_publish_rate=0.001, server_publish_burst=5
    )
    client, server = relay.token("game1"), relay.token(server=True)
    assert [(await relay.publish("game1", n, token=client)).status for n in range(3)] == [
        202,
        202,
        429,
    ]
    # The holder's client budget is spent; a server token of the same holder is not throttled
    # by it, only by the server budget.
    statuses = [(await relay.publish("game1", n, token=server)).status for n in range(6)]
    assert statuses == [202] * 5 + [429]


async def test_server_publishers_are_not_throttled_at_client_rates(relay: RelayHarness) -> None:
    """The defaults let the game service publish a burst far beyond a client's 100."""
    token = relay.token(server=True)
    ws = await relay.ws("/sub/public-lobby")
    await wait_subscribers(relay, "public-lobby", 1)
    statuses = {(await relay.publish("public-lobby", n, token=token)).status for n in range(300)}
    assert statuses == {201}
    await ws.close()


async def test_msgpack_frames_too_deep_close_a_publishing_subscriber(relay: RelayHarness) -> None:
    ws = await relay.ws(f"/sub/game1?token={relay.token('game1')}")
    await ws.send_bytes(b"\x91" * 60_000 + b"\x01")
    closing = await receive(ws)
    assert (closing.type, closing.data) == (aiohttp.WSMsgType.CLOSE, 4400)

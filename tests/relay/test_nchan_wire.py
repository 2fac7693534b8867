"""nchan's wire details that its clients rely on, as real nchan 1.3.6 answers them."""

from __future__ import annotations

import aiohttp

from tests.relay.conftest import RelayHarness, StartRelay, receive, wait_subscribers
from tests.relay.test_eventsource import SSE, sse

ORIGIN = "https://pages.example"


async def test_channel_info_as_nchan_formats_it(relay: RelayHarness) -> None:
    await relay.publish_ok("game1", 1)
    text = await relay.client.get("/pub/game1")
    assert text.headers["Content-Type"] == "text/plain"
    body = await text.text()
    assert body.split("\r\n")[0] == "queued messages: 1" and not body.endswith("\n")
    for accept in ("text/json", "application/json"):
        answer = await relay.client.get("/pub/game1", headers={"Accept": accept})
        assert answer.headers["Content-Type"] == "text/json"


async def test_x_eventsource_event_names_the_event(relay: RelayHarness) -> None:
    headers = {"Content-Type": "application/json", "X-EventSource-Event": "shot", **relay.auth("g")}
    async with sse(relay, "/sub/g") as stream:
        await wait_subscribers(relay, "g", 1)
        assert (await relay.client.post("/pub/g", data=b"[1]", headers=headers)).status == 201
        await relay.publish_ok("g", [2])  # no header: a plain message event
        named, plain = await stream.next(), await stream.next()
    assert (named["event"], named["data"]) == ("shot", "[1]")
    assert "event" not in plain
    # Resumed from the buffer, the name is still there (both backends store it).
    async with sse(relay, "/sub/g") as stream:
        assert (await stream.next())["event"] == "shot"


async def test_a_bad_event_name_is_400_and_stores_nothing(relay: RelayHarness) -> None:
    headers = {"Content-Type": "application/json", "X-EventSource-Event": "a b", **relay.auth("g")}
    response = await relay.client.post("/pub/g", data=b"1", headers=headers)
    assert response.status == 400
    assert "X-EventSource-Event" in (await response.json())["error"]
    assert await relay.info("g") is None


async def test_delete_closes_websockets_with_1001_410_gone(relay: RelayHarness) -> None:
    ws = await relay.ws("/sub/g", meta=False)
    await wait_subscribers(relay, "g", 1)
    await relay.client.delete("/pub/g", headers=relay.auth("g"))
    closing = await receive(ws)
    assert (closing.type, closing.data, closing.extra) == (
        aiohttp.WSMsgType.CLOSE,
        1001,
        "410 Gone",
    )


async def test_subscribers_from_another_origin_get_cors_headers(relay: RelayHarness) -> None:
    await relay.publish_ok("g", 1)
    headers = {"Origin": ORIGIN}
    async with relay.client.get("/sub/g", headers={**SSE, **headers}) as stream:
        assert stream.headers["Access-Control-Allow-Origin"] == ORIGIN
        assert stream.headers["Access-Control-Allow-Credentials"] == "true"
    poll = await relay.client.get("/sub/g", headers=headers)
    assert poll.headers["Access-Control-Allow-Origin"] == ORIGIN
    assert "Etag" in poll.headers["Access-Control-Expose-Headers"]
    refused = await relay.client.get("/sub/g,g", headers=headers)  # errors carry it too
    assert (refused.status, refused.headers["Access-Control-Allow-Origin"]) == (400, ORIGIN)
    preflight = await relay.client.options(
        "/sub/g", headers={**headers, "Access-Control-Request-Method": "GET"}
    )
    assert preflight.status == 200
    assert preflight.headers["Access-Control-Allow-Origin"] == ORIGIN
    assert "Last-Event-ID" in preflight.headers["Access-Control-Allow-Headers"]
    plain = await relay.client.get("/sub/g")
    assert "Access-Control-Allow-Origin" not in plain.headers


async def test_only_allowed_origins_may_subscribe(start_relay: StartRelay) -> None:
    relay = await start_relay(allowed_origins=[ORIGIN])
    await relay.publish_ok("g", 1)
    assert (await relay.client.get("/sub/g", headers={"Origin": ORIGIN})).status == 200
    refused = await relay.client.get("/sub/g", headers={"Origin": "https://evil.example"})
    assert refused.status == 403
    ws = await relay.client.get(
        "/sub/g",
        headers={
            "Origin": "https://evil.example",
            "Upgrade": "websocket",
            "Connection": "Upgrade",
            "Sec-WebSocket-Key": "dGhlIHNhbXBsZSBub25jZQ==",
            "Sec-WebSocket-Version": "13",
        },
    )
    assert ws.status == 403
    assert (await relay.client.get("/sub/g")).status == 200  # no Origin: not a browser page

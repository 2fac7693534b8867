"""A subscriber that cannot keep up is closed with a reason, never buffered without bound."""

from __future__ import annotations

import json

import aiohttp

from server.relay.sendqueue import OVERFLOW_REASON
from tests.relay.conftest import (
    RelayHarness,
    StartRelay,
    parse_meta,
    receive,
    receive_meta,
    wait_subscribers,
)
from tests.relay.test_eventsource import sse


async def _backlog(relay: RelayHarness, count: int) -> list[str]:
    return [await relay.publish_ok("game1", n) for n in range(count)]


async def test_overflowing_websocket_is_closed_with_a_reason_and_can_resume(
    start_relay: StartRelay,
) -> None:
    """A client that stops reading fills its socket's buffers, then its four-event queue.

    Frames go straight to a socket that has room, so only a reader that really falls behind
    fills the queue: the client reads nothing while 16 MB are published, more than the
    kernel's and the transport's buffers hold, then finds a close after what was queued.
    """
    relay = await start_relay(
        send_queue_length=4, buffer_length=1000, publish_rate=1e6, publish_burst=10**6
    )
    ws = await relay.ws("/sub/game1")
    await wait_subscribers(relay, "game1", 1)
    padding = "x" * 40_000
    ids = [await relay.publish_ok("game1", [n, padding]) for n in range(400)]
    received = []
    while (frame := await receive(ws)).type != aiohttp.WSMsgType.CLOSE:
        received.append(parse_meta(frame))
    assert frame.data == aiohttp.WSCloseCode.POLICY_VIOLATION
    assert frame.extra == OVERFLOW_REASON
    assert 0 < len(received) < len(ids)
    # In order, none missing, until the close.
    assert [message_id for message_id, _, _ in received] == ids[: len(received)]
    assert [json.loads(data)[0] for _, _, data in received] == list(range(len(received)))
    resumed = await relay.ws(f"/sub/game1?last_event_id={received[-1][0]}")
    for expected in range(len(received), min(len(received) + 4, len(ids))):
        message_id, _, data = await receive_meta(resumed)
        assert (message_id, json.loads(data)[0]) == (ids[expected], expected)
    await resumed.close()


async def test_overflowing_eventsource_ends_with_a_closed_event(start_relay: StartRelay) -> None:
    relay = await start_relay(send_queue_length=3)
    await _backlog(relay, 8)
    async with sse(relay, "/sub/game1") as stream:
        events = [await stream.next() for _ in range(4)]
    assert [event["data"] for event in events[:3]] == ["0", "1", "2"]
    assert events[3]["event"] == "closed"
    assert json.loads(events[3]["data"]) == {"channel": "game1", "reason": OVERFLOW_REASON}


async def test_a_queue_that_keeps_up_is_not_closed(start_relay: StartRelay) -> None:
    relay = await start_relay(send_queue_length=4)
    await _backlog(relay, 4)
    ws = await relay.ws("/sub/game1")
    for _ in range(4):
        await receive_meta(ws)
    for n in range(4, 12):  # one at a time: the queue never holds more than one
        await relay.publish_ok("game1", n)
        _, _, data = await receive_meta(ws)
        assert json.loads(data) == n
    await ws.close()

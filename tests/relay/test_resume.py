"""Resume without loss (every missed message, in order, exactly once) and explicit gaps."""

from __future__ import annotations

import asyncio
import json

import aiohttp

from server.relay.frames import GAP_TYPE
from tests.relay.conftest import RelayHarness, StartRelay, receive_meta, wait_subscribers


async def _collect(ws: aiohttp.ClientWebSocketResponse, count: int) -> list[tuple[str, int]]:
    """(id, value) of the next `count` messages."""
    got = []
    for _ in range(count):
        message_id, content_type, data = await receive_meta(ws)
        assert content_type == "application/json"
        got.append((message_id, json.loads(data)))
    return got


async def test_reconnect_with_last_id_gets_every_missed_message_once(
    relay: RelayHarness,
) -> None:
    ws = await relay.ws("/sub/game1")
    for n in range(5):
        await relay.publish_ok("game1", n)
    first = await _collect(ws, 5)
    assert [value for _, value in first] == [0, 1, 2, 3, 4]
    await ws.close()
    for n in range(5, 9):
        await relay.publish_ok("game1", n)
    last_id = first[2][0]  # as if the last two had not arrived before the drop
    ws = await relay.ws(f"/sub/game1?last_event_id={last_id}")
    resumed = await _collect(ws, 6)
    assert [value for _, value in resumed] == [3, 4, 5, 6, 7, 8]
    assert [message_id for message_id, _ in resumed] == [i for i, _ in first[3:]] + [
        i for i, _ in resumed[2:]
    ]
    await relay.publish_ok("game1", 9)
    assert [value for _, value in await _collect(ws, 1)] == [9]
    await ws.close()


async def test_resume_while_publishing_loses_and_repeats_nothing(relay: RelayHarness) -> None:
    """Messages published during the reconnect itself arrive exactly once, in order."""
    total = 60
    ws = await relay.ws("/sub/game1")
    await relay.publish_ok("game1", 0)
    (last_id, _), *_ = await _collect(ws, 1)
    await ws.close()

    async def publish_rest() -> None:
        for n in range(1, total):
            assert (await relay.publish("game1", n)).status in (201, 202)

    publisher = asyncio.create_task(publish_rest())
    await asyncio.sleep(0)  # let some publishes land before the resume, some after
    ws = await relay.ws(f"/sub/game1?last_event_id={last_id}")
    got = await _collect(ws, total - 1)
    await publisher
    assert [value for _, value in got] == list(range(1, total))
    await relay.publish_ok("game1", "end")
    assert [value for _, value in await _collect(ws, 1)] == ["end"]
    await ws.close()


async def test_expired_last_id_is_told_as_a_gap(start_relay: StartRelay) -> None:
    """nchan would silently jump to the oldest buffered message; we say there is a gap."""
    relay = await start_relay(buffer_length=3)
    ids = [await relay.publish_ok("game1", n) for n in range(6)]
    ws = await relay.ws(f"/sub/game1?last_event_id={ids[0]}")
    gap_id, content_type, body = await receive_meta(ws)
    assert content_type == GAP_TYPE
    assert json.loads(body) == {"channel": "game1", "last_id": ids[0]}
    assert gap_id == ids[0]
    assert [value for _, value in await _collect(ws, 3)] == [3, 4, 5]
    await ws.close()


async def test_resume_from_newest_evicted_id_has_no_gap(start_relay: StartRelay) -> None:
    """Evicted messages the subscriber already had are no gap."""
    relay = await start_relay(buffer_length=3)
    ids = [await relay.publish_ok("game1", n) for n in range(6)]
    ws = await relay.ws(f"/sub/game1?last_event_id={ids[2]}")
    _, content_type, _ = await receive_meta(ws)
    assert content_type == "application/json"
    await ws.close()


async def test_a_buffer_bounded_in_bytes_evicts_into_a_gap(start_relay: StartRelay) -> None:
    """Invariant 2's byte bound: large messages evict older ones by their size, not their
    count, the newest is kept even when it alone is over the bound, and a resume from before
    what was evicted is told of the gap."""
    relay = await start_relay(buffer_bytes=2500)
    ids = [await relay.publish_ok("game1", f"{n}" * 1000) for n in range(5)]  # ~1 KB each
    info = await relay.info("game1")
    assert info is not None and info["messages"] == 2
    ws = await relay.ws(f"/sub/game1?last_event_id={ids[0]}")
    _, content_type, _ = await receive_meta(ws)
    assert content_type == GAP_TYPE
    assert [value for _, value in await _collect(ws, 2)] == ["3" * 1000, "4" * 1000]
    await ws.close()
    big = await relay.publish_ok("game1", "x" * 4000)  # over the bound alone: kept alone
    info = await relay.info("game1")
    assert info is not None and info["messages"] == 1 and info["last_message_id"] == big
    ws = await relay.ws(f"/sub/game1?last_event_id={ids[4]}")
    assert await _collect(ws, 1) == [(big, "x" * 4000)]
    await ws.close()


async def test_messages_older_than_the_ttl_expire_into_a_gap(start_relay: StartRelay) -> None:
    relay = await start_relay(message_ttl=0.5)
    old = await relay.publish_ok("game1", "old")
    later = await relay.publish_ok("game1", "later")
    await asyncio.sleep(1.2)  # let both expire (the claim is expiry, not a duration)
    fresh = await relay.publish_ok("game1", "fresh")
    info = await relay.info("game1")
    assert info is not None
    assert info["messages"] == 1
    ws = await relay.ws(f"/sub/game1?last_event_id={old}")
    _, content_type, body = await receive_meta(ws)
    assert content_type == GAP_TYPE
    assert json.loads(body)["last_id"] == old
    assert await _collect(ws, 1) == [(fresh, "fresh")]
    await ws.close()
    ws = await relay.ws(f"/sub/game1?last_event_id={later}")
    assert await _collect(ws, 1) == [(fresh, "fresh")]  # nothing it lacked expired
    await ws.close()


async def test_malformed_last_id_is_400(relay: RelayHarness) -> None:
    response = await relay.client.get(
        "/sub/game1?last_event_id=yesterday", headers={"Accept": "text/event-stream"}
    )
    assert response.status == 400
    assert "malformed message id" in (await response.json())["error"]


async def test_first_message_setting_picks_oldest_or_only_new(start_relay: StartRelay) -> None:
    for first, expected in (("oldest", [0, 1, 2]), ("newest", [2])):
        relay = await start_relay(first_message=first)
        await relay.publish_ok(f"game_{first}", 0)
        await relay.publish_ok(f"game_{first}", 1)
        ws = await relay.ws(f"/sub/game_{first}")
        await wait_subscribers(relay, f"game_{first}", 1)
        await relay.publish_ok(f"game_{first}", 2)
        assert [value for _, value in await _collect(ws, len(expected))] == expected
        await ws.close()


async def test_a_long_backlog_goes_out_page_by_page_exactly_once_while_publishing(
    relay: RelayHarness,
) -> None:
    """A backlog many pages long, and live messages published while it is being sent: every
    message arrives once, in order, with nothing skipped between the pages and the live feed."""
    ids = [await relay.publish_ok("game1", n) for n in range(30)]
    ws = await relay.ws("/sub/game1")
    racing = asyncio.create_task(_publish_range(relay, 30, 60))
    received = [await receive_meta(ws) for _ in range(60)]
    ids += await racing
    assert [message_id for message_id, _, _ in received] == ids
    assert [json.loads(data) for _, _, data in received] == list(range(60))
    await ws.close()


async def _publish_range(relay: RelayHarness, start: int, stop: int) -> list[str]:
    return [await relay.publish_ok("game1", n) for n in range(start, stop)]


async def test_a_resume_into_history_the_relay_lost_gets_a_gap_notice(
    relay: RelayHarness,
) -> None:
    """A channel deleted and published again, or one the relay no longer holds at all (the
    memory backend after a restart): a resume from an id of its old life is told of the gap
    instead of hearing nothing, and `0:0` (from the very start) is not."""
    old = await relay.publish_ok("game1", "old")
    gone = await relay.client.delete("/pub/game1", headers=relay.auth("game1"))
    assert gone.status == 200
    await asyncio.sleep(1.05)  # a channel published again starts its ids afresh: in a new second
    fresh = await relay.publish_ok("game1", "fresh")
    ws = await relay.ws(f"/sub/game1?last_event_id={old}")
    _, content_type, body = await receive_meta(ws)
    assert content_type == GAP_TYPE and json.loads(body)["last_id"] == old
    assert await _collect(ws, 1) == [(fresh, "fresh")]
    await ws.close()
    ws = await relay.ws(f"/sub/game1?last_event_id={fresh}")
    await relay.publish_ok("game1", "next")
    assert [value for _, value in await _collect(ws, 1)] == ["next"]  # no gap: nothing lost
    await ws.close()
    ws = await relay.ws("/sub/game2?last_event_id=0:0")
    await wait_subscribers(relay, "game2", 1)
    await relay.publish_ok("game2", "first")
    assert [value for _, value in await _collect(ws, 1)] == ["first"]
    await ws.close()
    ws = await relay.ws(f"/sub/never_published?last_event_id={old}")
    _, content_type, _ = await receive_meta(ws)
    assert content_type == GAP_TYPE
    await ws.close()


async def test_a_memory_relay_restarted_tells_resuming_subscribers_of_the_gap(
    start_relay: StartRelay, redis_url_or_none: str | None
) -> None:
    """The embedded relay keeps its buffers in memory: after a restart a subscriber resuming
    with its last id gets a gap notice (then everything new), never silence. (On Redis the
    buffers outlive the process, and the resume gets the messages themselves.)"""
    before = await start_relay()
    last = await before.publish_ok("table-1", "v13")
    await before.publish_ok("table-1", "v14")  # published, never received by the subscriber
    after = await start_relay()
    ws = await after.ws(f"/sub/table-1?last_event_id={last}")
    _, content_type, data = await receive_meta(ws)
    if redis_url_or_none is None:
        assert content_type == GAP_TYPE
    else:
        assert json.loads(data) == "v14"
    await ws.close()


async def test_a_last_value_channel_keeps_and_sends_only_its_newest(
    start_relay: StartRelay,
) -> None:
    """Invariant 2: a channel named in `last_value` keeps its newest message only, so a new
    subscriber starts from it (a lobby page is not sent every snapshot before the last); the
    other channels keep their backlog."""
    relay = await start_relay(buffer_length=10, last_value=frozenset({"lobby"}))
    for n in range(5):
        await relay.publish_ok("lobby", n)
        await relay.publish_ok("game1", n)
    assert (await relay.info("lobby"))["messages"] == 1
    assert (await relay.info("game1"))["messages"] == 5
    lobby, game = await relay.ws("/sub/lobby"), await relay.ws("/sub/game1")
    assert [value for _, value in await _collect(game, 5)] == [0, 1, 2, 3, 4]
    assert [value for _, value in await _collect(lobby, 1)] == [4]
    await relay.publish_ok("lobby", "next")
    assert [value for _, value in await _collect(lobby, 1)] == ["next"]
    await lobby.close()
    await game.close()

"""EventSource subscribers: id lines, resume by Last-Event-ID or ?last_event_id=, gap events."""

from __future__ import annotations

import asyncio
import json
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager

import aiohttp

from tests.relay.conftest import WAIT_S, RelayHarness, StartRelay, wait_subscribers

SSE = {"Accept": "text/event-stream"}


class EventStream:
    """Reads one SSE response event by event (keepalive comments skipped)."""

    def __init__(self, response: aiohttp.ClientResponse) -> None:
        self.response = response

    async def next(self) -> dict[str, str]:
        while True:
            block = await asyncio.wait_for(self.response.content.readuntil(b"\n\n"), WAIT_S)
            fields: dict[str, str] = {}
            for line in block.decode().strip("\n").split("\n"):
                if line.startswith(":"):
                    continue
                name, _, value = line.partition(": ")
                fields[name] = fields[name] + "\n" + value if name in fields else value
            if fields:
                return fields


@asynccontextmanager
async def sse(
    relay: RelayHarness, path: str, headers: dict[str, str] | None = None
) -> AsyncIterator[EventStream]:
    async with relay.client.get(path, headers={**SSE, **(headers or {})}) as response:
        assert response.status == 200
        assert response.content_type == "text/event-stream"
        yield EventStream(response)


async def test_events_carry_id_lines_and_msgpack_as_json(relay: RelayHarness) -> None:
    async with sse(relay, "/sub/game1") as stream:
        await wait_subscribers(relay, "game1", 1)
        first = await relay.publish_ok("game1", {"a": 1})
        second = await relay.publish_ok("game1", {"b": [1, 2]}, as_msgpack=True)
        assert await stream.next() == {"id": first, "data": '{"a": 1}'}
        assert await stream.next() == {"id": second, "data": '{"b":[1,2]}'}


async def test_multiline_data_becomes_several_data_lines(relay: RelayHarness) -> None:
    await relay.client.post(
        "/pub/game1",
        data=b'{\n"a": 1\n}',
        headers={"Content-Type": "application/json", **relay.auth("game1")},
    )
    async with relay.client.get("/sub/game1", headers=SSE) as response:
        block = await asyncio.wait_for(response.content.readuntil(b"}\n\n"), WAIT_S)
    assert b'data: {\ndata: "a": 1\ndata: }\n\n' in block


async def test_resume_with_last_event_id_header_or_query(relay: RelayHarness) -> None:
    ids = [await relay.publish_ok("game1", n) for n in range(4)]
    async with sse(relay, "/sub/game1", {"Last-Event-ID": ids[1]}) as stream:
        assert [(await stream.next())["data"] for _ in range(2)] == ["2", "3"]
    async with sse(relay, f"/sub/game1?last_event_id={ids[2]}") as stream:
        assert await stream.next() == {"id": ids[3], "data": "3"}
        later = await relay.publish_ok("game1", 4)
        assert await stream.next() == {"id": later, "data": "4"}


async def test_expired_last_event_id_gets_a_gap_event(start_relay: StartRelay) -> None:
    relay = await start_relay(buffer_length=2)
    ids = [await relay.publish_ok("game1", n) for n in range(5)]
    async with sse(relay, "/sub/game1", {"Last-Event-ID": ids[0]}) as stream:
        gap = await stream.next()
        assert gap["event"] == "gap"
        assert json.loads(gap["data"]) == {"channel": "game1", "last_id": ids[0]}
        assert "id" not in gap  # the client's resume position stays where it was
        assert [(await stream.next())["data"] for _ in range(2)] == ["3", "4"]


async def test_multiplexed_eventsource_ids_are_cursors(relay: RelayHarness) -> None:
    async with sse(relay, "/sub/t1,t2") as stream:
        await wait_subscribers(relay, "t2", 1)
        a = await relay.publish_ok("t1", "a")
        b = await relay.publish_ok("t2", "b")
        assert (await stream.next())["id"] == f"t1/{a}"
        assert (await stream.next())["id"] == f"t2/{b},t1/{a}"


async def test_deleted_channel_ends_the_stream_with_a_closed_event(relay: RelayHarness) -> None:
    await relay.publish_ok("game1", 0)
    async with sse(relay, "/sub/game1") as stream:
        await stream.next()
        await relay.client.delete("/pub/game1", headers=relay.auth("game1"))
        closed = await stream.next()
        assert closed["event"] == "closed"
        assert json.loads(closed["data"]) == {"channel": "game1", "reason": "deleted"}
        assert await asyncio.wait_for(stream.response.content.read(), WAIT_S) == b""

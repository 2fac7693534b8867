"""Long-poll subscribers walk the buffer with nchan's cache headers.

`Last-Modified`/`If-Modified-Since` carry a message id's seconds, `Etag`/`If-None-Match` its tag.
"""

from __future__ import annotations

import asyncio
import json
from email.utils import parsedate_to_datetime

import aiohttp

from server.relay.ids import parse_message_id
from tests.relay.conftest import RelayHarness, StartRelay, wait_subscribers


async def _poll(relay: RelayHarness, previous: aiohttp.ClientResponse | None = None):
    headers = {}
    if previous is not None:
        headers = {
            "If-Modified-Since": previous.headers["Last-Modified"],
            "If-None-Match": previous.headers["Etag"],
        }
    response = await relay.client.get("/sub/game1", headers=headers)
    await response.read()
    return response


def _message_id(response: aiohttp.ClientResponse) -> str:
    seconds = int(parsedate_to_datetime(response.headers["Last-Modified"]).timestamp())
    return f"{seconds}:{response.headers['Etag']}"


async def test_longpoll_walks_the_buffer_then_waits_for_the_next(relay: RelayHarness) -> None:
    ids = [await relay.publish_ok("game1", n) for n in range(3)]
    response = await _poll(relay)  # no headers: the oldest buffered message
    walked = [(_message_id(response), await response.json())]
    for _ in range(2):
        response = await _poll(relay, response)
        walked.append((_message_id(response), await response.json()))
    assert walked == [(ids[0], 0), (ids[1], 1), (ids[2], 2)]
    waiting = asyncio.create_task(_poll(relay, response))
    await asyncio.sleep(0.05)
    assert not waiting.done()  # the buffer is exhausted: the request waits
    later = await relay.publish_ok("game1", {"n": 3})
    response = await waiting
    assert response.status == 200
    assert (_message_id(response), await response.json()) == (later, {"n": 3})
    assert response.content_type == "application/json"


async def test_longpoll_accepts_last_event_id(relay: RelayHarness) -> None:
    ids = [await relay.publish_ok("game1", n) for n in range(3)]
    response = await relay.client.get(f"/sub/game1?last_event_id={ids[0]}")
    assert await response.json() == 1
    assert _message_id(response) == ids[1]


async def test_many_messages_in_one_second_are_told_apart_by_etag(relay: RelayHarness) -> None:
    ids = [await relay.publish_ok("game1", n) for n in range(30)]
    response = await _poll(relay)
    seen = [await response.json()]
    for _ in range(29):
        response = await _poll(relay, response)
        seen.append(await response.json())
    assert seen == list(range(30))
    assert parse_message_id(_message_id(response)) == parse_message_id(ids[-1])


async def test_longpoll_times_out_with_408(start_relay: StartRelay) -> None:
    relay = await start_relay(longpoll_timeout=0.2)
    response = await relay.client.get("/sub/game1")
    assert response.status == 408


async def test_longpoll_reports_a_gap_in_a_header(start_relay: StartRelay) -> None:
    relay = await start_relay(buffer_length=2)
    ids = [await relay.publish_ok("game1", n) for n in range(5)]
    response = await relay.client.get(f"/sub/game1?last_event_id={ids[0]}")
    assert response.headers["X-Relay-Gap"] == ids[0]
    assert await response.json() == 3
    follow = await _poll(relay, response)
    assert "X-Relay-Gap" not in follow.headers
    assert await follow.json() == 4


async def test_longpoll_on_a_deleted_channel_answers_410(relay: RelayHarness) -> None:
    first = await relay.publish_ok("game1", 0)
    waiting = asyncio.create_task(relay.client.get(f"/sub/game1?last_event_id={first}"))
    await wait_subscribers(relay, "game1", 1)
    await relay.client.delete("/pub/game1", headers=relay.auth("game1"))
    response = await waiting
    assert response.status == 410


async def test_longpoll_ignores_cache_headers_it_cannot_read(relay: RelayHarness) -> None:
    """As HTTP says of conditional requests: a date that is not an HTTP date is ignored, and
    a tag that is not a message tag leaves only the date (its whole second)."""
    first = await relay.publish_ok("game1", 0)
    await relay.publish_ok("game1", 1)
    for headers in (
        {"If-Modified-Since": "not a date"},
        {"If-Modified-Since": "", "If-None-Match": ""},
        {"If-Modified-Since": "Mon, 23 Nov 2020 10:00:00 GMT", "If-None-Match": "abc"},
    ):
        response = await relay.client.get("/sub/game1", headers=headers)
        assert response.status == 200, headers
        assert json.loads(await response.text()) == 0
        assert response.headers["Etag"] == first.split(":")[1]
    response = await relay.client.get("/sub/a,b")
    assert response.status == 400

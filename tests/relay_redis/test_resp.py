"""The relay's lean Redis connection (server.relay.resp) against a real redis-server: what its
module docstring guarantees (order, error replies in place, nothing written twice, a deadline)."""

from __future__ import annotations

import asyncio

import pytest
import redis.asyncio as aioredis
from redis.exceptions import ConnectionError as RedisConnectionError
from redis.exceptions import ResponseError
from redis.exceptions import TimeoutError as RedisTimeoutError

from server.relay.resp import Connection, pack
from tests.redis_server import RedisServer


async def test_replies_come_in_order_with_error_replies_in_their_place(redis_url: str):
    connection = await Connection.open(redis_url, 5.0)
    packed = b"".join(
        [pack("SET", "k", "v"), pack("INCR", "k"), pack("GET", "k"), pack("XLEN", "nothing")]
    )
    ok, failed, value, length = await connection.round_trip(packed, 4, 5.0)
    assert (ok, value, length) == (b"OK", b"v", 0)
    assert isinstance(failed, ResponseError) and "not an integer" in str(failed)
    assert not connection.closed  # an error reply is an answer, not a failure
    connection.close()


async def test_the_url_database_and_password_are_used(redis_server: RedisServer):
    base = f"127.0.0.1:{redis_server.port}"
    admin = aioredis.from_url(redis_server.url)
    await admin.config_set("requirepass", "s3cret")
    admin = aioredis.from_url(f"redis://:s3cret@{base}/0")
    try:
        connection = await Connection.open(f"redis://:s3cret@{base}/3", 5.0)
        assert await connection.round_trip(pack("SET", "where", "three"), 1, 5.0) == [b"OK"]
        connection.close()
        assert await admin.get("where") is None  # not in database 0
        three = aioredis.from_url(f"redis://:s3cret@{base}/3")
        assert await three.get("where") == b"three"
        await three.aclose()
        with pytest.raises(RedisConnectionError, match="refused"):
            await Connection.open(f"redis://:wrong@{base}/0", 5.0)
    finally:
        await admin.config_set("requirepass", "")
        await admin.aclose()


async def test_closing_fails_a_waiting_request_and_nothing_is_written_after(redis_url: str):
    connection = await Connection.open(redis_url, 5.0)
    blocked = asyncio.ensure_future(connection.round_trip(pack("BLPOP", "empty", 10), 1, 20.0))
    await asyncio.sleep(0.1)
    connection.close()
    (reply,) = await asyncio.wait_for(blocked, 2.0)
    assert isinstance(reply, RedisConnectionError)
    assert connection.closed
    # A closed connection writes nothing: the request fails at once, and Redis never sees it.
    (later,) = await connection.round_trip(pack("SET", "after", "1"), 1, 5.0)
    assert isinstance(later, RedisConnectionError)
    admin = aioredis.from_url(redis_url)
    assert await admin.exists("after") == 0
    await admin.aclose()


async def test_a_reply_past_the_deadline_fails_the_connection(redis_url: str):
    connection = await Connection.open(redis_url, 5.0)
    packed = pack("SET", "first", "1") + pack("BLPOP", "empty", 5)
    first, blocked = await connection.round_trip(packed, 2, 0.3)
    assert first == b"OK"  # replies read before the deadline are kept
    assert isinstance(blocked, RedisTimeoutError)
    assert connection.closed


async def test_a_lost_server_fails_the_requests_waiting(redis_server: RedisServer):
    connection = await Connection.open(redis_server.url, 5.0)
    blocked = asyncio.ensure_future(connection.round_trip(pack("BLPOP", "empty", 30), 1, 60.0))
    await asyncio.sleep(0.1)
    await asyncio.to_thread(redis_server.stop, kill=True)
    (reply,) = await asyncio.wait_for(blocked, 5.0)
    assert isinstance(reply, RedisConnectionError)
    with pytest.raises(RedisConnectionError):
        await Connection.open(redis_server.url, 5.0)

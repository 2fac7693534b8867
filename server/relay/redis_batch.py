"""Calls of one Lua script made together go to Redis together: one pipeline, one round trip.

Under load many publishes wait on Redis at once. Sent one by one, each costs a connection from
the pool, a write system call, a wake-up for its reply and a task switch of its own, in this
process and in Redis; with `appendfsync always` Redis fsyncs once per turn of its event loop
anyway, whatever it executed in that turn. So a call made while `pipelines` pipelines of this
script are already on their way waits, and goes with the others that waited in the next
pipeline (a group commit); a lone call goes out at the next turn of the event loop, so a quiet
server adds no delay. Calls are sent in the order they were made, and each gets its own reply
or error. A call whose caller has stopped waiting before it was sent is not sent.

The script is called by its SHA1 (`EVALSHA`); if Redis does not know it (it restarted, or its
script cache was flushed), it is loaded and the calls refused for that reason are sent again:
Redis refused them before running anything, so none runs twice.

Nothing else is ever sent twice. A pipeline is written once; if its connection fails before
every reply has been read, the calls whose replies were read get them, and the others get the
connection's error: Redis may have run them (their messages stored, the answer lost), so
resending would store them twice. The caller answers 503 and the publisher decides, as with any
request whose answer never came. A pooled connection that Redis closed while it sat idle (a
restart) is not a failure of this kind: the pool sees it closed when it hands it out, before
anything is written, and connects afresh (`ConnectionPool.ensure_connection`).
"""

from __future__ import annotations

import asyncio
import hashlib
import math
from typing import Any

import hiredis
import redis.asyncio as aioredis
from redis.asyncio.connection import Connection
from redis.exceptions import ConnectionError as RedisConnectionError
from redis.exceptions import NoScriptError, ResponseError
from redis.exceptions import TimeoutError as RedisTimeoutError

Call = tuple[list[Any], list[Any], "asyncio.Future[Any]"]


class ScriptBatcher:
    """`await batcher(keys, args)`: the script's reply, the calls of a moment sent as one."""

    def __init__(self, redis: aioredis.Redis, script: str, pipelines: int, batch: int) -> None:
        self._redis = redis
        self._script = script
        self._sha = hashlib.sha1(script.encode()).hexdigest()
        self._pipelines = pipelines  # at most this many on their way at once
        self._batch = batch  # calls per pipeline, at most
        self._waiting: list[Call] = []
        self._sending = 0
        self._scheduled = False
        self._tasks: set[asyncio.Task[None]] = set()

    async def __call__(self, keys: list[Any], args: list[Any]) -> Any:
        future: asyncio.Future[Any] = asyncio.get_running_loop().create_future()
        self._waiting.append((keys, args, future))
        self._schedule()
        return await future

    def _schedule(self) -> None:
        if not self._scheduled and self._waiting and self._sending < self._pipelines:
            self._scheduled = True
            asyncio.get_running_loop().call_soon(self._flush)

    def _flush(self) -> None:
        self._scheduled = False
        while self._waiting and self._sending < self._pipelines:
            calls = [call for call in self._waiting[: self._batch] if not call[2].done()]
            del self._waiting[: self._batch]
            if calls:
                self._sending += 1
                task = asyncio.create_task(self._send(calls))
                self._tasks.add(task)
                task.add_done_callback(self._tasks.discard)

    async def _send(self, calls: list[Call]) -> None:
        try:
            replies = await self._execute([(keys, args) for keys, args, _ in calls])
        except Exception as error:  # Redis unreachable: every call of the pipeline fails
            replies = [error] * len(calls)
        except BaseException:  # cancelled (the loop is closing): so are its callers
            for _, _, future in calls:
                future.cancel()
            raise
        finally:
            self._sending -= 1
            self._schedule()
        for (_, _, future), reply in zip(calls, replies, strict=True):
            if future.done():
                continue
            if isinstance(reply, Exception):
                future.set_exception(reply)
            else:
                future.set_result(reply)

    async def _execute(self, calls: list[tuple[list[Any], list[Any]]]) -> list[Any]:
        replies = await self._pipeline(calls)
        unknown = [n for n, reply in enumerate(replies) if isinstance(reply, NoScriptError)]
        if unknown:
            await self._redis.script_load(self._script)
            again = await self._pipeline([calls[n] for n in unknown])
            for n, reply in zip(unknown, again, strict=True):
                replies[n] = reply
        return replies

    async def _pipeline(self, calls: list[tuple[list[Any], list[Any]]]) -> list[Any]:
        """One round trip for `calls` on a connection of the pool, written once (see the module
        docstring). Packed by hiredis in one piece, not command by command as redis-py's asyncio
        pipeline does in Python: on the publish path that packing was the larger cost."""
        packed = b"".join(
            hiredis.pack_command(("EVALSHA", self._sha, len(keys), *keys, *args))
            for keys, args in calls
        )
        pool = self._redis.connection_pool
        connection = await pool.get_connection()
        replies: list[Any] = []
        try:
            await _round_trip(connection, packed, len(calls), replies)
        except (RedisConnectionError, RedisTimeoutError, OSError) as error:
            await connection.disconnect()
            replies += [error] * (len(calls) - len(replies))
        finally:
            await pool.release(connection)
        return replies


async def _round_trip(
    connection: Connection, packed: bytes, count: int, replies: list[Any]
) -> None:
    """Send packed commands, then append their `count` replies to `replies` as they come (an
    error reply as its exception, in its place). One deadline for the whole round trip, the
    connection's socket timeout, rather than one timer per reply."""
    async with asyncio.timeout(connection.socket_timeout):
        await connection.send_packed_command(packed, check_health=False)
        for _ in range(count):
            try:
                replies.append(await connection.read_response(timeout=math.inf))
            except ResponseError as error:
                replies.append(error)

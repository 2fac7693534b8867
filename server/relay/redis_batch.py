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
"""

from __future__ import annotations

import asyncio
import hashlib
from typing import Any

import hiredis
import redis.asyncio as aioredis
from redis.asyncio.connection import Connection
from redis.exceptions import NoScriptError, ResponseError

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
        """One round trip for `calls` on a connection of the pool, with the pool's retry
        policy. Packed by hiredis in one piece, not command by command as redis-py's asyncio
        pipeline does in Python: on the publish path that packing was the larger cost."""
        packed = b"".join(
            hiredis.pack_command(("EVALSHA", self._sha, len(keys), *keys, *args))
            for keys, args in calls
        )
        pool = self._redis.connection_pool
        connection = await pool.get_connection()
        try:
            return await connection.retry.call_with_retry(
                lambda: _round_trip(connection, packed, len(calls)),
                lambda _: connection.disconnect(),
            )
        finally:
            await pool.release(connection)


async def _round_trip(connection: Connection, packed: bytes, count: int) -> list[Any]:
    """Send packed commands, then read their `count` replies (an error reply is returned as
    its exception, in its place)."""
    await connection.send_packed_command(packed, check_health=False)
    replies: list[Any] = []
    for _ in range(count):
        try:
            replies.append(await connection.read_response())
        except ResponseError as error:
            replies.append(error)
    return replies

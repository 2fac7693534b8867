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

Nothing else is ever sent twice. A pipeline is written once, on one of the batcher's own
lean connections (`server.relay.resp`, one per pipeline in flight); if its connection fails
before every reply has been read, the calls whose replies were read get them, and the others
get the connection's error: Redis may have run them (their messages stored, the answer lost),
so resending would store them twice. The caller answers 503 and the publisher decides, as with
any request whose answer never came. A connection that failed, or that Redis closed while it
sat idle (a restart), is dropped, and the next pipeline opens a new one before writing
anything.
"""

from __future__ import annotations

import asyncio
import hashlib
from collections.abc import Sequence
from typing import Any

from redis.exceptions import ResponseError

from server.relay.resp import Connection, pack

Call = tuple[Sequence[Any], Sequence[Any], "asyncio.Future[Any]"]


class ScriptBatcher:
    """`await batcher(keys, args)`: the script's reply, the calls of a moment sent as one."""

    def __init__(self, url: str, script: str, pipelines: int, batch: int, timeout: float) -> None:
        self._url = url
        self._timeout = timeout  # to connect, and for a pipeline's replies
        self._script = script
        self._sha = hashlib.sha1(script.encode()).hexdigest()
        self._pipelines = pipelines  # at most this many on their way at once
        self._batch = batch  # calls per pipeline, at most
        self._waiting: list[Call] = []
        self._sending = 0
        self._scheduled = False
        self._tasks: set[asyncio.Task[None]] = set()
        self._idle: list[Connection] = []  # open connections with no pipeline on their way
        self._closed = False

    async def __call__(self, keys: Sequence[Any], args: Sequence[Any]) -> Any:
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

    async def _execute(self, calls: list[tuple[Sequence[Any], Sequence[Any]]]) -> list[Any]:
        replies = await self._pipeline(
            b"".join(self._evalsha(keys, args) for keys, args in calls), len(calls)
        )
        unknown = [n for n, reply in enumerate(replies) if _no_script(reply)]
        if unknown:
            (loaded,) = await self._pipeline(pack("SCRIPT", "LOAD", self._script), 1)
            if isinstance(loaded, Exception):
                raise loaded
            again = await self._pipeline(
                b"".join(self._evalsha(*calls[n]) for n in unknown), len(unknown)
            )
            for n, reply in zip(unknown, again, strict=True):
                replies[n] = reply
        return replies

    def _evalsha(self, keys: Sequence[Any], args: Sequence[Any]) -> bytes:
        return pack("EVALSHA", self._sha, len(keys), *keys, *args)

    async def _pipeline(self, packed: bytes, count: int) -> list[Any]:
        """One round trip for `count` packed commands, written once (see the module
        docstring), on an idle connection of the batcher or a new one."""
        connection = self._idle.pop() if self._idle else None
        if connection is None or connection.closed:
            connection = await Connection.open(self._url, self._timeout)
        try:
            return await connection.round_trip(packed, count, self._timeout)
        finally:
            if self._closed:
                connection.close()
            elif not connection.closed:
                self._idle.append(connection)

    def close(self) -> None:
        """Close the batcher's connections (a pipeline on its way closes its own when done)."""
        self._closed = True
        for connection in self._idle:
            connection.close()
        self._idle.clear()


def _no_script(reply: Any) -> bool:
    """Redis refused the call, before running anything, for not knowing the script's SHA1."""
    return isinstance(reply, ResponseError) and str(reply).startswith("NOSCRIPT")

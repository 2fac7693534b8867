"""One blocking Redis reader per replica, for all of the replica's channels.

Every publish and every delete, from any replica, also appends a small entry to one stream,
`relay:news`: the channel's name (and, for a delete, the deleting replica). Each replica blocks
on that single stream with one `XREAD` on one connection, whatever its number of channels. When
news arrives, it fetches the new entries of those of its channels that have some, in one
pipelined round trip (`XRANGE` after the newest id it holds for each), and hands each message to
its local subscribers. A thousand channels cost one blocked read and one fetch per batch of
news, not a thousand reads; Redis' connection count per replica is fixed (this reader plus the
backend's command pool), and a new channel needs no wake-up: its position is recorded and the
next news about it is read like any other.

The per-channel positions are the truth; the news only says where to look. So nothing is lost
when news is: after a Redis outage, or if the news stream was trimmed past the reader's position
(it keeps about `NEWS_KEPT` entries), the reader sweeps every local channel from its position.
Entries of a channel read for an earlier generation of its subscribers are dropped (`Position`
identity), and a channel's entries are always delivered in stream order, each once. A delete
renames the channel's stream to `relay:{c}:deleted` for a minute: a reader delivers what it
had not yet read from there, then closes the channel's subscribers.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import Callable, Iterable

import redis.asyncio as aioredis
from redis.asyncio.retry import Retry
from redis.backoff import NoBackoff
from redis.exceptions import ConnectionError as RedisConnectionError
from redis.exceptions import TimeoutError as RedisTimeoutError

log = logging.getLogger(__name__)

NEWS_KEY = "relay:news"
DELETED_PART = "deleted"  # a deleted channel's stream, kept briefly under this name
NEWS_KEPT = 100_000  # entries of the news stream kept (approximately)
READ_BLOCK_MS = 30_000  # an idle reader re-blocks this often
READ_BATCH = 1024  # news entries per read, and messages per channel per fetch
RECONNECT_MAX_S = 1.0
STOP_S = 1.0
REDIS_DOWN = (RedisConnectionError, RedisTimeoutError, OSError)

Entries = list[tuple[bytes, dict[bytes, bytes]]]


def channel_key(channel: str, part: str) -> str:
    """A channel's Redis key: `relay:{c}:<part>`, the hash tag keeping them in one slot."""
    return f"relay:{{{channel}}}:{part}"


def stream_key(channel: str) -> str:
    """The Redis stream holding a channel's buffer."""
    return channel_key(channel, "stream")


def stream_order(stream_id: bytes) -> tuple[int, int]:
    """A stream id `<ms or s>-<seq>` as a pair that orders like Redis orders ids."""
    first, _, second = stream_id.partition(b"-")
    return int(first), int(second or 0)


def cancelled() -> bool:
    """True once this task was asked to stop. A cancellation can get lost inside redis-py
    (Python 3.11's `asyncio.wait_for` around a send drops one that arrives as the send
    completes), so the loops check this instead of relying on CancelledError alone."""
    task = asyncio.current_task()
    return task is not None and task.cancelling() > 0


class Position:
    """The newest stream id read for one channel, for one generation of its subscribers."""

    __slots__ = ("stream_id",)

    def __init__(self, stream_id: bytes) -> None:
        self.stream_id = stream_id


class ReplicaReader:
    """Reads every channel of one replica through one blocking connection on `relay:news`."""

    def __init__(
        self,
        url: str,
        replica: str,
        commands: aioredis.Redis,
        on_messages: Callable[[str, Entries], None],
        on_deleted: Callable[[str], None],
    ) -> None:
        self.replica = replica
        self._commands = commands  # the backend's pool: positions and fetches
        self._on_messages = on_messages
        self._on_deleted = on_deleted
        self._client = aioredis.Redis.from_url(
            url,
            single_connection_client=True,
            retry=Retry(NoBackoff(), 0),
            socket_timeout=READ_BLOCK_MS / 1000 + 10,  # longer than a blocked XREAD
            socket_keepalive=True,
            driver_info=None,
        )
        self._positions: dict[str, Position] = {}
        self._news_at = b"0-0"
        self._sweep = False  # news may have been missed: fetch every channel
        self._task: asyncio.Task[None] | None = None
        self._starting = asyncio.Lock()

    async def add(self, channel: str) -> None:
        """Read `channel` from its newest entry on. Returns once every later entry is certain
        to be read (its position is fixed); raises the Redis error if Redis is unreachable."""
        await self._start()
        newest = await self._commands.xrevrange(stream_key(channel), count=1)
        self._positions[channel] = Position(newest[0][0] if newest else b"0-0")

    async def flush_deleted(self, channel: str) -> None:
        """Deliver what this replica had not read of `channel` before it was deleted."""
        await self._fetch([channel], part=DELETED_PART)

    def remove(self, channel: str) -> None:
        """Stop reading `channel`."""
        self._positions.pop(channel, None)

    async def _start(self) -> None:
        async with self._starting:
            if self._task is not None:
                return
            newest = await self._commands.xrevrange(NEWS_KEY, count=1)
            self._news_at = newest[0][0] if newest else b"0-0"
            self._task = asyncio.create_task(self._loop(), name=f"relay-reader-{self.replica}")

    async def close(self) -> None:
        """Stop reading: cancel the task and drop the connection under a blocked XREAD."""
        if self._task is not None:
            self._task.cancel()
            connection = self._client.connection
            if connection is not None:
                await connection.disconnect(nowait=True)
            await asyncio.wait({self._task}, timeout=STOP_S)
        with contextlib.suppress(*REDIS_DOWN):
            await self._client.aclose()

    async def _loop(self) -> None:
        delay = 0.05
        while not cancelled():
            try:
                if self._sweep:
                    self._sweep = False
                    await self._fetch(list(self._positions))
                await self._read_news()
            except REDIS_DOWN as error:
                if cancelled():
                    break
                log.warning("relay reader: Redis unavailable (%s), retrying", error)
            except Exception:
                if cancelled():
                    break
                # A reply it could not digest: the reader must not die with every feed.
                log.exception("relay reader: unexpected failure, sweeping every channel")
            else:
                delay = 0.05
                continue
            self._sweep = True
            await asyncio.sleep(delay)
            delay = min(delay * 2, RECONNECT_MAX_S)

    async def _read_news(self) -> None:
        read_from = self._news_at
        reply = await self._client.xread(
            {NEWS_KEY: read_from}, count=READ_BATCH, block=READ_BLOCK_MS
        )
        if cancelled() or not reply:
            return
        entries = reply[0][1]
        self._news_at = entries[-1][0]
        with_news: dict[str, None] = {}  # ordered, without repeats
        deleted = []
        for _, fields in entries:
            channel = fields[b"c"].decode()
            if channel not in self._positions:
                continue
            if b"r" in fields:
                if fields[b"r"].decode() != self.replica:  # our own deletes closed at once
                    deleted.append(channel)
            else:
                with_news[channel] = None
        if await self._fetch(with_news, trimmed_after=read_from):
            await self._fetch(list(self._positions))  # news was lost: sweep everything
        await self._fetch(deleted, part=DELETED_PART)
        for channel in deleted:  # after the messages published before the delete
            self._on_deleted(channel)

    async def _fetch(
        self, channels: Iterable[str], trimmed_after: bytes | None = None, part: str = "stream"
    ) -> bool:
        """Fetch and deliver the new entries of `channels` (all of them, page after page) from
        their streams (or, with `part`, their deleted streams).

        With `trimmed_after`, also say whether the news stream no longer holds the entry after
        that id (it was trimmed while unread): True means some news was lost.
        """
        pending = [(name, self._positions[name]) for name in channels if name in self._positions]
        trimmed = False
        while pending or trimmed_after is not None:
            async with self._commands.pipeline(transaction=False) as pipe:
                for channel, at in pending:
                    key = channel_key(channel, part)
                    pipe.xrange(key, b"(" + at.stream_id, "+", count=READ_BATCH)
                if trimmed_after is not None:
                    pipe.xrange(NEWS_KEY, "-", "+", count=1)
                replies = await pipe.execute()
            if trimmed_after is not None:
                oldest = replies.pop()
                trimmed = bool(oldest) and stream_order(oldest[0][0]) > stream_order(trimmed_after)
                trimmed_after = None
            full = []
            for (channel, at), entries in zip(pending, replies, strict=True):
                self._deliver(channel, at, entries)
                if len(entries) == READ_BATCH:
                    full.append((channel, at))
            pending = full
        return trimmed

    def _deliver(self, channel: str, at: Position, entries: Entries) -> None:
        if self._positions.get(channel) is not at:
            return  # unsubscribed meanwhile (perhaps subscribed again from a newer position)
        newest = stream_order(at.stream_id)
        fresh = [entry for entry in entries if stream_order(entry[0]) > newest]
        if fresh:
            at.stream_id = fresh[-1][0]
            self._on_messages(channel, fresh)

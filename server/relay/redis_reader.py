"""One blocking Redis reader per replica, for all of the replica's channels.

A replica with subscribers on a thousand channels reads them all on one connection: one
`XREAD BLOCK` names every channel stream with local subscribers (each from the newest entry the
replica has seen), plus two streams of its own:

- `relay:wake:<replica>`: the replica adds an entry when its channel set grows, which ends the
  blocked read at once; the reader then blocks again with the new set. The entry stays, so a
  read sent just before the change still returns at once: no message of a new channel waits.
  Wakes are coalesced: while one is pending (the reader has not yet rebuilt its read), further
  arrivals add nothing.
- `relay:deleted`: one entry per channel deleted anywhere (its channel and the deleting
  replica), so that every replica closes its own subscribers of that channel.

Redis' connection count per replica is therefore fixed (this reader plus the command pool),
whatever the number of channels, and one read round trip serves every channel that has news.
After a Redis restart the reader reconnects and goes on from the positions it holds, so
subscribers see neither a gap nor a duplicate.

A channel that leaves the set is simply not named in the next read (no wake is needed); entries
of a channel read for an earlier generation of its subscribers are dropped (`Position` identity).
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import Callable

import redis.asyncio as aioredis
from redis.asyncio.retry import Retry
from redis.backoff import NoBackoff
from redis.exceptions import ConnectionError as RedisConnectionError
from redis.exceptions import TimeoutError as RedisTimeoutError

log = logging.getLogger(__name__)

DELETED_KEY = "relay:deleted"
DELETED_KEPT = 1000  # entries of the delete stream kept (approximately)
READ_BLOCK_MS = 30_000  # an idle reader re-blocks this often
READ_BATCH = 512  # entries per stream per read
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


def wake_key(replica: str) -> str:
    return f"relay:wake:{replica}"


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
    """Reads every channel of one replica with a single blocking connection."""

    def __init__(
        self,
        url: str,
        replica: str,
        commands: aioredis.Redis,
        on_messages: Callable[[str, Entries], None],
        on_deleted: Callable[[str], None],
    ) -> None:
        self.replica = replica
        self._commands = commands  # the backend's pool, for wakes and starting positions
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
        self._own: dict[str, bytes] = {}  # wake and delete streams -> position
        self._wake_pending = False
        self._task: asyncio.Task[None] | None = None
        self._starting = asyncio.Lock()

    @property
    def channels(self) -> int:
        return len(self._positions)

    async def add(self, channel: str) -> None:
        """Read `channel` from its newest entry on. Returns once every later entry is certain
        to be read (its position is fixed); raises the Redis error if Redis is unreachable."""
        await self._start()
        newest = await self._commands.xrevrange(stream_key(channel), count=1)
        self._positions[channel] = Position(newest[0][0] if newest else b"0-0")
        if not self._wake_pending:
            self._wake_pending = True
            try:
                await self._commands.xadd(wake_key(self.replica), {"w": 1}, maxlen=8)
            except BaseException:
                self._wake_pending = False  # the position holds: the next wake covers it
                raise

    def remove(self, channel: str) -> None:
        """Stop reading `channel` (from the next read on)."""
        self._positions.pop(channel, None)

    async def _start(self) -> None:
        async with self._starting:
            if self._task is not None:
                return
            async with self._commands.pipeline(transaction=False) as pipe:
                pipe.xrevrange(wake_key(self.replica), count=1)
                pipe.xrevrange(DELETED_KEY, count=1)
                wake, deleted = await pipe.execute()
            self._own = {
                wake_key(self.replica): wake[0][0] if wake else b"0-0",
                DELETED_KEY: deleted[0][0] if deleted else b"0-0",
            }
            self._task = asyncio.create_task(self._run(), name=f"relay-reader-{self.replica}")

    async def close(self) -> None:
        """Stop reading: cancel the task and drop the connection under a blocked XREAD."""
        if self._task is not None:
            self._task.cancel()
            connection = self._client.connection
            if connection is not None:
                await connection.disconnect(nowait=True)
            await asyncio.wait({self._task}, timeout=STOP_S)
        with contextlib.suppress(*REDIS_DOWN):
            await self._commands.delete(wake_key(self.replica))
        await self._client.aclose()

    async def _run(self) -> None:
        try:
            await self._loop()
        except Exception:
            if not cancelled():
                raise
            # Stopped while `close` dropped the connection under a command in progress.

    async def _loop(self) -> None:
        delay = 0.05
        while not cancelled():
            self._wake_pending = False
            reading = {stream_key(name): (name, at) for name, at in self._positions.items()}
            streams = {**self._own, **{key: at.stream_id for key, (_, at) in reading.items()}}
            try:
                reply = await self._client.xread(streams, count=READ_BATCH, block=READ_BLOCK_MS)
            except REDIS_DOWN as error:
                if cancelled():
                    break
                log.warning("relay reader: Redis unavailable (%s), retrying", error)
                await asyncio.sleep(delay)
                delay = min(delay * 2, RECONNECT_MAX_S)
                continue
            delay = 0.05
            if cancelled():
                break
            deleted: Entries = []
            for raw_key, entries in reply or ():
                key = raw_key.decode()
                if key in self._own:
                    self._own[key] = entries[-1][0]
                    if key == DELETED_KEY:
                        deleted = entries
                else:
                    self._deliver(*reading[key], entries)
            for _, fields in deleted:  # after the messages that preceded the delete
                if fields[b"r"].decode() != self.replica:  # our own deletes closed at once
                    self._on_deleted(fields[b"c"].decode())

    def _deliver(self, channel: str, at: Position, entries: Entries) -> None:
        if self._positions.get(channel) is not at:
            return  # unsubscribed meanwhile (perhaps subscribed again from a newer position)
        newest = stream_order(at.stream_id)
        fresh = [entry for entry in entries if stream_order(entry[0]) > newest]
        if fresh:
            at.stream_id = fresh[-1][0]
            self._on_messages(channel, fresh)

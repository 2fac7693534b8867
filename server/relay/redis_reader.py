"""One blocking Redis reader per replica, for all of the replica's channels.

Each replica has its own news stream, `relay:news:<replica>`. A channel's `readers` set names
the replicas that read it; every publish and every delete appends an entry to the news stream
of each live reader other than the replica that made it, in the order Redis executed them: the
channel's name, a sequence number (consecutive per stream), and for a publish the message's
stream id, the id of the channel's message before it and, unless it is larger than
`NEWS_DATA_MAX`, the message itself (for a delete, the deleting replica instead). Each replica
blocks on its own stream with one `XREAD` on one connection, whatever its number of channels,
and hands each message of its channels to their local subscribers straight from the news: one
round trip per batch of news, none per message or per channel, on a lean connection of its own
(`server.relay.resp`), and no news at all about channels it does not read, nor about what it
published itself (it delivers that when Redis answers, `take_own`). Only a message too large
to travel in the news is fetched from its channel's stream (`XRANGE` after the newest id held
for the channel, pipelined for every such channel of the batch). Redis' connection count per
replica is fixed (this reader, the publish pipelines' and the backend's command pool).

What the reader guarantees, which `_open_feed`'s promise rests on:

1. **Registered before positioned.** `add` joins the channel's readers and reads the channel's
   newest id in one script: every message stored after that id is announced in this replica's
   news, or was published here.
2. **Next or fetched.** A message is handed on only if it is the next one the channel owes
   (its previous id, from the news or from the publish's answer, is the channel's position).
   A message further ahead means one in between has not arrived (another replica's, or this
   replica's own whose answer is still on its way): the channel is read from its stream after
   its position instead (`XRANGE`), which delivers everything in order; later copies of what
   was read there are dropped as old.
3. **Nothing lost with the news.** The sequence numbers are consecutive, so a reader sees when
   entries it had not read were trimmed (the stream keeps about `NEWS_KEPT` of them), or when
   Redis came back without them, and after that, and after a Redis outage, it reads every
   local channel from its position.
4. **One registration at a time.** A channel's `add` and `remove` run one after the other, in
   the order they were asked, so a replica never leaves the readers of a channel it still
   reads.

The per-channel positions are the truth; the news only carries copies. Every channel's entries
are delivered in stream order, each once; entries of a channel read for an earlier generation
of its subscribers are dropped (`Position` identity). A delete renames the channel's stream to
`relay:{c}:deleted` for a minute: a reader delivers what it had not yet read from there, then
closes the channel's subscribers.
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import logging
from collections.abc import Awaitable, Callable, Iterable

import redis.asyncio as aioredis
from redis.exceptions import ConnectionError as RedisConnectionError
from redis.exceptions import TimeoutError as RedisTimeoutError

from server.relay.resp import Connection, pack

log = logging.getLogger(__name__)

REPLICAS_KEY = "relay:replicas"  # sorted set: replica id -> Redis time of its last heartbeat
DELETED_PART = "deleted"  # a deleted channel's stream, kept briefly under this name
READERS_PART = "readers"  # a channel's set of the replicas that read it
# Entries of a news stream kept (approximately), and the largest message copied into one:
# what a news stream holds beside the channels' own buffers stays below about 80 MB.
NEWS_KEPT = 10_000
NEWS_DATA_MAX = 8 * 1024
READ_BLOCK_MS = 30_000  # an idle reader re-blocks this often
READ_TIMEOUT_S = READ_BLOCK_MS / 1000 + 10  # a blocked read answers within this, or Redis is gone
CONNECT_TIMEOUT_S = 10.0
READ_BATCH = 1024  # news entries per read, and messages per channel per fetch
RECONNECT_MAX_S = 1.0
STOP_S = 1.0
REDIS_DOWN = (RedisConnectionError, RedisTimeoutError, OSError)

Fields = dict[bytes, bytes]
Entries = list[tuple[bytes, Fields]]

# Where a news stream ends now: its newest entry id and sequence number, read together.
# KEYS: news sequence
_NEWS_END = """
local newest = redis.call('XREVRANGE', KEYS[1], '+', '-', 'COUNT', 1)[1]
return {newest and newest[1] or '0-0', redis.call('GET', KEYS[2]) or '0'}
"""

# Join a channel's readers, and read its newest id, at once (guarantee 1). The replica counts
# as alive from now on, so that publishers announce to it before its first heartbeat.
# KEYS: stream readers replicas; ARGV: replica idle_s
_REGISTER = """
local t = redis.call('TIME')
redis.call('ZADD', KEYS[3], tonumber(t[1]) + tonumber(t[2]) / 1e6, ARGV[1])
redis.call('SADD', KEYS[2], ARGV[1])
redis.call('EXPIRE', KEYS[2], ARGV[2])
local newest = redis.call('XREVRANGE', KEYS[1], '+', '-', 'COUNT', 1)[1]
return newest and newest[1] or '0-0'
"""


def news_key(replica: str) -> str:
    """The stream of news for one replica."""
    return f"relay:news:{replica}"


def news_sequence_key(replica: str) -> str:
    """The sequence number of the newest entry of a replica's news."""
    return f"{news_key(replica)}:sequence"


def _pairs(flat: list[bytes]) -> Fields:
    """A stream entry's fields as Redis sends them, [field, value, ...], as a dict."""
    items = iter(flat)
    return dict(zip(items, items, strict=True))


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

    __slots__ = ("order", "stream_id")

    def __init__(self, stream_id: bytes) -> None:
        self.stream_id = stream_id
        self.order = stream_order(stream_id)

    def advance(self, entries: Entries) -> Entries:
        """The entries newer than the position, which moves past them."""
        fresh = [entry for entry in entries if stream_order(entry[0]) > self.order]
        if fresh:
            self.move_to(fresh[-1][0])
        return fresh

    def move_to(self, stream_id: bytes) -> None:
        self.stream_id = stream_id
        self.order = stream_order(stream_id)


class ReplicaReader:
    """Reads every channel of one replica through one blocking connection on its news."""

    def __init__(
        self,
        url: str,
        replica: str,
        commands: aioredis.Redis,
        on_messages: Callable[[str, Entries], None],
        on_deleted: Callable[[str], None],
        idle_s: int,
    ) -> None:
        self.replica = replica
        self.news = news_key(replica)
        self._url = url
        self._idle_s = idle_s  # a channel's readers set lives as long as its other keys
        self._commands = commands  # the backend's pool: registrations, positions and fetches
        self._on_messages = on_messages
        self._on_deleted = on_deleted
        self._connection: Connection | None = None  # the blocking reads' own
        self._news_end = commands.register_script(_NEWS_END)
        self._register = commands.register_script(_REGISTER)
        self._positions: dict[str, Position] = {}
        self._starting: dict[str, bool] = {}  # channel -> news about it came while adding
        self._registrations: dict[str, asyncio.Task[None]] = {}  # the last add or remove
        self._behind: set[str] = set()  # channels to read from their streams (guarantee 2)
        self._catching_up: asyncio.Task[None] | None = None
        self._news_at = b"0-0"
        self._next_sequence = 1  # of the news entry after `_news_at`
        self._sweep = False  # news may have been missed: fetch every channel
        self._task: asyncio.Task[None] | None = None
        self._starting_lock = asyncio.Lock()

    async def add(self, channel: str) -> None:
        """Read `channel` from its newest entry on. Returns once every later entry is certain
        to be read (its position is fixed); raises the Redis error if Redis is unreachable."""
        await self._start()
        await asyncio.shield(self._in_turn(channel, functools.partial(self._position, channel)))

    async def remove(self, channel: str) -> None:
        """Stop reading `channel`, and leave its readers (after any `add` still on its way)."""
        self._positions.pop(channel, None)  # nothing more is handed on from now
        with contextlib.suppress(*REDIS_DOWN):  # left behind, it costs only unread news
            await self._in_turn(channel, functools.partial(self._leave, channel))

    def _in_turn(self, channel: str, step: Callable[[], Awaitable[None]]) -> asyncio.Task[None]:
        """Run `step` once the channel's previous registration step is done (guarantee 4)."""
        previous = self._registrations.get(channel)

        async def run() -> None:
            if previous is not None:
                await asyncio.wait({previous})
            await step()

        task = asyncio.ensure_future(run())
        self._registrations[channel] = task
        task.add_done_callback(lambda done: self._forget_registration(channel, done))
        return task

    def _forget_registration(self, channel: str, task: asyncio.Task[None]) -> None:
        if self._registrations.get(channel) is task:
            del self._registrations[channel]
        if not task.cancelled():
            task.exception()  # retrieved: the caller, if still waiting, has it too

    async def _position(self, channel: str) -> None:
        self._starting[channel] = False
        try:
            newest = await self._register(
                keys=[stream_key(channel), channel_key(channel, READERS_PART), REPLICAS_KEY],
                args=[self.replica, self._idle_s],
            )
        finally:
            missed = self._starting.pop(channel)
        self._positions[channel] = Position(newest)
        if missed:  # news of it came before its position was known: read what followed
            self._fall_behind(channel)

    async def _leave(self, channel: str) -> None:
        self._positions.pop(channel, None)  # an `add` that was on its way has set it
        await self._commands.srem(channel_key(channel, READERS_PART), self.replica)

    async def flush_deleted(self, channel: str) -> None:
        """Deliver what this replica had not read of `channel` before it was deleted."""
        await self._fetch([channel], part=DELETED_PART)

    def take_own(self, channel: str, previous: bytes, stream_id: bytes) -> bool:
        """A message this replica has just published as `stream_id`, right after `previous`
        (the channel's last id when Redis stored it). True if the channel is read here and
        its position is `previous`: the message is the next one owed, the position moves past
        it and the caller delivers it at once. If it is further ahead, the channel is read
        from its stream (guarantee 2); if it is not newer, it was delivered already."""
        at = self._positions.get(channel)
        if at is None:
            self._missed_while_starting(channel)
            return False
        if at.stream_id == previous:
            at.move_to(stream_id)
            return True
        if stream_order(stream_id) > at.order:
            self._fall_behind(channel)
        return False

    def _missed_while_starting(self, channel: str) -> None:
        """A message of `channel` came while its position was being read: it may be newer, so
        the channel is read from its stream once the position is known."""
        if channel in self._starting:
            self._starting[channel] = True

    def _fall_behind(self, channel: str) -> None:
        """Read `channel` from its stream after its position, soon (guarantee 2)."""
        self._behind.add(channel)
        if self._catching_up is None or self._catching_up.done():
            self._catching_up = asyncio.create_task(self._catch_up())

    async def _catch_up(self) -> None:
        while self._behind:
            channels, self._behind = self._behind, set()
            try:
                await self._fetch(channels)
            except REDIS_DOWN as error:  # the reader's loop sweeps every channel when back
                log.warning("relay reader: catching up failed, Redis unavailable (%s)", error)
                self._sweep = True
                return

    async def _start(self) -> None:
        async with self._starting_lock:
            if self._task is not None:
                return
            self._news_at, sequence = await self._news_end(
                keys=[self.news, news_sequence_key(self.replica)]
            )
            self._next_sequence = int(sequence) + 1
            self._task = asyncio.create_task(self._loop(), name=f"relay-reader-{self.replica}")

    async def close(self) -> None:
        """Stop reading: cancel the tasks and drop the connection under a blocked XREAD."""
        tasks = {task for task in (self._task, self._catching_up) if task is not None}
        for task in tasks:
            task.cancel()
        if self._connection is not None:
            self._connection.close()
        if tasks:
            await asyncio.wait(tasks, timeout=STOP_S)

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

    async def _next_news(self) -> Entries:
        """The news after `_news_at` (blocking until there is some, or READ_BLOCK_MS)."""
        if self._connection is None or self._connection.closed:
            self._connection = await Connection.open(self._url, CONNECT_TIMEOUT_S)
        command = ("XREAD", "COUNT", READ_BATCH, "BLOCK", READ_BLOCK_MS, "STREAMS")
        (reply,) = await self._connection.round_trip(
            pack(*command, self.news, self._news_at), 1, READ_TIMEOUT_S
        )
        if isinstance(reply, Exception):
            raise reply
        # [[news, [[id, [field, value, ...]], ...]]], or None when the block ran out
        return [] if reply is None else [(id_, _pairs(flat)) for id_, flat in reply[0][1]]

    async def _read_news(self) -> None:
        entries = await self._next_news()
        if cancelled() or not entries:
            return
        self._news_at = entries[-1][0]
        # Consecutive sequence numbers: nothing unread was trimmed, Redis lost nothing.
        lost = int(entries[0][1][b"n"]) != self._next_sequence
        self._next_sequence = int(entries[-1][1][b"n"]) + 1
        if lost:
            await self._fetch(list(self._positions))
        await self._deliver_news(entries)

    async def _deliver_news(self, entries: Entries) -> None:
        """Hand on the messages of the news that concern this replica's channels, in order."""
        to_fetch: dict[str, None] = {}  # channels with a message not handed on from the news
        for _, fields in entries:
            channel = fields[b"ch"].decode()
            at = self._positions.get(channel)
            if at is None:
                self._missed_while_starting(channel)
                continue
            if b"r" in fields:  # a delete
                to_fetch.pop(channel, None)  # what it had not read is in the deleted stream
                await self._fetch([channel], part=DELETED_PART)
                self._on_deleted(channel)
            elif channel in to_fetch or fields[b"p"] != at.stream_id:
                # Not the next message: an old copy, or one ahead of a message still on its
                # way (guarantee 2). Either way the channel's stream has the truth.
                if stream_order(fields[b"id"]) > at.order:
                    to_fetch[channel] = None
            elif b"d" not in fields:
                to_fetch[channel] = None  # too large for the news: it and what follows, below
            else:
                self._deliver(channel, at, [(fields[b"id"], fields)])
        await self._fetch(to_fetch)

    async def _fetch(self, channels: Iterable[str], part: str = "stream") -> None:
        """Fetch and deliver the new entries of `channels` (all of them, page after page) from
        their streams (or, with `part`, their deleted streams)."""
        pending = [(name, self._positions[name]) for name in channels if name in self._positions]
        while pending:
            async with self._commands.pipeline(transaction=False) as pipe:
                for channel, at in pending:
                    key = channel_key(channel, part)
                    pipe.xrange(key, b"(" + at.stream_id, "+", count=READ_BATCH)
                replies = await pipe.execute()
            full = []
            for (channel, at), entries in zip(pending, replies, strict=True):
                self._deliver(channel, at, entries)
                if len(entries) == READ_BATCH:
                    full.append((channel, at))
            pending = full

    def _deliver(self, channel: str, at: Position, entries: Entries) -> None:
        if self._positions.get(channel) is not at:
            return  # unsubscribed meanwhile (perhaps subscribed again from a newer position)
        fresh = at.advance(entries)
        if fresh:
            self._on_messages(channel, fresh)

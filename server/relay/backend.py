"""The storage-and-fan-out interface of the relay, and the guarantees every backend must keep.

A backend holds each channel's message buffer and delivers new messages to this process's
subscribers. The relay (HTTP and WebSocket transports) is written against `Backend` only; the
memory backend (`server.relay.memory`) and the Redis backend (`server.relay.redis_backend`)
implement it and must pass the same tests.

What a backend must guarantee
-----------------------------
1. **Ids and order.** Every message gets an id `<unix seconds>:<tag>` (see `server.relay.ids`)
   strictly greater, by (seconds, tag), than every earlier id of the channel since it was
   created (a deleted channel starts afresh), even across process or Redis restarts and clock
   steps backwards. Messages of a channel are delivered to
   every subscriber in id order.
2. **Bounded buffer.** A channel keeps at most `config.buffer_length` messages (one, the
   newest, if it is one of `config.last_value`), none older than
   `config.message_ttl` seconds, and at most `config.buffer_bytes` bytes of message data (the
   newest message is always kept, whatever its size). Older ones are dropped ("evicted"), and
   the backend remembers the newest id it ever evicted from each channel.
3. **Exactly-once resume.** `read_since(channel, last_id, limit)` returns the buffered messages
   with ids greater than `last_id`, oldest first, at most `limit` of them. `subscribe(...,
   last_id=...)` delivers those and then every later message, each exactly once and in order,
   with no window between the backlog and the live feed (the base class does this if
   `_open_feed` keeps its promise, see below).
4. **Explicit gaps.** When a message newer than `last_id` has been evicted, the subscriber cannot
   get everything it missed: `read_since` sets `Backlog.gap`, and `subscribe` sends a `Gap`
   event before the remaining messages. Never jump silently over lost messages. The same holds
   when the backend no longer knows what came after `last_id` at all: a channel it does not
   hold, or one whose history starts after `last_id` (the memory backend after a restart, a
   channel deleted and published again, Redis that lost its data) gets a gap notice too, not
   silence (`unknown_history`); `0:0` resumes from the very start and never does.
5. **One feed per channel per process.** Subscribers of one channel in one process share one
   feed: `_open_feed(channel)` runs when the first local subscriber arrives and `_close_feed`
   when the last leaves; the feed calls `_fan_out(channel, event)` once per message, which hands
   the same event object to every local subscriber. Never one backend read per subscriber.
6. **Delete closes subscribers** everywhere (every process): they get `ChannelClosed` with
   reason `DELETED`, the buffer is gone, and `info` answers None afterwards.
7. **Counts are global.** `ChannelInfo.subscribers` and `Published.had_subscribers` count the
   subscribers of all processes sharing the backend.

Delivery never blocks: `Sink.offer` must return at once. A connection whose queue is full closes
itself (see `server.relay.sendqueue`), and the subscriber resumes by id.

Backlogs go out a page at a time (`BackendConfig.backlog_page` messages): the next page is read
only once the sink has sent the previous one (`Sink.drained`), so a subscriber that never reads
holds one page, not the whole buffer, however long the buffer and however many such readers.
Live messages that arrive meanwhile wait in the subscription, at most `buffer_length` of them:
any it had to drop are still in the buffer, and the catch-up reads on until it has them. At most
`backlog_reads` pages are being read at once in a process, so a crowd arriving together does
not materialize a crowd of pages before the send queues' byte budget can refuse them.
"""

from __future__ import annotations

import asyncio
from abc import ABC, abstractmethod
from enum import StrEnum
from typing import Protocol

from pydantic import BaseModel, ConfigDict, Field

from server.relay.ids import MessageKey, format_message_id, parse_message_id
from server.relay.messages import (
    SHUTDOWN,
    Backlog,
    ChannelClosed,
    ChannelInfo,
    Event,
    Gap,
    Published,
    StoredMessage,
)


class BackendConfig(BaseModel):
    """Buffer bounds shared by all backends (immutable, passed in)."""

    model_config = ConfigDict(frozen=True)

    buffer_length: int = Field(default=100, ge=1, description="messages kept per channel")
    buffer_bytes: int = Field(
        default=16 * 1024 * 1024,
        ge=1,
        description="bytes of message data kept per channel (the newest message is always kept)",
    )
    message_ttl: float = Field(default=3600.0, gt=0, description="seconds a message is kept")
    last_value: frozenset[str] = Field(
        default=frozenset(),
        description="channels that keep only their newest message, each replacing the last "
        "(a lobby's snapshots): a new subscriber gets that one, not a backlog of stale ones",
    )
    backlog_page: int = Field(default=4, ge=1, description="messages read at a time to resume")
    backlog_reads: int = Field(
        default=8, ge=1, description="backlog pages being read at once in one process"
    )

    def length_of(self, channel: str) -> int:
        """The most messages `channel` keeps (invariant 2)."""
        return 1 if channel in self.last_value else self.buffer_length


class Start(StrEnum):
    """Where a subscription without a last id begins (nchan's `nchan_subscriber_first_message`)."""

    OLDEST = "oldest"
    NEWEST = "newest"


class Sink(Protocol):
    """Where a subscription's events go, typically a connection's bounded send queue."""

    def offer(self, event: Event, shared: bool = True) -> None:
        """Take one event without waiting (a full sink closes its connection instead).

        `shared`: the same object goes to every local subscriber (live messages); False for
        messages read for this subscriber alone (its backlog), which it alone keeps alive."""

    async def drained(self) -> bool:
        """Wait until everything offered has been sent on; False if the sink has closed."""


class Subscription:
    """One subscriber of one channel in this process; end it with `Backend.unsubscribe`.

    It remembers the newest id it delivered and drops anything not newer, so a feed that starts
    before the backlog was read (and so repeats some of it) never causes duplicates.
    """

    __slots__ = ("_dropped", "_newest", "_pending", "catch_up", "channel", "pending_limit", "sink")

    def __init__(self, channel: str, sink: Sink, pending_limit: int) -> None:
        self.channel = channel
        self.sink = sink
        self.pending_limit = pending_limit
        self._newest: MessageKey = (-1, -1)
        # While the backlog is being read, live events wait here so that they follow it.
        self._pending: list[Event] | None = []
        self._dropped = False  # pending messages were dropped since the last backlog read
        self.catch_up: asyncio.Future[None] | None = None  # reads the backlog's later pages

    @property
    def newest_id(self) -> str | None:
        """The id of the newest message delivered (or resumed from), None before any."""
        return None if self._newest == (-1, -1) else format_message_id(self._newest)

    def push(self, event: Event) -> None:
        """Deliver one live event (held back until the backlog has gone out)."""
        if self._pending is None and type(event) is StoredMessage:  # `_offer`, inlined:
            if event.key > self._newest:  # the common case, once per message and subscriber
                self._newest = event.key
                self.sink.offer(event)
        elif isinstance(event, ChannelClosed) and self.catch_up is not None:
            self.catch_up.cancel()  # the end comes at once, not after the backlog
            self.sink.offer(event)
        elif self._pending is not None:
            if isinstance(event, StoredMessage) and len(self._pending) >= self.pending_limit:
                # Still in the buffer (or reported as a gap): the catch-up reads it again.
                self._pending.pop(0)
                self._dropped = True
            self._pending.append(event)
        else:
            self._offer(event)

    def _offer(self, event: Event, shared: bool = True) -> None:
        if isinstance(event, StoredMessage):
            if event.key > self._newest:
                self._newest = event.key
                self.sink.offer(event, shared)
        else:
            self.sink.offer(event, shared)

    def resume_from(self, last_id: str | None) -> None:
        if last_id is not None:
            self._newest = parse_message_id(last_id)

    def deliver(self, backlog: Backlog, after: str | None) -> bool:
        """Send a gap notice (if messages after `after` were lost) and one page of backlog.

        True when the subscription may go live: the page was the last one and no live message
        was dropped while it was read.
        """
        if backlog.gap and after is not None:
            self.sink.offer(Gap(channel=self.channel, last_id=after))
        for message in backlog.messages:
            self._offer(message, shared=False)
        caught_up = not backlog.more and not self._dropped
        self._dropped = False
        return caught_up

    def go_live(self) -> None:
        """Send the held-back live events not already sent, then everything as it comes."""
        pending, self._pending = self._pending or [], None
        for event in pending:
            self._offer(event)


def unknown_history(after: MessageKey | None, born: MessageKey | None) -> bool:
    """Whether a resume after `after` asks for history this backend does not hold (invariant
    4): the channel's first message here (`born`; None: it has none) came after `after`, so
    whatever the subscriber was owed in between is lost. `0:0` (from the very start) and a
    fresh subscription (None) ask for nothing earlier."""
    if after is None or after == (0, 0):
        return False
    return born is None or born > after


class Backend(ABC):
    """Channel buffers plus local fan-out; subclasses provide storage and the per-channel feed."""

    def __init__(self, config: BackendConfig) -> None:
        self.config = config
        self._local: dict[str, set[Subscription]] = {}
        self._feeds: dict[str, asyncio.Future[None]] = {}
        self._backlog_reads = asyncio.Semaphore(config.backlog_reads)

    # ----- storage: implemented by each backend -------------------------------------------
    @abstractmethod
    async def publish(
        self, channel: str, data: bytes, content_type: str, event: str | None = None
    ) -> Published:
        """Append a message (new id, evicting beyond the bounds) and deliver it everywhere."""

    @abstractmethod
    async def read_since(self, channel: str, last_id: str | None, limit: int) -> Backlog:
        """The oldest `limit` buffered messages newer than `last_id` (None: from the oldest),
        whether more follow them, and the gap flag."""

    @abstractmethod
    async def info(self, channel: str) -> ChannelInfo | None:
        """The channel's state, None if it has neither buffered messages nor subscribers."""

    @abstractmethod
    async def delete(self, channel: str) -> bool:
        """Drop the channel and close its subscribers everywhere; False if it did not exist."""

    async def close(self) -> None:
        """Close every local subscription ("shutdown") and release connections."""
        for channel in list(self._local):
            await self._end_local(channel, SHUTDOWN)

    # ----- the per-channel feed: implemented by backends that share state between processes --
    @abstractmethod
    async def _open_feed(self, channel: str) -> None:
        """Start delivering this channel's new messages via `_fan_out`.

        Return only once every message published from now on is certain to be fanned out (a
        Redis reader must have fixed its starting stream id).
        """

    @abstractmethod
    async def _close_feed(self, channel: str) -> None:
        """Stop the feed started by `_open_feed` (the last local subscriber has left)."""

    @abstractmethod
    async def _subscribers_changed(self, channel: str, delta: int) -> None:
        """Record a local subscriber arriving (+1) or leaving (-1), for global counts."""

    # ----- local fan-out: shared by all backends --------------------------------------------
    @property
    def open_feeds(self) -> int:
        """Channels with a running feed in this process: one each, however many subscribe."""
        return len(self._feeds)

    def local_subscribers(self, channel: str) -> int:
        """Subscribers of `channel` in this process."""
        return len(self._local.get(channel, ()))

    async def subscribe(
        self, channel: str, sink: Sink, last_id: str | None = None, start: Start = Start.OLDEST
    ) -> Subscription:
        """Subscribe `sink` to `channel`, resuming after `last_id` if given.

        Without `last_id` the subscription starts at the oldest buffered message or at the next
        new one, per `start`. ValueError for a malformed `last_id`.
        """
        if last_id is not None:
            parse_message_id(last_id)
        subscription = Subscription(channel, sink, self.config.buffer_length)
        subscribers = self._local.setdefault(channel, set())
        subscribers.add(subscription)
        try:
            if channel not in self._feeds:
                self._feeds[channel] = asyncio.ensure_future(self._open_feed(channel))
            await asyncio.shield(self._feeds[channel])
            await self._subscribers_changed(channel, +1)
            if last_id is None and start is Start.NEWEST:
                backlog = Backlog(messages=[], gap=False)
            else:
                backlog = await self._read_page(channel, last_id)
        except BaseException:
            feed = self._feeds.get(channel)
            if feed is not None and feed.done() and (feed.cancelled() or feed.exception()):
                del self._feeds[channel]  # a failed feed: the next subscriber tries again
            await self._forget(subscription, counted=False)
            raise
        subscription.resume_from(last_id)
        if subscription.deliver(backlog, last_id):
            subscription.go_live()
        else:
            subscription.catch_up = asyncio.ensure_future(self._catch_up(subscription))
        return subscription

    async def _catch_up(self, subscription: Subscription) -> None:
        """Read and send the backlog's later pages, each once the sink has sent the last."""
        try:
            while await subscription.sink.drained():
                if await self._deliver_next_page(subscription):
                    subscription.go_live()
                    return
        except Exception as error:  # the store failed: end it, the client resumes by id
            reason = f"backlog could not be read ({error}); resume with your last message id"
            subscription.sink.offer(ChannelClosed(channel=subscription.channel, reason=reason))

    async def _deliver_next_page(self, subscription: Subscription) -> bool:
        """Read and deliver one page; True once caught up. (A function of its own so that the
        page is not held while the loop above waits for the sink to send it.)"""
        after = subscription.newest_id
        return subscription.deliver(await self._read_page(subscription.channel, after), after)

    async def _read_page(self, channel: str, after: str | None) -> Backlog:
        async with self._backlog_reads:
            return await self.read_since(channel, after, self.config.backlog_page)

    async def unsubscribe(self, subscription: Subscription) -> None:
        """End a subscription (idempotent)."""
        if subscription.catch_up is not None:
            subscription.catch_up.cancel()
        await self._forget(subscription, counted=True)

    async def _forget(self, subscription: Subscription, *, counted: bool) -> None:
        subscribers = self._local.get(subscription.channel)
        if subscribers is None or subscription not in subscribers:
            return
        subscribers.discard(subscription)
        if counted:
            await self._subscribers_changed(subscription.channel, -1)
        if not subscribers:
            await self._release_feed(subscription.channel)

    async def _release_feed(self, channel: str) -> None:
        if self._local.get(channel):
            return
        self._local.pop(channel, None)
        feed = self._feeds.pop(channel, None)
        if feed is not None:
            if not feed.done():
                feed.cancel()
            await self._close_feed(channel)

    def _fan_out(self, channel: str, event: Event) -> None:
        """Hand one event to every local subscriber of `channel` (called by the feed)."""
        for subscription in tuple(self._local.get(channel, ())):
            subscription.push(event)

    async def _end_local(self, channel: str, reason: str) -> int:
        """Close every local subscription of `channel` with `reason`; how many there were.

        The subscriptions are forgotten and the feed stopped without `_subscribers_changed`:
        the caller (delete, close) owns the global count of the whole channel.
        """
        subscribers = self._local.get(channel, set())
        closed = ChannelClosed(channel=channel, reason=reason)
        for subscription in tuple(subscribers):
            subscription.push(closed)
        count = len(subscribers)
        subscribers.clear()
        await self._release_feed(channel)
        return count

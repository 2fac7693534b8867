"""The Redis backend: channels in Redis Streams, shared by every server replica.

Layout, per channel `c` (the `{c}` hash tag keeps a channel's keys in one cluster slot):

- `relay:{c}:stream`  the message buffer, a stream whose entry ids are `<unix seconds>-<tag>`,
  i.e. nchan's `<unix seconds>:<tag>` with a dash. Redis generates the tag (`XADD key <s>-*`),
  so ids increase within a channel and need no mapping table.
- `relay:{c}:meta`    hash: `last` id ever published, newest `evicted` id (for gap notices),
  `requested` time of the last read, `bytes` of message data in the stream (the byte bound),
  `first`, the time of the stream's oldest entry when known (so that a publish that exceeds
  no bound reads no entry to check its age), `kept`, when the keys' idle expiry was last
  renewed (at most once per `RENEW_S`).
- `relay:{c}:subs`    hash: replica id -> its local subscriber count.
- `relay:{c}:readers` set: the replicas that read the channel (have local subscribers).
- `relay:{c}:deleted` the stream of a channel just deleted, kept a minute (DELETED_KEPT_S) so
  that every replica delivers what preceded the delete before closing.
- `relay:news:<replica>` a stream per replica of the publishes and deletes, made by other
  replicas, of the channels it reads, in the order Redis ran them: the channel, a sequence
  number (`relay:news:<replica>:sequence`), the message's stream id and its predecessor's and,
  unless it is larger than `NEWS_DATA_MAX`, the message; for a delete, the deleting replica
  (see `server.relay.redis_reader`). It expires an hour after the replica's last heartbeat.
- `relay:replicas`    sorted set: replica id -> Redis time of its last heartbeat; counts of
  replicas silent for `ALIVE_S` are ignored, so a crashed replica's subscribers stop counting.

Every state change is one Lua script, so it is atomic and uses Redis' clock (one clock for all
replicas). With `appendonly yes` and `appendfsync always` (docker-compose.yml, the test
fixture) a publish that was answered is on disk, and survives a Redis restart. Publishes made
while others are on their way to Redis go together in one pipeline (`server.relay.redis_batch`),
so under load a round trip and an fsync serve many of them.

Fan-out: each replica runs one reader (`server.relay.redis_reader`) on one connection for all
channels with local subscribers. It blocks in one `XREAD` on its own news and hands each
message of its channels, straight from the news, to every local subscriber
(`Backend._fan_out`), so Redis is read once per message per reading replica, never once per
subscriber or per channel, and the replica's Redis connections do not grow with its channels.
The replica that published a message delivers it to its own subscribers as soon as Redis
answers, when it is the next message they are owed (the script returns the channel's previous
id; `ReplicaReader.take_own`), and is sent no news of it: a game table's players and
spectators on that replica do not wait for a second round trip, and a replica alone on its
channels reads no news at all.

While Redis cannot be reached, every operation raises `Unavailable` (503 with Retry-After to a
publisher): nothing is half-done, and the reader retries on its own.
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import logging
import uuid
from collections.abc import Iterator
from typing import Any

import redis.asyncio as aioredis
from redis.asyncio.retry import Retry
from redis.backoff import NoBackoff
from redis.maint_notifications import MaintNotificationsConfig

from server.relay.backend import Backend, BackendConfig, unknown_history
from server.relay.errors import Unavailable
from server.relay.ids import MessageKey, parse_message_id
from server.relay.messages import DELETED, Backlog, ChannelInfo, Published, StoredMessage
from server.relay.redis_batch import ScriptBatcher
from server.relay.redis_reader import (
    DELETED_PART,
    NEWS_DATA_MAX,
    NEWS_KEPT,
    READERS_PART,
    REDIS_DOWN,
    REPLICAS_KEY,
    Entries,
    ReplicaReader,
    cancelled,
    channel_key,
    news_key,
    news_sequence_key,
)

log = logging.getLogger(__name__)

HEARTBEAT_S = 5.0
ALIVE_S = 15.0
IDLE_KEY_S = 86400  # a channel's keys outlive its last message by this long, less at most
RENEW_S = 3600  # this: the publish that renews their expiry comes at most once in this time
NEWS_IDLE_S = 3600  # a replica's news outlives its last heartbeat by this long
COMMAND_CONNECTIONS = 64
PUBLISH_PIPELINES = 2  # publishes on their way to Redis at once, in pipelines of at most
PUBLISH_BATCH = 256  # this many (see `server.relay.redis_batch`)
DELETED_KEPT_S = 60  # a deleted stream stays readable this long for the replicas' readers
RETRY_AFTER_S = 1
_NEWS_LAST = (NEWS_KEPT, NEWS_DATA_MAX, RENEW_S)  # the publish script's last arguments
REDIS_TIMEOUT_S = 10.0  # to connect, and for a publish pipeline's replies (then 503)


def _unavailable(error: Exception) -> Unavailable:
    return Unavailable(f"message store unavailable ({error}): retry", RETRY_AFTER_S)


@contextlib.contextmanager
def _store_errors() -> Iterator[None]:
    """Turn "Redis cannot be reached" into the relay's Unavailable (503, Retry-After)."""
    try:
        yield
    except REDIS_DOWN as error:
        raise _unavailable(error) from None


# Shared Lua helpers, prepended to the scripts below.
_LUA_HELPERS = """
local function clock()
  local t = redis.call('TIME')
  return tonumber(t[1]) + tonumber(t[2]) / 1e6, tonumber(t[1])
end

-- Drop the oldest entries while there are more than `maxlen`, or their data (`bytes`, the `d`
-- fields' total) exceeds `maxbytes` and more than one is left, or the oldest is older than
-- `cutoff`. `first` is the oldest entry's time if known (meta.first), else false: while no
-- bound is exceeded and it is not older than `cutoff`, nothing is read (the common case: an
-- entry is only read to be dropped, or to learn its time). Returns the entries left, their
-- bytes, the newest dropped id (or nil) and the oldest entry's time (false if none is left).
local function trim(stream, count, bytes, first, maxlen, cutoff, maxbytes)
  local evicted = nil
  while count > 0 do
    local over = count > maxlen or (count > 1 and bytes > maxbytes)
    if not over and first and first >= cutoff then break end
    local oldest = redis.call('XRANGE', stream, '-', '+', 'COUNT', 1)[1]
    first = tonumber(oldest[2][2])
    if not over and first >= cutoff then break end
    redis.call('XDEL', stream, oldest[1])
    bytes = bytes - string.len(oldest[2][6])  -- fields: t, time, c, type, d, data[, e, event]
    count = count - 1
    evicted = oldest[1]
    first = false
  end
  return count, bytes, evicted, first
end

-- The meta fields that `trim` changed, as HSET arguments (HDEL of `first` if none is left);
-- meta.evicted remembers the newest dropped id so that a resume from before it is told about
-- the gap.
local function trimmed(meta, fields, evicted, first, known)
  if evicted then
    table.insert(fields, 'evicted')
    table.insert(fields, evicted)
  end
  if first and first ~= known then
    table.insert(fields, 'first')
    table.insert(fields, string.format('%.6f', first))
  elseif not first and known then
    redis.call('HDEL', meta, 'first')
  end
  if #fields > 0 then redis.call('HSET', meta, unpack(fields)) end
end

-- `trim` with the stream's state read from Redis and written back; the entries left.
local function evict(stream, meta, maxlen, cutoff, maxbytes)
  local state = redis.call('HMGET', meta, 'bytes', 'first')
  local known = tonumber(state[2]) or false
  local count, bytes, evicted, first = trim(
    stream, redis.call('XLEN', stream), tonumber(state[1] or '0'), known, maxlen, cutoff, maxbytes)
  trimmed(meta, evicted and {'bytes', bytes} or {}, evicted, first, known)
  return count
end

-- Whether `replica` sent a heartbeat within `alive` seconds.
local function living(replicas, replica, now, alive)
  local seen = redis.call('ZSCORE', replicas, replica)
  return seen and tonumber(seen) >= now - alive
end

-- Subscribers of all living replicas.
local function subscribers(subs, replicas, now, alive)
  local total = 0
  local counts = redis.call('HGETALL', subs)
  for i = 1, #counts, 2 do
    if living(replicas, counts[i], now, alive) then total = total + tonumber(counts[i + 1]) end
  end
  return total
end

-- The news streams of a channel's living readers but `author` (whose own subscribers are
-- served as it publishes or deletes). A reader that missed news while it was not counted as
-- living sees the gap in its next message's predecessor.
local function audience(readers, replicas, now, alive, author)
  local streams = {}
  for _, reader in ipairs(redis.call('SMEMBERS', readers)) do
    if reader ~= author and living(replicas, reader, now, alive) then
      table.insert(streams, 'relay:news:' .. reader)  -- as `news_key` names it
    end
  end
  return streams
end

-- Append `fields` to each of the news `streams`, with the stream's next sequence number.
local function announce(streams, kept, fields)
  for _, news in ipairs(streams) do
    redis.call('XADD', news, 'MAXLEN', '~', kept, '*',
      'n', redis.call('INCR', news .. ':sequence'), unpack(fields))
  end
end
"""

# KEYS: stream meta subs replicas readers
# ARGV: maxlen ttl maxbytes alive idle_s content_type data event channel replica news_kept
#       news_data_max renew_s
_PUBLISH = (
    _LUA_HELPERS
    + """
local now, seconds = clock()
local meta = redis.call('HMGET', KEYS[2], 'last', 'bytes', 'first', 'requested', 'kept')
if meta[1] then
  local last_seconds = tonumber(string.match(meta[1], '^(%d+)-'))
  if last_seconds > seconds then seconds = last_seconds end
end
local fields = {'t', string.format('%.6f', now), 'c', ARGV[6], 'd', ARGV[7]}
if ARGV[8] ~= '' then
  table.insert(fields, 'e')
  table.insert(fields, ARGV[8])
end
local id = redis.call('XADD', KEYS[1], seconds .. '-*', unpack(fields))
local previous = meta[1] or '0-0'
local streams = audience(KEYS[5], KEYS[4], now, tonumber(ARGV[4]), ARGV[10])
if #streams > 0 then  -- most channels are read only where they are published
  local news = {'ch', ARGV[9], 'id', id, 'p', previous}
  if #ARGV[7] <= tonumber(ARGV[12]) then
    for i = 1, #fields do table.insert(news, fields[i]) end
  end
  announce(streams, ARGV[11], news)
end
local count = redis.call('XLEN', KEYS[1])
local known = tonumber(meta[3]) or false
local first = known
if count == 1 then first = tonumber(fields[2]) end  -- the new entry is the only one
local bytes = tonumber(meta[2] or '0') + string.len(ARGV[7])
local evicted
count, bytes, evicted, first = trim(KEYS[1], count, bytes, first, tonumber(ARGV[1]),
  now - tonumber(ARGV[2]), tonumber(ARGV[3]))
-- The keys' idle expiry is renewed once per renew_s rather than by every publish: two EXPIREs,
-- each with its entry in the append-only file, were a sixth of this script's time.
local changed = {'last', id, 'bytes', bytes}
if not meta[1] then  -- the channel's first message: its history here starts with it
  table.insert(changed, 'born')
  table.insert(changed, id)
end
local renew = not meta[5] or now - tonumber(meta[5]) >= tonumber(ARGV[13])
if renew then
  table.insert(changed, 'kept')
  table.insert(changed, string.format('%.6f', now))
end
trimmed(KEYS[2], changed, evicted, first, known)
if renew then  -- after the HSET, which creates the meta hash of a new channel
  redis.call('EXPIRE', KEYS[1], ARGV[5])
  redis.call('EXPIRE', KEYS[2], ARGV[5])
  redis.call('EXPIRE', KEYS[5], ARGV[5])
end
return {id, fields[2], count, meta[4] or '',
  subscribers(KEYS[3], KEYS[4], now, tonumber(ARGV[4])), previous}
"""
)

# KEYS: stream meta; ARGV: maxlen ttl maxbytes start(XRANGE bound) count
# Returns the entries, the newest evicted id, whether more entries follow (the one entry read
# to know it stays in Redis: a backlog page of large messages crosses the wire once), and the
# channel's first id (false: no such channel; 0-0: published before first ids were kept).
_READ_SINCE = (
    _LUA_HELPERS
    + """
if redis.call('EXISTS', KEYS[2]) == 0 then return {{}, false, 0, false} end
local now = clock()
redis.call('HSET', KEYS[2], 'requested', string.format('%.6f', now))
evict(KEYS[1], KEYS[2], tonumber(ARGV[1]), now - tonumber(ARGV[2]), tonumber(ARGV[3]))
local count = tonumber(ARGV[5])
local entries = redis.call('XRANGE', KEYS[1], ARGV[4], '+', 'COUNT', count + 1)
local more = #entries > count
if more then entries[#entries] = nil end
local marks = redis.call('HMGET', KEYS[2], 'evicted', 'born')
return {entries, marks[1], more and 1 or 0, marks[2] or '0-0'}
"""
)

# KEYS: stream meta subs replicas; ARGV: maxlen ttl maxbytes alive
_INFO = (
    _LUA_HELPERS
    + """
local now = clock()
evict(KEYS[1], KEYS[2], tonumber(ARGV[1]), now - tonumber(ARGV[2]), tonumber(ARGV[3]))
local messages = redis.call('XLEN', KEYS[1])
local subs = subscribers(KEYS[3], KEYS[4], now, tonumber(ARGV[4]))
if messages == 0 and subs == 0 then return false end
local meta = redis.call('HMGET', KEYS[2], 'last', 'requested')
return {messages, meta[2] or '', subs, meta[1] or '', string.format('%.6f', now)}
"""
)

# KEYS: stream meta subs replicas readers deleted
# ARGV: alive channel replica news_kept grave_s
# The stream is kept a little while as `deleted`, so that every replica can still deliver the
# messages published before the delete, then the close.
_DELETE = (
    _LUA_HELPERS
    + """
local now = clock()
local subs = subscribers(KEYS[3], KEYS[4], now, tonumber(ARGV[1]))
local existed = redis.call('EXISTS', KEYS[1]) + redis.call('DEL', KEYS[2]) > 0 or subs > 0
if redis.call('EXISTS', KEYS[1]) == 1 then
  redis.call('RENAME', KEYS[1], KEYS[6])
  redis.call('EXPIRE', KEYS[6], ARGV[5])
end
redis.call('DEL', KEYS[3])
announce(audience(KEYS[5], KEYS[4], now, tonumber(ARGV[1]), ARGV[3]), ARGV[4],
  {'ch', ARGV[2], 'r', ARGV[3]})
redis.call('DEL', KEYS[5])
return existed and 1 or 0
"""
)

# KEYS: subs replicas; ARGV: replica delta idle_s
_COUNT = """
local t = redis.call('TIME')
redis.call('ZADD', KEYS[2], tonumber(t[1]) + tonumber(t[2]) / 1e6, ARGV[1])
if redis.call('HINCRBY', KEYS[1], ARGV[1], ARGV[2]) <= 0 then
  redis.call('HDEL', KEYS[1], ARGV[1])
end
redis.call('EXPIRE', KEYS[1], ARGV[3])
"""

# KEYS: replicas news news_sequence; ARGV: replica news_idle_s
_HEARTBEAT = """
local t = redis.call('TIME')
local now = tonumber(t[1]) + tonumber(t[2]) / 1e6
redis.call('ZADD', KEYS[1], now, ARGV[1])
redis.call('ZREMRANGEBYSCORE', KEYS[1], '-inf', now - 3600)
redis.call('EXPIRE', KEYS[2], ARGV[2])
redis.call('EXPIRE', KEYS[3], ARGV[2])
"""


@functools.lru_cache(maxsize=4096)
def _publish_keys(channel: str) -> tuple[str, ...]:
    """The publish script's keys for `channel` (a game table publishes again and again)."""
    return (
        channel_key(channel, "stream"),
        channel_key(channel, "meta"),
        channel_key(channel, "subs"),
        REPLICAS_KEY,
        channel_key(channel, READERS_PART),
    )


def _encoded(values: tuple[Any, ...]) -> tuple[bytes, ...]:
    """Script arguments as Redis receives them, so that no publish converts them again."""
    return tuple(str(value).encode() for value in values)


def _keys(channel: str) -> dict[str, str]:
    return {part: channel_key(channel, part) for part in ("stream", "meta", "subs")}


def _to_message_id(stream_id: bytes) -> str:
    return stream_id.decode().replace("-", ":")


def _key(stream_id: bytes) -> MessageKey:
    return parse_message_id(_to_message_id(stream_id))


def _to_stream_id(message_id: str) -> str:
    seconds, tag = parse_message_id(message_id)
    return f"{seconds}-{tag}"


def _stored(
    channel: str, stream_id: bytes, fields: dict[bytes, bytes] | list[bytes]
) -> StoredMessage:
    """A StoredMessage from a stream entry (a dict from redis-py, a flat list from Lua)."""
    if isinstance(fields, list):
        fields = dict(zip(fields[::2], fields[1::2], strict=True))
    return StoredMessage(
        channel=channel,
        id=_to_message_id(stream_id),
        content_type=fields[b"c"].decode(),
        data=fields[b"d"],
        time=float(fields[b"t"]),
        event=fields[b"e"].decode() if b"e" in fields else None,
    )


def _info(reply: list[Any]) -> ChannelInfo:
    messages, requested, subscribers, last, now = reply
    return ChannelInfo(
        messages=int(messages),
        requested=-1 if not requested else int(float(now) - float(requested)),
        subscribers=int(subscribers),
        last_message_id=_to_message_id(last) if last else None,
    )


class RedisBackend(Backend):
    """Channels in Redis Streams; any number of replicas may share one Redis."""

    def __init__(self, config: BackendConfig, url: str) -> None:
        super().__init__(config)
        self.replica = uuid.uuid4().hex
        # No retry: a command whose answer was lost may have run, and publishes, counts and
        # deletes must not run twice. (A pooled connection that a Redis restart left closed is
        # replaced by the pool when it hands it out, before anything is sent on it; that check
        # is skipped while redis-py's maintenance notifications, a Redis Cloud feature, are on.)
        # Commands wait for a free connection rather than fail when all are busy.
        # (driver_info=None: no CLIENT SETINFO, which costs a package-metadata lookup per
        # connection, and readers connect often.)
        self._redis = aioredis.Redis.from_pool(
            aioredis.BlockingConnectionPool.from_url(
                url,
                retry=Retry(NoBackoff(), 0),
                max_connections=COMMAND_CONNECTIONS,
                driver_info=None,
                maint_notifications_config=MaintNotificationsConfig(enabled=False),
            )
        )
        self._reader = ReplicaReader(
            url,
            self.replica,
            self._redis,
            self._fan_out_entries,
            self._deleted_elsewhere,
            IDLE_KEY_S,
        )
        self._publish = ScriptBatcher(
            url, _PUBLISH, PUBLISH_PIPELINES, PUBLISH_BATCH, REDIS_TIMEOUT_S
        )
        self._read_since = self._redis.register_script(_READ_SINCE)
        self._info_script = self._redis.register_script(_INFO)
        self._delete = self._redis.register_script(_DELETE)
        self._count = self._redis.register_script(_COUNT)
        self._heartbeat_script = self._redis.register_script(_HEARTBEAT)
        self._heartbeat: asyncio.Task[None] | None = None
        self._unsynced: set[str] = set()
        self._closing: set[asyncio.Future[int]] = set()  # deletes seen by the reader
        self._encoded_bounds: dict[int, tuple[bytes, ...]] = {}  # `_publish_bounds`, by length

    def _bounds(self, channel: str) -> list[Any]:
        config = self.config
        return [config.length_of(channel), config.message_ttl, config.buffer_bytes]

    def _publish_bounds(self, length: int) -> tuple[bytes, ...]:
        """The publish script's arguments before the message's, encoded once per length."""
        found = self._encoded_bounds.get(length)
        if found is None:
            config = self.config
            bounds = (length, config.message_ttl, config.buffer_bytes, ALIVE_S, IDLE_KEY_S)
            found = self._encoded_bounds[length] = _encoded(bounds)
        return found

    @functools.cached_property
    def _publish_tail(self) -> tuple[bytes, ...]:
        """The publish script's arguments after the channel's, encoded once."""
        return _encoded((self.replica, *_NEWS_LAST))

    async def publish(
        self, channel: str, data: bytes, content_type: str, event: str | None = None
    ) -> Published:
        try:
            message_args = (content_type, data, event or "", channel)
            reply = await self._publish(
                _publish_keys(channel),
                (
                    *self._publish_bounds(self.config.length_of(channel)),
                    *message_args,
                    *self._publish_tail,
                ),
            )
        except REDIS_DOWN as error:
            raise _unavailable(error) from None
        stream_id, now, messages, requested, subscribers, previous = reply
        message_id = _to_message_id(stream_id)
        message = StoredMessage(
            channel=channel,
            id=message_id,
            content_type=content_type,
            data=data,
            time=float(now),
            event=event,
        )
        # This replica's subscribers get it now if it is the next message they are owed;
        # otherwise once the reader has read the channel's stream (other replicas' from their
        # news).
        if self._reader.take_own(channel, previous, stream_id):
            self._fan_out(channel, message)
        info = ChannelInfo(
            messages=messages,
            requested=-1 if not requested else int(float(now) - float(requested)),
            subscribers=subscribers,
            last_message_id=message_id,
        )
        return Published(message=message, info=info, had_subscribers=info.subscribers > 0)

    async def read_since(self, channel: str, last_id: str | None, limit: int) -> Backlog:
        start = "-" if last_id is None else "(" + _to_stream_id(last_id)
        keys = _keys(channel)
        with _store_errors():
            entries, evicted, more, born = await self._read_since(
                keys=[keys["stream"], keys["meta"]], args=[*self._bounds(channel), start, limit]
            )
        messages = [_stored(channel, stream_id, fields) for stream_id, fields in entries]
        after = None if last_id is None else parse_message_id(last_id)
        first = _key(born) if born else None
        gap = unknown_history(after, first) or (
            after is not None and bool(evicted) and _key(evicted) > after
        )
        return Backlog(messages=messages, gap=gap, more=bool(more))

    async def info(self, channel: str) -> ChannelInfo | None:
        keys = _keys(channel)
        with _store_errors():
            reply = await self._info_script(
                keys=[keys["stream"], keys["meta"], keys["subs"], REPLICAS_KEY],
                args=[*self._bounds(channel), ALIVE_S],
            )
        return None if reply is None else _info(reply)

    async def delete(self, channel: str) -> bool:
        keys = _keys(channel)
        with _store_errors():
            existed = await self._delete(
                keys=[
                    keys["stream"],
                    keys["meta"],
                    keys["subs"],
                    REPLICAS_KEY,
                    channel_key(channel, READERS_PART),
                    channel_key(channel, DELETED_PART),
                ],
                args=[ALIVE_S, channel, self.replica, NEWS_KEPT, DELETED_KEPT_S],
            )
            await self._reader.flush_deleted(channel)
        # Local subscribers now; other replicas' readers see the entry in their news.
        closed = await self._end_local(channel, DELETED)
        return bool(existed) or closed > 0

    async def close(self) -> None:
        """Close local subscriptions, withdraw this replica's counts, release connections."""
        channels = list(self._local)
        await super().close()
        if self._heartbeat is not None:
            self._heartbeat.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._heartbeat
        with contextlib.suppress(*REDIS_DOWN):
            async with self._redis.pipeline(transaction=False) as pipe:
                for channel in channels:
                    pipe.hdel(_keys(channel)["subs"], self.replica)
                pipe.zrem(REPLICAS_KEY, self.replica)
                pipe.delete(news_key(self.replica), news_sequence_key(self.replica))
                await pipe.execute()
        await self._reader.close()
        self._publish.close()
        await self._redis.aclose()

    # ----- the feed: this replica's one reader --------------------------------------------
    async def _open_feed(self, channel: str) -> None:
        with _store_errors():
            await self._reader.add(channel)

    async def _close_feed(self, channel: str) -> None:
        await self._reader.remove(channel)

    def _fan_out_entries(self, channel: str, entries: Entries) -> None:
        for stream_id, fields in entries:
            self._fan_out(channel, _stored(channel, stream_id, fields))

    def _deleted_elsewhere(self, channel: str) -> None:
        """Another replica deleted `channel` (and every replica's count of it)."""
        if channel in self._local:
            closing = asyncio.ensure_future(self._end_local(channel, DELETED))
            self._closing.add(closing)
            closing.add_done_callback(self._closing.discard)

    # ----- global subscriber counts ----------------------------------------------------------
    async def _subscribers_changed(self, channel: str, delta: int) -> None:
        if self._heartbeat is None:
            self._heartbeat = asyncio.create_task(self._beat(), name="relay-heartbeat")
        try:
            await self._count(
                keys=[_keys(channel)["subs"], REPLICAS_KEY],
                args=[self.replica, delta, IDLE_KEY_S],
            )
        except REDIS_DOWN as error:
            if delta > 0:
                raise _unavailable(error) from None  # the subscription fails, uncounted
            self._unsynced.add(channel)  # a departure must not fail: the heartbeat repairs it

    async def _beat(self) -> None:
        """Keep this replica counted as alive, and repair counts that could not be lowered."""
        while not cancelled():
            await asyncio.sleep(HEARTBEAT_S)
            try:
                await self._heartbeat_script(
                    keys=[REPLICAS_KEY, news_key(self.replica), news_sequence_key(self.replica)],
                    args=[self.replica, NEWS_IDLE_S],
                )
                for channel in list(self._unsynced):
                    subs_key, subscribers = _keys(channel)["subs"], self.local_subscribers(channel)
                    if subscribers:
                        await self._redis.hset(subs_key, self.replica, subscribers)
                    else:
                        await self._redis.hdel(subs_key, self.replica)
                    self._unsynced.discard(channel)
            except REDIS_DOWN as error:
                log.warning("relay heartbeat: Redis unavailable (%s)", error)

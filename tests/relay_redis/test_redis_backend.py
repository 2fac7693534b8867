"""RedisBackend against a real redis-server: order, resume, gaps, replicas, restarts, delete.

Two `RedisBackend` instances on one Redis stand for two server replicas. The transports'
tests (tests/relay) run the same HTTP-level suite on both backends; these check what only the
Redis backend can get wrong: state shared through Redis, one reader per channel, recovery.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Callable

import pytest
import redis.asyncio as aioredis

from server.relay import redis_backend, redis_reader
from server.relay.backend import BackendConfig, Start
from server.relay.errors import Unavailable
from server.relay.ids import parse_message_id
from server.relay.messages import ChannelClosed, Event, Gap, StoredMessage
from server.relay.redis_backend import IDLE_KEY_S, RENEW_S, RedisBackend
from tests.redis_server import RedisServer

WAIT_S = 10.0  # generous bound for events to arrive on a loaded machine (not a timing claim)

MakeBackend = Callable[..., RedisBackend]


class Collector:
    """A Sink that keeps every event, and lets a test wait for some number of them."""

    def __init__(self) -> None:
        self.events: list[Event] = []
        self._changed = asyncio.Event()

    def offer(self, event: Event, shared: bool = True) -> None:
        self.events.append(event)
        self._changed.set()

    async def drained(self) -> bool:
        return True  # it keeps everything at once

    async def wait_for(self, count: int) -> list[Event]:
        async def enough() -> None:
            while len(self.events) < count:
                self._changed.clear()
                await self._changed.wait()

        await asyncio.wait_for(enough(), WAIT_S)
        return self.events

    @property
    def ids(self) -> list[str]:
        return [event.id for event in self.events if isinstance(event, StoredMessage)]


@pytest.fixture
async def make_backend(redis_url: str) -> AsyncIterator[MakeBackend]:
    """Backends ("replicas") on the test's Redis, all closed at the end."""
    backends: list[RedisBackend] = []

    def make(**config: float) -> RedisBackend:
        backend = RedisBackend(BackendConfig(**config), redis_url)
        backends.append(backend)
        return backend

    yield make
    for backend in backends:
        await backend.close()


async def publish_many(
    backend: RedisBackend, channel: str, count: int, start: int = 0
) -> list[str]:
    ids = []
    for n in range(start, start + count):
        published = await backend.publish(channel, b'{"n": %d}' % n, "application/json")
        ids.append(published.message.id)
    return ids


async def test_ids_increase_and_subscribers_get_messages_in_order(make_backend: MakeBackend):
    backend = make_backend()
    sink = Collector()
    await backend.subscribe("table-1", sink, start=Start.NEWEST)

    ids = await publish_many(backend, "table-1", 30)

    keys = [parse_message_id(message_id) for message_id in ids]
    assert keys == sorted(keys) and len(set(keys)) == len(keys)
    await sink.wait_for(30)
    assert sink.ids == ids
    assert [event.data for event in sink.events] == [b'{"n": %d}' % n for n in range(30)]
    info = await backend.info("table-1")
    assert info is not None
    assert (info.messages, info.subscribers, info.last_message_id) == (30, 1, ids[-1])


async def test_resume_delivers_each_missed_message_exactly_once(make_backend: MakeBackend):
    backend = make_backend()
    ids = await publish_many(backend, "game", 5)
    sink = Collector()

    # Publish while the subscription is being set up: nothing may be lost or doubled between
    # the backlog and the live feed.
    racing = asyncio.create_task(publish_many(backend, "game", 20, start=5))
    await backend.subscribe("game", sink, last_id=ids[1])
    ids += await racing

    await sink.wait_for(len(ids) - 2)
    await asyncio.sleep(0.1)  # room for a duplicate to show up
    assert sink.ids == ids[2:]


async def test_resume_from_an_evicted_id_announces_the_gap(make_backend: MakeBackend):
    backend = make_backend(buffer_length=3)
    ids = await publish_many(backend, "game", 6)

    sink = Collector()
    await backend.subscribe("game", sink, last_id=ids[0])
    events = await sink.wait_for(4)
    assert events[0] == Gap(channel="game", last_id=ids[0])
    assert sink.ids == ids[3:]

    # ids[2] is the newest evicted message: resuming from it misses nothing.
    backlog = await backend.read_since("game", ids[2], 100)
    assert not backlog.gap
    assert [message.id for message in backlog.messages] == ids[3:]
    info = await backend.info("game")
    assert info is not None and info.messages == 3


async def test_expired_messages_leave_the_buffer(make_backend: MakeBackend):
    backend = make_backend(message_ttl=0.5)
    ids = await publish_many(backend, "lobby", 2)
    await asyncio.sleep(0.8)
    backlog = await backend.read_since("lobby", None, 100)
    assert backlog.messages == []
    assert (await backend.read_since("lobby", ids[0], 100)).gap
    assert await backend.info("lobby") is None


async def test_two_replicas_relay_to_each_others_subscribers(make_backend: MakeBackend):
    first, second = make_backend(), make_backend()
    on_first, on_second = Collector(), Collector()
    await first.subscribe("match", on_first, start=Start.NEWEST)
    await second.subscribe("match", on_second, start=Start.NEWEST)

    published = await first.publish("match", b"shot", "text/plain")
    ids = [published.message.id, *await publish_many(second, "match", 3)]

    assert published.had_subscribers and published.info.subscribers == 2
    await on_first.wait_for(4)
    await on_second.wait_for(4)
    assert on_first.ids == on_second.ids == ids
    info = await second.info("match")
    assert info is not None and info.subscribers == 2


async def test_subscribers_count_only_while_their_replica_lives(make_backend: MakeBackend):
    first, second = make_backend(), make_backend()
    subscription = await second.subscribe("match", Collector())
    assert not (await first.publish("other", b"x", "text/plain")).had_subscribers
    assert (await first.publish("match", b"x", "text/plain")).had_subscribers

    await second.unsubscribe(subscription)
    info = await first.info("match")
    assert info is not None and info.subscribers == 0
    await second.subscribe("match", Collector())
    await second.close()  # a replica shutting down withdraws its subscribers
    info = await first.info("match")
    assert info is not None and info.subscribers == 0


async def test_a_silent_replica_stops_counting(
    make_backend: MakeBackend, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(redis_backend, "HEARTBEAT_S", 0.1)
    monkeypatch.setattr(redis_backend, "ALIVE_S", 0.6)
    observer, crashing = make_backend(), make_backend()
    await crashing.subscribe("match", Collector())
    await asyncio.sleep(1.0)  # several heartbeats: still alive, still counted
    info = await observer.info("match")
    assert info is not None and info.subscribers == 1

    assert crashing._heartbeat is not None
    crashing._heartbeat.cancel()  # the replica hangs or dies without a word
    await asyncio.sleep(1.0)
    assert await observer.info("match") is None


async def _clients(redis_url: str) -> list[dict]:
    admin = aioredis.from_url(redis_url)
    try:
        return [client for client in await admin.client_list() if client["cmd"] != "client|list"]
    finally:
        await admin.aclose()


async def test_one_redis_reader_per_replica_whatever_its_channels(
    make_backend: MakeBackend, redis_url: str
) -> None:
    """One channel or two hundred: one blocked XREAD and the same connection count, and every
    subscriber of every channel gets its messages through that one reader."""
    backend = make_backend()
    first = [Collector() for _ in range(20)]
    for sink in first:
        await backend.subscribe("crowd", sink, start=Start.NEWEST)
    await backend.publish("crowd", b"hello", "text/plain")
    for sink in first:
        await sink.wait_for(1)
    connections = len(await _clients(redis_url))

    many = {f"table-{n}": Collector() for n in range(200)}
    for channel, sink in many.items():
        await backend.subscribe(channel, sink, start=Start.NEWEST)
    for channel in many:
        await backend.publish(channel, channel.encode(), "text/plain")
    for channel, sink in many.items():
        events = await sink.wait_for(1)
        assert [event.data for event in events] == [channel.encode()]

    clients = await _clients(redis_url)
    assert len(clients) == connections
    assert sum(client["cmd"] == "xread" for client in clients) == 1


@pytest.mark.parametrize("kill", [False, True], ids=["shutdown", "sigkill"])
async def test_redis_restart_loses_nothing_acknowledged(
    make_backend: MakeBackend, redis_server: RedisServer, kill: bool
) -> None:
    publisher, reader = make_backend(), make_backend()
    sink = Collector()
    await reader.subscribe("game", sink, start=Start.NEWEST)
    ids = await publish_many(publisher, "game", 10)
    await sink.wait_for(10)

    await asyncio.to_thread(redis_server.restart, kill=kill)
    ids += await publish_many(publisher, "game", 10, start=10)

    await sink.wait_for(20)  # the reader reconnected and went on from where it was
    assert sink.ids == ids
    backlog = await make_backend().read_since("game", None, 100)
    assert [message.id for message in backlog.messages] == ids
    later = await publisher.publish("game", b"after", "text/plain")
    assert parse_message_id(later.message.id) > parse_message_id(ids[-1])


async def test_replica_restart_resumes_by_id(make_backend: MakeBackend):
    old = make_backend()
    sink = Collector()
    await old.subscribe("game", sink, start=Start.NEWEST)
    ids = await publish_many(old, "game", 3)
    await sink.wait_for(3)
    await old.close()

    ids += await publish_many(make_backend(), "game", 4, start=3)
    resumed = Collector()
    await make_backend().subscribe("game", resumed, last_id=sink.ids[-1])
    await resumed.wait_for(4)
    assert resumed.ids == ids[3:]


async def test_delete_closes_subscribers_on_every_replica(make_backend: MakeBackend):
    first, second = make_backend(), make_backend()
    on_first, on_second = Collector(), Collector()
    await first.subscribe("game", on_first, start=Start.NEWEST)
    await second.subscribe("game", on_second, start=Start.NEWEST)
    await publish_many(first, "game", 2)

    assert await first.delete("game")

    closed = ChannelClosed(channel="game", reason="deleted")
    assert (await on_first.wait_for(3))[-1] == closed
    assert (await on_second.wait_for(3))[-1] == closed
    assert await second.info("game") is None
    assert (await second.read_since("game", None, 100)).messages == []
    assert second.local_subscribers("game") == 0
    assert not await second.delete("game")


@pytest.mark.parametrize("bad", ["", "12", "1:2:3", "a:b", "-1:0"])
async def test_malformed_resume_id_is_refused(make_backend: MakeBackend, bad: str):
    backend = make_backend()
    with pytest.raises(ValueError):
        await backend.subscribe("game", Collector(), last_id=bad)
    assert backend.local_subscribers("game") == 0


class HeldReads:
    """Holds a replica's news reader before its next XREAD until `release`, so that a test can
    change Redis while the reader is behind (its reads are real once released)."""

    def __init__(self, backend: RedisBackend) -> None:
        self._gate = asyncio.Event()
        reader = backend._reader
        real = reader._next_news

        async def held() -> object:
            await self._gate.wait()
            return await real()

        reader._next_news = held  # type: ignore[method-assign]

    def release(self) -> None:
        self._gate.set()


async def test_news_trimmed_before_it_was_read_loses_no_message(
    make_backend: MakeBackend, redis_url: str
) -> None:
    """The reader sees from the news' sequence numbers that entries it never read are gone,
    and reads its channels' own streams instead of skipping to the news that is left."""
    here, there = make_backend(), make_backend()
    held = HeldReads(here)
    sink = Collector()
    await here.subscribe("game", sink, start=Start.NEWEST)
    ids = await publish_many(there, "game", 3)
    admin = aioredis.from_url(redis_url)
    news = redis_reader.news_key(here.replica)
    await admin.xtrim(news, maxlen=0)  # as if trimmed while this reader lagged
    await admin.aclose()
    ids += await publish_many(there, "game", 2, start=3)

    held.release()
    await sink.wait_for(5)
    await asyncio.sleep(0.1)  # room for a duplicate to show up
    assert sink.ids == ids


async def test_messages_too_large_for_the_news_keep_their_place(make_backend: MakeBackend):
    """Small messages come with the news, large ones are fetched from the channel's stream:
    one batch of news mixing both still delivers each once, in order."""
    here, there = make_backend(), make_backend()
    held = HeldReads(here)
    sink, other = Collector(), Collector()
    await here.subscribe("game", sink, start=Start.NEWEST)
    await here.subscribe("lobby", other, start=Start.NEWEST)
    large = b"x" * (redis_reader.NEWS_DATA_MAX + 1)
    bodies = [b"1", large + b"2", b"3", b"4", large + b"5", b"6"]
    ids = []
    for body in bodies:
        ids.append((await there.publish("game", body, "text/plain")).message.id)
        await there.publish("lobby", body[-1:], "text/plain")

    held.release()
    await sink.wait_for(len(bodies))
    await other.wait_for(len(bodies))
    await asyncio.sleep(0.1)
    assert sink.ids == ids
    assert [event.data for event in sink.events] == bodies
    assert [event.data for event in other.events] == [body[-1:] for body in bodies]


async def test_concurrent_publishes_each_get_their_own_id(make_backend: MakeBackend):
    """Publishes made at once go to Redis in one pipeline, in the order they were made."""
    backend = make_backend()
    sink = Collector()
    await backend.subscribe("game", sink, start=Start.NEWEST)
    published = await asyncio.gather(
        *(backend.publish("game", b"%d" % n, "text/plain") for n in range(50))
    )
    ids = [result.message.id for result in published]
    keys = [parse_message_id(message_id) for message_id in ids]
    assert keys == sorted(keys) and len(set(keys)) == 50
    await sink.wait_for(50)
    assert [event.data for event in sink.events] == [b"%d" % n for n in range(50)]
    assert [result.info.messages for result in published] == list(range(1, 51))


async def test_publish_survives_a_flushed_script_cache(
    make_backend: MakeBackend, redis_url: str
) -> None:
    backend = make_backend()
    first = await backend.publish("game", b"1", "text/plain")
    admin = aioredis.from_url(redis_url)
    await admin.script_flush()
    await admin.aclose()
    second = await asyncio.gather(*(backend.publish("game", b"2", "text/plain") for _ in range(3)))
    assert [result.info.messages for result in second] == [2, 3, 4]
    assert parse_message_id(second[0].message.id) > parse_message_id(first.message.id)


class ReplyCutter:
    """A TCP relay to a real Redis that, once `armed`, lets the next script call through and
    closes its connection as soon as Redis answers: the call ran, its answer never arrives."""

    def __init__(self, redis_port: int) -> None:
        self.armed = False
        self._redis_port = redis_port
        self._server: asyncio.Server | None = None

    @property
    def url(self) -> str:
        assert self._server is not None
        return f"redis://127.0.0.1:{self._server.sockets[0].getsockname()[1]}/0"

    async def __aenter__(self) -> ReplyCutter:
        self._server = await asyncio.start_server(self._relay, "127.0.0.1", 0)
        return self

    async def __aexit__(self, *exc_info: object) -> None:
        assert self._server is not None
        self._server.close()

    async def _relay(self, client_in: asyncio.StreamReader, client_out: asyncio.StreamWriter):
        redis_in, redis_out = await asyncio.open_connection("127.0.0.1", self._redis_port)
        doomed = False

        async def requests() -> None:
            nonlocal doomed
            while data := await client_in.read(65536):
                if self.armed and b"EVALSHA" in data:
                    self.armed, doomed = False, True
                redis_out.write(data)
                await redis_out.drain()

        async def replies() -> None:
            while (data := await redis_in.read(65536)) and not doomed:
                client_out.write(data)
                await client_out.drain()
            client_out.close()
            redis_out.close()

        await asyncio.gather(requests(), replies(), return_exceptions=True)


async def test_a_publish_whose_answer_was_lost_is_not_sent_again(redis_server: RedisServer):
    """The publisher is told the store failed (503), and the message, which Redis did store, is
    stored once: the pipeline is not sent again on a fresh connection. The replica's own
    subscribers still get it, before the next."""
    async with ReplyCutter(redis_server.port) as cutter:
        backend = RedisBackend(BackendConfig(), cutter.url)
        sink = Collector()
        try:
            await backend.subscribe("game", sink, start=Start.NEWEST)
            first = await backend.publish("game", b"1", "text/plain")
            cutter.armed = True
            with pytest.raises(Unavailable):
                await backend.publish("game", b"2", "text/plain")
            third = await backend.publish("game", b"3", "text/plain")  # a fresh connection
            await sink.wait_for(3)
        finally:
            await backend.close()
    messages = [event for event in sink.events if isinstance(event, StoredMessage)]
    assert [message.data for message in messages] == [b"1", b"2", b"3"]
    admin = aioredis.from_url(redis_server.url)
    entries = await admin.xrange(redis_reader.stream_key("game"))
    await admin.aclose()
    assert [fields[b"d"] for _, fields in entries] == [b"1", b"2", b"3"]
    assert third.info.messages == 3
    assert parse_message_id(third.message.id) > parse_message_id(first.message.id)


async def test_a_channels_keys_expire_a_day_after_its_last_renewal(
    make_backend: MakeBackend, redis_url: str
) -> None:
    """Every channel's keys carry the idle expiry from its first publish; later publishes
    renew it only once RENEW_S has passed since the last renewal (the meta's `kept`)."""
    backend = make_backend()
    stream, meta = (redis_reader.channel_key("game", part) for part in ("stream", "meta"))
    admin = aioredis.from_url(redis_url)
    try:

        async def ttls() -> list[int]:
            return [await admin.ttl(key) for key in (stream, meta)]

        await backend.publish("game", b"1", "text/plain")
        assert all(IDLE_KEY_S - 5 < ttl <= IDLE_KEY_S for ttl in await ttls())
        for key in (stream, meta):
            await admin.expire(key, 1000)
        await backend.publish("game", b"2", "text/plain")  # renewed a moment ago: left alone
        assert all(990 < ttl <= 1000 for ttl in await ttls())
        kept = float(await admin.hget(meta, "kept"))
        await admin.hset(meta, "kept", f"{kept - RENEW_S:.6f}")  # as if an hour had passed
        await backend.publish("game", b"3", "text/plain")
        assert all(IDLE_KEY_S - 5 < ttl <= IDLE_KEY_S for ttl in await ttls())
    finally:
        await admin.aclose()


async def test_a_replicas_own_message_reaches_its_subscribers_without_waiting_for_the_news(
    make_backend: MakeBackend, redis_url: str
) -> None:
    """While the reader is held, what this replica publishes is delivered at once, in order,
    and its own news stays empty: a replica alone on its channels reads no news."""
    backend = make_backend()
    held = HeldReads(backend)
    sink = Collector()
    await backend.subscribe("game", sink, start=Start.NEWEST)
    ids = await publish_many(backend, "game", 3)
    assert sink.ids == ids  # before any news was read
    held.release()
    ids += await publish_many(backend, "game", 1, start=3)
    await asyncio.sleep(0.2)  # room for a duplicate to show up
    assert sink.ids == ids
    admin = aioredis.from_url(redis_url)
    try:
        assert await admin.xlen(redis_reader.news_key(backend.replica)) == 0
    finally:
        await admin.aclose()


async def test_an_own_message_after_another_replicas_does_not_overtake_it(
    make_backend: MakeBackend,
) -> None:
    """A message that follows one this replica has not read yet is not delivered ahead of
    it: the channel is read from its stream, both in order, without waiting for the news;
    the news' copy of the first, read later, is dropped as old."""
    here, there = make_backend(), make_backend()
    held = HeldReads(here)
    sink = Collector()
    await here.subscribe("game", sink, start=Start.NEWEST)
    first = await there.publish("game", b"there", "text/plain")
    second = await here.publish("game", b"here", "text/plain")
    await sink.wait_for(2)  # the news reader is still held
    assert sink.ids == [first.message.id, second.message.id]
    held.release()
    third = await there.publish("game", b"there again", "text/plain")
    await sink.wait_for(3)
    await asyncio.sleep(0.1)  # room for a duplicate to show up
    assert sink.ids == [first.message.id, second.message.id, third.message.id]


async def test_a_replica_is_sent_news_only_of_the_channels_it_reads(
    make_backend: MakeBackend, redis_url: str
) -> None:
    """Each replica's news holds other replicas' messages of its own channels, and no more
    once its last subscriber of a channel has left."""
    here, there = make_backend(), make_backend()
    sink = Collector()
    subscription = await here.subscribe("game", sink, start=Start.NEWEST)
    await there.subscribe("lobby", Collector(), start=Start.NEWEST)
    await there.publish("game", b"1", "text/plain")
    await there.publish("lobby", b"2", "text/plain")
    await sink.wait_for(1)
    await here.unsubscribe(subscription)
    await there.publish("game", b"3", "text/plain")
    admin = aioredis.from_url(redis_url)
    try:
        news = await admin.xrange(redis_reader.news_key(here.replica))
        assert [(fields[b"ch"], fields[b"d"]) for _, fields in news] == [(b"game", b"1")]
        assert await admin.xlen(redis_reader.news_key(there.replica)) == 0
        readers = redis_reader.channel_key("game", redis_reader.READERS_PART)
        assert await admin.smembers(readers) == set()
    finally:
        await admin.aclose()


async def test_subscribing_while_another_replica_publishes_misses_nothing(
    make_backend: MakeBackend,
) -> None:
    """Subscribers that arrive on one replica while another publishes, as the channel's feed
    there opens and closes, each get every message once and in order: the backlog, then the
    live feed, with nothing between (a replica joins a channel's readers and reads its
    position in one step, and leaves only after any join on its way)."""
    here, there = make_backend(), make_backend()
    sinks = [Collector() for _ in range(10)]
    published: list[str] = []

    async def publisher() -> None:
        for n in range(60):
            published.append((await there.publish("game", b"%d" % n, "text/plain")).message.id)
            await asyncio.sleep(0)

    async def subscriber(sink: Collector, delay: int) -> None:
        for _ in range(delay):
            await asyncio.sleep(0)
        await here.subscribe("game", sink, start=Start.OLDEST)

    async def churner() -> None:  # opens and closes the channel's feed until others hold it
        while len(published) < 60:
            await here.unsubscribe(await here.subscribe("game", Collector()))

    await asyncio.gather(
        publisher(), churner(), *(subscriber(sink, 8 * n + 4) for n, sink in enumerate(sinks))
    )
    for sink in sinks:
        await sink.wait_for(60)
    await asyncio.sleep(0.1)  # room for a duplicate to show up
    for sink in sinks:
        assert sink.ids == published

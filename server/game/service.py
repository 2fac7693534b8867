"""The game service's parts, built once per server process and shared by the HTTP handlers.

Storage follows the settings: SQLite (a file, or in memory when none is given) by default,
Redis when the app runs with a Redis URL (then replicas share it, and the relay's Redis too).
"""

from __future__ import annotations

import time
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass, field

from aiohttp import web

from server.game.actor import OUTAGE, MatchContext, Matches, new_replica_id, take
from server.game.background import running
from server.game.challenges import Challenges
from server.game.clock import running_clock
from server.game.diagrams import DiagramWork
from server.game.expiry import running_expiry
from server.game.identity import ONLINE, Identity
from server.game.leaderboard import Breaks
from server.game.lobby import Lobby
from server.game.publisher import Publisher
from server.game.replays import ReplayShotsCache
from server.game.tables import GRACE
from server.game.workers import WorkerPool, default_workers
from server.relay import RateLimiter, Relay
from server.storage import Storage

#: Names one client address may hold: new identities per address are limited to this many
#: at once and as many again per `ONLINE` seconds, the time an unused name stays held (so an
#: address holds at most about this many names; before: some 1,500). `billiards serve
#: --names-per-address` sets it (a network behind one NAT address may need more).
NAMES_PER_ADDRESS = 50

#: (requests per second, burst) per caller for what makes the server store or send something:
#: new identities per client address (`NAMES_PER_ADDRESS`), tables, quick-match requests and
#: heartbeats per player, quick messages per player and table (one per 2 s), aims per player
#: and table (the web client sends one no sooner than 250 ms after the answer to the last, so
#: that no delay on the way brings two closer than the 200 ms allowed), leaderboard claims per
#: player (their worker time is bounded apart, server/game/budget.py), and a practice table's
#: shots, re-racks and retakes per player (far above anyone's practice: each is stored, and a
#: rack's end archives a replay; before, one player stored 190 shots a second). A match's
#: intents need none: only the player to act may send one, and it waits for the previous
#: outcome, which the opponent's shot comes before.
LIMITS: dict[str, tuple[float, int]] = {
    "register": (NAMES_PER_ADDRESS / ONLINE, NAMES_PER_ADDRESS),
    "create": (1.0, 20),
    "quick": (2.0, 20),
    "challenge": (0.5, 10),
    "chat": (0.5, 1),
    "aim": (5.0, 1),
    "heartbeat": (2.0, 10),
    "claim": (0.5, 10),
    "practice": (5.0, 100),
}

#: How much lower than the server the background worker runs: claims, replays' shots and the
#: diagrams page's shot families and real shots (server/game/diagrams.py),
#: which nobody at a table waits on, go to one worker of their own at this priority, so that
#: a flood of them takes neither the matches' workers nor the CPU their shots want.
BACKGROUND_NICE = 10


@dataclass
class Service:
    storage: Storage
    pool: WorkerPool
    bots: WorkerPool
    publisher: Publisher
    identity: Identity
    breaks: Breaks
    lobby: Lobby
    challenges: Challenges
    matches: Matches
    replay_shots: ReplayShotsCache
    diagrams: DiagramWork
    #: Token buckets for what a client can make the server store or send (see LIMITS).
    limits: dict[str, RateLimiter] = field(
        default_factory=lambda: {kind: RateLimiter(*limit) for kind, limit in LIMITS.items()}
    )

    def throttle(self, kind: str, key: str) -> None:
        """Take one `kind` request for `key` from its bucket; RATE_LIMITED if it is empty."""
        take(self.limits[kind], key)


async def open_storage(database: str | None, redis_url: str | None) -> Storage:
    if redis_url is not None:
        from server.storage.redis import RedisStorage

        return await RedisStorage.open(redis_url)
    from server.storage.sqlite import SqliteStorage

    return await SqliteStorage.open(database or ":memory:")


@asynccontextmanager
async def running_service(
    relay: Relay,
    database: str | None,
    redis_url: str | None,
    workers: int | None,
    grace: float = GRACE,
    names_per_address: int = NAMES_PER_ADDRESS,
) -> AsyncIterator[Service]:
    """The service, its storage open, worker pool started and lobby publishing, until exit."""
    storage = await open_storage(database, redis_url)
    pool = WorkerPool(workers or default_workers())
    # The bots' searches (up to a second of a worker each) have workers of their own, so that
    # a match's shot never queues behind them (server/game/actor.py, invariant 6).
    bots = WorkerPool(workers or default_workers())
    background = WorkerPool(1, nice=BACKGROUND_NICE)
    publisher = Publisher(relay)
    lobby = Lobby(storage, publisher)
    breaks = Breaks(storage, background, publisher)
    limits = {kind: RateLimiter(*limit) for kind, limit in LIMITS.items()}
    context = MatchContext(
        storage,
        pool,
        bots,
        publisher,
        lobby.changed,
        new_replica_id(),
        breaks,
        practice=limits["practice"],
        grace=grace,
    )
    lobby.seen = context.seen
    service = Service(
        storage=storage,
        pool=pool,
        bots=bots,
        publisher=publisher,
        identity=Identity(relay.authority, storage),
        breaks=breaks,
        lobby=lobby,
        challenges=Challenges(storage, publisher, lobby),
        matches=Matches(context),
        replay_shots=ReplayShotsCache(storage, background),
        diagrams=DiagramWork(background),
        limits=limits,
    )
    service.limits["register"] = RateLimiter(names_per_address / ONLINE, names_per_address)
    context.up_since = await storage.service_since(time.time(), OUTAGE)  # before any request
    try:
        async with (
            lobby.running(),
            running(context.keep_run),
            running_clock(storage, service.matches),
            running_expiry(storage, publisher, lambda table: context.presence.pop(table, None)),
        ):
            yield service
            await service.matches.idle()
    finally:
        pool.close()
        bots.close()
        background.close()
        await storage.close()


SERVICE_KEY = web.AppKey("service", Service)

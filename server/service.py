"""The game service's parts, built once per server process and shared by the HTTP handlers.

Storage follows the settings: SQLite (a file, or in memory when none is given) by default,
Redis when the app runs with a Redis URL (then replicas share it, and the relay's Redis too).
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass, field

from aiohttp import web

from server.api_models import PresenceMessage
from server.channels import Publisher
from server.clock import running_clock
from server.errors import ErrorCode, ServiceError
from server.expiry import running_expiry
from server.identity import Identity
from server.leaderboard import Breaks
from server.lobby import Lobby
from server.match import MatchContext, Matches, new_replica_id
from server.relay.limits import RateLimiter
from server.relay.relay import Relay
from server.replays import ReplayShotsCache
from server.storage import Storage
from server.tables import GRACE
from server.workers import WorkerPool, default_workers

#: (requests per second, burst) per caller for what makes the server store or send something:
#: new identities per client address, tables, quick-match requests and heartbeats per player,
#: quick messages per player and table (one per 2 s), aims per player and table (clients send
#: one per 250 ms at most; one per 200 ms leaves room for the network's jitter). Intents need
#: none: only the player to act may send one, and it waits for the previous outcome.
LIMITS: dict[str, tuple[float, int]] = {
    "register": (5.0, 200),
    "create": (1.0, 20),
    "quick": (2.0, 20),
    "chat": (0.5, 1),
    "aim": (5.0, 1),
    "heartbeat": (2.0, 10),
}


@dataclass
class Service:
    storage: Storage
    pool: WorkerPool
    publisher: Publisher
    identity: Identity
    breaks: Breaks
    lobby: Lobby
    matches: Matches
    replay_shots: ReplayShotsCache
    #: Seconds a disconnected player may stay away before the opponent may claim the win.
    grace: float = GRACE
    #: The presence each table last announced from this process (to announce changes once).
    presence: dict[str, PresenceMessage] = field(default_factory=dict)
    #: Token buckets for what a client can make the server store or send (see LIMITS).
    limits: dict[str, RateLimiter] = field(
        default_factory=lambda: {kind: RateLimiter(*limit) for kind, limit in LIMITS.items()}
    )

    def throttle(self, kind: str, key: str) -> None:
        """Take one `kind` request for `key` from its bucket; RATE_LIMITED if it is empty."""
        wait = self.limits[kind].allow(key)
        if wait > 0:
            raise ServiceError(ErrorCode.RATE_LIMITED, f"too many requests: retry in {wait:.1f} s")


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
) -> AsyncIterator[Service]:
    """The service, its storage open, worker pool started and lobby publishing, until exit."""
    storage = await open_storage(database, redis_url)
    pool = WorkerPool(workers or default_workers())
    publisher = Publisher(relay)
    lobby = Lobby(storage, publisher)
    breaks = Breaks(storage, pool, publisher)
    context = MatchContext(storage, pool, publisher, lobby.changed, new_replica_id(), breaks)
    service = Service(
        storage=storage,
        pool=pool,
        publisher=publisher,
        identity=Identity(relay.authority, storage),
        breaks=breaks,
        lobby=lobby,
        matches=Matches(context),
        replay_shots=ReplayShotsCache(storage, pool),
        grace=grace,
    )
    try:
        async with (
            lobby.running(),
            running_clock(storage, service.matches),
            running_expiry(storage, publisher, lambda table: service.presence.pop(table, None)),
        ):
            yield service
            await service.matches.idle()
    finally:
        pool.close()
        await storage.close()


SERVICE_KEY = web.AppKey("service", Service)

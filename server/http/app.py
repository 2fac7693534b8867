"""The aiohttp application of the billiards server: `create_app(settings)`.

It mounts the relay (`server.relay`) and the game service's API (`server.http.api`). Both follow
the settings: in memory and SQLite by default (one process), Redis when a Redis URL is given
(several replicas).
"""

from __future__ import annotations

from collections.abc import AsyncIterator

from aiohttp import web
from pydantic import BaseModel, ConfigDict, Field

from server.game.service import NAMES_PER_ADDRESS
from server.game.tables import GRACE
from server.http.api import mount_api
from server.http.logs import one_line_bad_requests
from server.http.pages import mount_web
from server.protocol.ids import LOBBY
from server.relay import Backend, BackendConfig, MemoryBackend, Relay, RelaySettings, mount_relay

#: The buffer of every channel the game service uses: the relay's 100 messages, and at most
#: 4 MiB of their data. A table channel's outcomes carry trajectories (an eight-ball break's is
#: some 40 KB, a long snooker visit's far more), so a count alone would let one table hold 100
#: of the largest; 4 MiB is still several racks of outcomes. A client resuming from further
#: back is told of the gap and fetches the table's state (docs/protocol.md). The lobby's
#: channel keeps only its newest snapshot, which replaces the last: a lobby page opened would
#: otherwise be sent the 100 last snapshots (700 KB with a busy lobby) to draw each in turn.
SERVICE_BUFFER = BackendConfig(buffer_bytes=4 * 1024 * 1024, last_value=frozenset({LOBBY}))


def relay_settings(**fields: object) -> RelaySettings:
    """The relay configuration the game service runs with: the relay's defaults, each
    channel's backlog bounded by SERVICE_BUFFER."""
    return RelaySettings(buffer=SERVICE_BUFFER, **fields)


class AppSettings(BaseModel):
    """The server's configuration, immutable and passed in."""

    model_config = ConfigDict(frozen=True)

    relay: RelaySettings = Field(default_factory=relay_settings)
    redis_url: str | None = Field(default=None, description="Redis backend; None: in memory")
    database: str | None = Field(
        default=None, description="SQLite file of the game service (without Redis); None: memory"
    )
    workers: int | None = Field(default=None, ge=1, description="simulation processes")
    names_per_address: int = Field(
        default=NAMES_PER_ADDRESS, ge=1, description="names one client address may hold"
    )
    grace: float = Field(
        default=GRACE, ge=0, le=3600, description="seconds before a gone player's win is claimable"
    )


def make_backend(settings: AppSettings) -> Backend:
    """The relay backend the settings ask for (Redis is imported only when asked for)."""
    if settings.redis_url is None:
        return MemoryBackend(settings.relay.buffer)
    from server.relay.redis_backend import RedisBackend

    return RedisBackend(settings.relay.buffer, settings.redis_url)


def create_app(settings: AppSettings | None = None) -> web.Application:
    """The application, its relay backend created on startup and closed on cleanup."""
    settings = settings or AppSettings()
    one_line_bad_requests()
    app = web.Application()
    backend = make_backend(settings)
    relay = Relay.build(backend, settings.relay)
    mount_relay(app, relay)
    mount_web(app)

    async def backend_lifetime(app: web.Application) -> AsyncIterator[None]:
        yield
        await backend.close()

    app.cleanup_ctx.append(backend_lifetime)
    mount_api(
        app,
        relay,
        database=settings.database,
        redis_url=settings.redis_url,
        workers=settings.workers,
        grace=settings.grace,
        names_per_address=settings.names_per_address,
    )
    return app

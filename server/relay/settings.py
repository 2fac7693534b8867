"""The relay's configuration: one immutable pydantic model, passed in (never module globals)."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, field_validator

from server.relay.addresses import networks
from server.relay.backend import BackendConfig, Start


class RelaySettings(BaseModel):
    """Every knob of the relay, with nchan-like defaults where nchan has one."""

    model_config = ConfigDict(frozen=True)

    buffer: BackendConfig = Field(default_factory=BackendConfig)
    max_message_bytes: int = Field(default=64 * 1024, ge=1, description="larger bodies: 413")
    send_queue_length: int = Field(
        default=1024, ge=1, description="events queued per connection before it is closed"
    )
    send_queue_bytes: int = Field(
        default=1024 * 1024, ge=1, description="bytes queued per connection before it is closed"
    )
    socket_buffer_bytes: int = Field(
        default=16 * 1024,
        ge=1024,
        description="bytes a subscriber's socket may buffer in the process before writes wait "
        "(the transport's high-water mark; the kernel's buffers come on top)",
    )
    send_budget_bytes: int = Field(
        default=8 * 1024 * 1024,
        ge=1,
        description="bytes queued over all connections of the process; past it, the connection "
        "asking for more is closed",
    )
    publish_rate: float = Field(default=50.0, gt=0, description="publishes/s per client token")
    publish_burst: int = Field(default=100, ge=1, description="client publishes allowed at once")
    server_publish_rate: float = Field(
        default=5000.0, gt=0, description="publishes/s per server token holder (game service)"
    )
    server_publish_burst: int = Field(
        default=10_000, ge=1, description="server publishes allowed at once"
    )
    auth_secret: str | None = Field(
        default=None,
        min_length=32,
        description="HMAC-SHA256 key of the JWTs (32+ characters); None: random per process",
    )
    public_prefix: str = Field(
        default="public-", description="channels read-only for clients (server tokens only)"
    )
    allowed_origins: list[str] = Field(
        default=["*"],
        description="origins whose pages may subscribe (CORS, as nchan's "
        "nchan_access_control_allow_origin); '*' allows any; others get 403",
    )
    first_message: Start = Field(default=Start.OLDEST, description="start without a last id")
    longpoll_timeout: float = Field(default=60.0, gt=0, description="seconds before 408")
    max_multiplex: int = Field(default=8, ge=1, description="channels per subscriber request")
    keepalive: float | None = Field(
        default=30.0, description="s between WebSocket pings, SSE comments"
    )
    max_connections_per_address: int | None = Field(
        default=None,
        ge=1,
        description="subscriber connections one client address may hold (429 past it); None: "
        "no cap (the byte bounds hold without one)",
    )
    trusted_proxies: list[str] = Field(
        default=[],
        description="addresses or CIDR blocks of load balancers whose X-Forwarded-For names the "
        "client (server.relay.addresses); from anyone else the header is ignored",
    )

    @field_validator("trusted_proxies")
    @classmethod
    def _networks(cls, entries: list[str]) -> list[str]:
        networks(entries)  # ValueError on a malformed entry
        return entries

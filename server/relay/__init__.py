"""An nchan-like publish/subscribe relay on aiohttp: its public face.

It carries messages between clients and knows nothing of billiards. `backend` holds the
storage interface (memory or Redis), the transports (`publisher`, `websocket`, `eventsource`,
`longpoll`) speak nchan's wire protocol, and `routes` mounts them on an aiohttp application.

The rest of the server (the game service, the HTTP app, the protocol's feed constants) uses
only what this module exports; the modules behind it are the relay's own.
"""

from server.relay.addresses import client_address
from server.relay.auth import AuthError, TokenAuthority
from server.relay.backend import Backend, BackendConfig
from server.relay.frames import GAP_TYPE
from server.relay.http import bearer_token, relay_of
from server.relay.limits import RateLimiter
from server.relay.memory import MemoryBackend
from server.relay.messages import Published
from server.relay.payloads import JSON, media_type
from server.relay.redis_backend import RedisBackend
from server.relay.relay import Relay
from server.relay.routes import mount_relay
from server.relay.settings import RelaySettings
from server.relay.websocket import CLOSE_GOING_AWAY, DELETED_REASON, META_PROTOCOL

__all__ = [
    "CLOSE_GOING_AWAY",
    "DELETED_REASON",
    "GAP_TYPE",
    "JSON",
    "META_PROTOCOL",
    "AuthError",
    "Backend",
    "BackendConfig",
    "MemoryBackend",
    "Published",
    "RateLimiter",
    "RedisBackend",
    "Relay",
    "RelaySettings",
    "TokenAuthority",
    "bearer_token",
    "client_address",
    "media_type",
    "mount_relay",
    "relay_of",
]

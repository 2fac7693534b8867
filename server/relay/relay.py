"""The relay's shared state and the one publish path used by HTTP and WebSocket publishers.

Checks run cheapest first and before anything is stored, so a refused publish changes nothing:
channel id, token, rate, size, content type, then the body itself.
"""

from __future__ import annotations

import secrets
from collections.abc import Callable
from dataclasses import dataclass

from server.relay.addresses import ConnectionCounts, Network, networks
from server.relay.auth import TokenAuthority, TokenClaims
from server.relay.backend import Backend
from server.relay.errors import RelayError
from server.relay.ids import is_channel_id
from server.relay.limits import RateLimiter
from server.relay.messages import Event, Published
from server.relay.payloads import (
    ACCEPTED_TYPES,
    EventNameError,
    PayloadError,
    check_message,
    media_type,
)
from server.relay.sendqueue import OutputBudget, SendQueue
from server.relay.settings import RelaySettings


def check_channel(channel: str) -> str:
    """`channel` if it is a valid id; RelayError(400) otherwise."""
    if not is_channel_id(channel):
        raise RelayError(400, "channel ids are 1 to 64 letters, digits, '_' or '-'")
    return channel


@dataclass
class Relay:
    """Everything a transport needs: the backend, the settings, tokens and rate limits."""

    backend: Backend
    settings: RelaySettings
    authority: TokenAuthority
    limiter: RateLimiter
    server_limiter: RateLimiter  # server tokens (the game service) have a budget of their own
    output: OutputBudget  # what every connection's send queue draws on
    connections: ConnectionCounts  # subscriber connections per client address
    trusted_proxies: tuple[Network, ...]  # whose X-Forwarded-For names the client

    @classmethod
    def build(cls, backend: Backend, settings: RelaySettings) -> Relay:
        secret = settings.auth_secret or secrets.token_hex(32)
        return cls(
            backend=backend,
            settings=settings,
            authority=TokenAuthority(secret.encode(), settings.public_prefix),
            limiter=RateLimiter(settings.publish_rate, settings.publish_burst),
            server_limiter=RateLimiter(settings.server_publish_rate, settings.server_publish_burst),
            output=OutputBudget(settings.send_budget_bytes),
            connections=ConnectionCounts(settings.max_connections_per_address),
            trusted_proxies=networks(settings.trusted_proxies),
        )

    def send_queue(
        self,
        write_now: Callable[[Event], bool] | None = None,
        on_pending: Callable[[], None] | None = None,
    ) -> SendQueue:
        """A connection's send queue with the configured bounds (see `SendQueue`)."""
        settings = self.settings
        return SendQueue(
            settings.send_queue_length,
            settings.send_queue_bytes,
            self.output,
            write_now,
            on_pending,
        )

    def admit(self, channel: str, token: str | None) -> TokenClaims:
        """Check the right to publish on `channel` and take one from the rate budget."""
        check_channel(channel)
        claims = self.authority.authorize_publish(token, channel)
        limiter = self.server_limiter if claims.server else self.limiter
        wait = limiter.allow(claims.sub)
        if wait > 0:
            raise RelayError(429, f"publishing too fast: retry in {wait:.3f} s")
        return claims

    def validate(self, content_type: str | None, data: bytes, event: str | None = None) -> str:
        """The canonical content type if the message's size, type, event name and body are
        acceptable; RelayError otherwise."""
        limit = self.settings.max_message_bytes
        if len(data) > limit:
            raise RelayError(413, f"message of {len(data)} bytes exceeds the {limit}-byte limit")
        canonical = media_type(content_type)
        if canonical not in ACCEPTED_TYPES:
            accepted = " or ".join(ACCEPTED_TYPES)
            raise RelayError(415, f"unsupported content type {content_type!r}: send {accepted}")
        try:
            check_message(canonical, data, event)
        except EventNameError as error:
            raise RelayError(400, f"X-EventSource-Event: {error}") from None
        except PayloadError as error:
            raise RelayError(400, str(error)) from None
        return canonical

    async def publish(
        self,
        channel: str,
        token: str | None,
        content_type: str | None,
        data: bytes,
        event: str | None = None,
    ) -> Published:
        """Admit, validate and publish one message (503 `Unavailable` if the store is down)."""
        self.admit(channel, token)
        canonical = self.validate(content_type, data, event)
        return await self.backend.publish(channel, data, canonical, event)

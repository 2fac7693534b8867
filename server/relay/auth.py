"""Publish tokens: HMAC-signed, expiring grants to publish on named channels.

The game server issues a token to each player for its game's channels; the relay checks the
signature and the expiry and never trusts anything else a client says. Channels whose id starts
with the public prefix (lobby, leaderboard) are read-only for clients: only a token marked
`server` may publish there. Without a token, nobody publishes anywhere.

Wire form: `base64url(claims JSON) + "." + base64url(HMAC-SHA256(key, first part))`, sent as
`Authorization: Bearer <token>` or, where browsers cannot set headers (WebSocket), `?token=`.
"""

from __future__ import annotations

import base64
import hashlib
import hmac
import time
from collections.abc import Callable

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from server.relay.errors import RelayError
from server.relay.ids import ChannelId


class AuthError(RelayError):
    """A publish refused for its token: 401 (no valid token) or 403 (no right)."""


class TokenClaims(BaseModel):
    """What a token grants: who, which channels, until when."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    sub: str = Field(min_length=1, max_length=128, description="the holder (player or service)")
    channels: list[ChannelId] = Field(max_length=64, description="channels it may publish to")
    exp: int = Field(description="unix time after which it is refused")
    server: bool = Field(default=False, description="may also publish to public channels")


def _b64(data: bytes) -> str:
    return base64.urlsafe_b64encode(data).rstrip(b"=").decode("ascii")


def _unb64(text: str) -> bytes:
    return base64.urlsafe_b64decode(text + "=" * (-len(text) % 4))


class TokenAuthority:
    """Issues and checks tokens with one secret key (shared by every replica)."""

    def __init__(
        self, secret: bytes, public_prefix: str, clock: Callable[[], float] = time.time
    ) -> None:
        self._secret = secret
        self.public_prefix = public_prefix
        self._clock = clock

    def _sign(self, body: str) -> str:
        return _b64(hmac.new(self._secret, body.encode("ascii"), hashlib.sha256).digest())

    def issue(self, sub: str, channels: list[str], ttl: float, *, server: bool = False) -> str:
        """A token for `sub` to publish on `channels` for `ttl` seconds."""
        claims = TokenClaims(
            sub=sub, channels=channels, exp=int(self._clock() + ttl), server=server
        )
        body = _b64(claims.model_dump_json().encode())
        return f"{body}.{self._sign(body)}"

    def verify(self, token: str | None) -> TokenClaims:
        """The claims of a genuine, unexpired token; AuthError(401) otherwise."""
        if not token:
            raise AuthError(401, "publishing needs a token (Authorization: Bearer or ?token=)")
        body, _, signature = token.partition(".")
        if not token.isascii() or not hmac.compare_digest(self._sign(body), signature):
            raise AuthError(401, "token signature is invalid")
        try:
            claims = TokenClaims.model_validate_json(_unb64(body))
        except (ValueError, ValidationError):
            raise AuthError(401, "token claims are malformed") from None
        if claims.exp < self._clock():
            raise AuthError(401, "token has expired")
        return claims

    def authorize_publish(self, token: str | None, channel: str) -> TokenClaims:
        """The claims if `token` may publish to (or delete) `channel`; AuthError otherwise."""
        claims = self.verify(token)
        if channel.startswith(self.public_prefix) and not claims.server:
            raise AuthError(403, f"channel {channel!r} is public: read-only for clients")
        if channel not in claims.channels and not claims.server:
            raise AuthError(403, f"token does not grant publishing to {channel!r}")
        return claims

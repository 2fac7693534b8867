"""Tokens: signed, expiring JWTs (HS256) that name their holder and grant publishing.

The game server issues a token to each player, and the same token identifies the player to the
game API and grants publishing on its game's channels; the relay checks the signature and the
expiry and never trusts anything else a client says. Channels whose id starts with the public
prefix (lobby, leaderboard) are read-only for clients: only a token marked `server` may publish
there. Without a token, nobody publishes anywhere.

Wire form: a compact JWT signed with HMAC-SHA256 (claims `sub`, `channels`, `server`, optional
`name`, `iat`, `exp`), sent as `Authorization: Bearer <token>` or, where browsers cannot set
headers (WebSocket), `?token=`. Only HS256 is accepted: `alg: none` and every other algorithm
are refused, as are forged, expired and malformed tokens.

Checking a token's signature and claims was a fifth of the server's work per publish (PyJWT's
decoding, HMAC, the claims' model), and a holder sends the same token with every publish. So
the claims of up to `TOKENS_KEPT` genuine tokens are kept, keyed by the whole token, the
oldest forgotten first (a token forgotten while still in use is checked once more and kept
anew): a token seen before costs a dictionary look-up, and only the expiry, which depends on
the time, is checked again. A refused token is never kept, so forged ones cannot fill it.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import jwt
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from server.relay.errors import RelayError
from server.relay.ids import ChannelId

ALGORITHM = "HS256"
_REQUIRED = ["sub", "exp", "iat"]
TOKENS_KEPT = 4096  # genuine tokens whose claims are kept (at most a few MB)


class AuthError(RelayError):
    """A publish refused for its token: 401 (no valid token) or 403 (no right)."""


class TokenClaims(BaseModel):
    """What a token grants: who, which channels, until when."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    sub: str = Field(min_length=1, max_length=128, description="the holder (player or service)")
    channels: list[ChannelId] = Field(max_length=64, description="channels it may publish to")
    iat: int = Field(description="unix time it was issued")
    exp: int = Field(description="unix time after which it is refused")
    server: bool = Field(default=False, description="may also publish to public channels")
    name: str | None = Field(
        default=None, min_length=1, max_length=64, description="display name of the holder"
    )


class TokenAuthority:
    """Issues and checks tokens with one secret key (shared by every replica)."""

    def __init__(
        self, secret: bytes, public_prefix: str, clock: Callable[[], float] = time.time
    ) -> None:
        self._secret = secret
        self.public_prefix = public_prefix
        self._clock = clock
        self._known: dict[str, TokenClaims] = {}  # genuine tokens' claims, oldest first

    def issue(
        self,
        sub: str,
        channels: list[str],
        ttl: float,
        *,
        server: bool = False,
        name: str | None = None,
    ) -> str:
        """A token for `sub` (shown as `name`) to publish on `channels` for `ttl` seconds."""
        now = int(self._clock())
        claims = TokenClaims(
            sub=sub,
            channels=channels,
            iat=now,
            exp=int(self._clock() + ttl),
            server=server,
            name=name,
        )
        return jwt.encode(claims.model_dump(exclude_none=True), self._secret, ALGORITHM)

    def verify(self, token: str | None) -> TokenClaims:
        """The claims of a genuine, unexpired token; AuthError(401) otherwise."""
        if not token:
            raise AuthError(401, "publishing needs a token (Authorization: Bearer or ?token=)")
        if not token.isascii():  # a token is ASCII; PyJWT would fail to encode surrogates
            raise AuthError(401, "token is malformed")
        claims = self._known.get(token)
        if claims is None:
            claims = self._claims(token)
            if len(self._known) >= TOKENS_KEPT:
                del self._known[next(iter(self._known))]
            self._known[token] = claims
        if claims.exp < self._clock():
            raise AuthError(401, "token has expired")
        return claims

    def _claims(self, token: str) -> TokenClaims:
        """The claims of a token signed with this authority's key, whatever its expiry."""
        try:
            payload = jwt.decode(
                token,
                self._secret,
                algorithms=[ALGORITHM],
                # Expiry is checked below against the injectable clock, not PyJWT's.
                options={"require": _REQUIRED, "verify_exp": False, "verify_iat": False},
            )
        except jwt.InvalidSignatureError:
            raise AuthError(401, "token signature is invalid") from None
        except jwt.InvalidAlgorithmError:
            raise AuthError(401, f"token algorithm is not {ALGORITHM}") from None
        except jwt.InvalidTokenError:
            raise AuthError(401, "token is malformed") from None
        try:
            claims = TokenClaims.model_validate(payload)
        except ValidationError:
            raise AuthError(401, "token claims are malformed") from None
        return claims

    def authorize_publish(self, token: str | None, channel: str) -> TokenClaims:
        """The claims if `token` may publish to (or delete) `channel`; AuthError otherwise."""
        claims = self.verify(token)
        if channel.startswith(self.public_prefix) and not claims.server:
            raise AuthError(403, f"channel {channel!r} is public: read-only for clients")
        if channel not in claims.channels and not claims.server:
            raise AuthError(403, f"token does not grant publishing to {channel!r}")
        return claims

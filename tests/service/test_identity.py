"""Guest identity: a remembered token is still checked for expiry, a forged one never passes."""

from __future__ import annotations

import pytest

from server.game.identity import TOKEN_TTL, Identity
from server.protocol.errors import ErrorCode, ServiceError
from server.relay.auth import TokenAuthority
from server.storage import Storage


class Clock:
    def __init__(self, now: float) -> None:
        self.now = now

    def __call__(self) -> float:
        return self.now


async def test_a_remembered_token_expires_on_time(storage: Storage) -> None:
    clock = Clock(1_000_000.0)
    identity = Identity(TokenAuthority(b"k" * 32, "public-", clock), storage, clock)
    issued = await identity.register("Ada")
    assert await identity.authenticate(issued.token) == issued.player
    assert await identity.authenticate(issued.token) == issued.player  # remembered now
    clock.now += TOKEN_TTL + 1
    with pytest.raises(ServiceError) as refused:
        await identity.authenticate(issued.token)
    assert refused.value.code is ErrorCode.UNAUTHORIZED


async def test_a_forged_token_is_refused_after_the_genuine_one_was_seen(storage: Storage) -> None:
    identity = Identity(TokenAuthority(b"k" * 32, "public-"), storage)
    issued = await identity.register("Ada")
    await identity.authenticate(issued.token)
    head, payload, signature = issued.token.split(".")
    forged = ".".join((head, payload, signature[::-1]))
    for token in (forged, issued.token + "x", None, ""):
        with pytest.raises(ServiceError) as refused:
            await identity.authenticate(token)
        assert refused.value.code is ErrorCode.UNAUTHORIZED

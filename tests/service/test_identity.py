"""Guest identity: a remembered token is still checked for expiry, a forged one never passes."""

from __future__ import annotations

import time

import pytest
from aiohttp.test_utils import TestClient

from server.game.identity import GUEST_KEPT, ONLINE, RECHECK, TOKEN_TTL, Identity, name_key
from server.game.service import NAMES_PER_ADDRESS
from server.protocol.errors import ErrorCode, ServiceError
from server.relay.auth import TokenAuthority
from server.storage import Storage
from tests.service.conftest import register, service_of


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


@pytest.mark.parametrize("lookalike", ["AIice", "A1ice", "Alice.", "alice", "A-lice", "ALICE"])
async def test_a_name_that_reads_as_an_online_one_is_taken(
    storage: Storage, lookalike: str
) -> None:
    """Before: only case was folded, so `AIice` could pose as `Alice` while she was online."""
    identity = Identity(TokenAuthority(b"k" * 32, "public-"), storage)
    await identity.register("Alice")
    with pytest.raises(ServiceError) as refused:
        await identity.register(lookalike)
    assert refused.value.code is ErrorCode.NAME_TAKEN


@pytest.mark.parametrize(("one", "other"), [("rn", "m"), ("vvill", "will"), ("O8", "ob")])
def test_skeletons_fold_what_reads_the_same(one: str, other: str) -> None:
    assert name_key(one) == name_key(other)


def test_names_that_read_differently_keep_apart() -> None:
    assert len({name_key(n) for n in ("Alice", "Alicia", "Bob", "Bab", "Ada", "Eve")}) == 6


async def test_one_address_holds_a_bounded_number_of_names(server: TestClient) -> None:
    """Before: 200 at once and 5 more per second, each kept 5 minutes (some 1,500 names)."""
    statuses = [
        (await server.post("/api/players", json={"name": f"flood {n}"})).status
        for n in range(NAMES_PER_ADDRESS + 1)
    ]
    assert statuses == [201] * NAMES_PER_ADDRESS + [429]


async def test_a_remembered_token_of_an_expired_guest_stops_working(storage: Storage) -> None:
    """Unused guests are deleted (invariant 15); a token remembered before must not outlive
    its player by more than RECHECK seconds."""
    clock = Clock(1_000_000.0)
    identity = Identity(TokenAuthority(b"k" * 32, "public-", clock), storage, clock)
    issued = await identity.register("Ada")
    assert await identity.authenticate(issued.token) == issued.player
    assert await storage.expire_players(time.time() + GUEST_KEPT + 1, 10) == [issued.player.id]
    assert await identity.authenticate(issued.token) == issued.player  # remembered a while
    clock.now += RECHECK + 1
    with pytest.raises(ServiceError) as refused:
        await identity.authenticate(issued.token)
    assert refused.value.code is ErrorCode.UNAUTHORIZED


@pytest.mark.parametrize("poll", ["/api/challenges", "/api/quick"])
async def test_a_player_on_the_lobby_page_keeps_their_name(server: TestClient, poll: str) -> None:
    """The lobby page polls its challenges (and a waiting one its quick match), and that keeps
    its player's name: before, only a seated player's heartbeat did, so a player who stayed on
    the lobby page lost the name after 5 minutes to whoever registered it then."""
    ada = await register(server, "Ada")
    storage = service_of(server).storage
    now = time.time()
    await storage.claim_name(name_key("Ada"), ada.info["id"], now + 1.0, now)  # about to lapse
    await ada.call("GET", poll, expect=200)
    holder = await storage.name_holder(name_key("Ada"))
    assert holder is not None and holder[0] == ada.info["id"] and holder[1] > now + ONLINE - 60


@pytest.mark.parametrize("name", ["..", ".", "_-_", "- -"])
async def test_a_name_of_separators_alone_is_refused(server: TestClient, name: str) -> None:
    """Before, `..` was a name: its profile link opened the home page, and since every name of
    separators alone folds to the same empty skeleton, the first one took all the others."""
    response = await server.post("/api/players", json={"name": name})
    assert response.status == 400 and (await response.json())["code"] == "bad_request"
    await register(server, "._Ada")  # separators beside a letter are a name

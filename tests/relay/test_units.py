"""Pieces with no I/O: cursors, the rate limiter, tokens, and the memory backend's clock."""

from __future__ import annotations

import json

import jwt
import pytest

from server.relay.auth import AuthError, TokenAuthority
from server.relay.backend import BackendConfig
from server.relay.cursor import Cursor
from server.relay.limits import RateLimiter
from server.relay.memory import MemoryBackend
from server.relay.payloads import JSON, MAX_DEPTH, PayloadError, decode


class FakeClock:
    def __init__(self, now: float = 1_700_000_000.0) -> None:
        self.now = now

    def __call__(self) -> float:
        return self.now


def test_cursor_round_trip_over_several_channels() -> None:
    cursor = Cursor(["a", "b"])
    assert cursor.advance("a", "10:0") == "a/10:0"
    assert cursor.advance("b", "10:1") == "b/10:1,a/10:0"
    resumed = Cursor.parse(["a", "b"], cursor.text("a"))
    assert resumed.positions == {"a": "10:0", "b": "10:1"}


@pytest.mark.parametrize("text", ["c/10:0", "a/10", "a:10:0", "a/x:1"])
def test_cursor_rejects_entries_it_cannot_resume(text: str) -> None:
    with pytest.raises(ValueError):
        Cursor.parse(["a", "b"], text)


def test_rate_limiter_refills_at_its_rate() -> None:
    clock = FakeClock(0.0)
    limiter = RateLimiter(rate=2.0, burst=3, clock=clock)
    assert [limiter.allow("p") for _ in range(3)] == [0.0, 0.0, 0.0]
    assert limiter.allow("p") == pytest.approx(0.5)
    assert limiter.allow("q") == 0.0  # budgets are per publisher
    clock.now = 0.5
    assert limiter.allow("p") == 0.0
    assert limiter.allow("p") > 0.0


def test_tokens_expire_and_cannot_be_altered() -> None:
    clock = FakeClock()
    authority = TokenAuthority(b"k" * 32, "public-", clock=clock)
    token = authority.issue("alice", ["g1"], ttl=60)
    assert authority.authorize_publish(token, "g1").sub == "alice"
    with pytest.raises(AuthError) as refused:
        authority.authorize_publish(token, "g2")
    assert refused.value.status == 403
    # Verified once, its claims are kept: an altered copy is still checked in full.
    header, _, signature = token.split(".")
    claims = jwt.decode(token, options={"verify_signature": False})
    claims["channels"] = ["g1", "g2"]
    altered = jwt.encode(claims, b"x" * 32, "HS256").split(".")[1]
    for _ in range(2):
        with pytest.raises(AuthError) as forged:
            authority.verify(f"{header}.{altered}.{signature}")
        assert forged.value.status == 401
    clock.now += 61  # kept or not, an expired token is refused
    with pytest.raises(AuthError) as expired:
        authority.verify(token)
    assert expired.value.status == 401
    assert "expired" in expired.value.reason


async def test_memory_ids_stay_increasing_when_the_clock_steps_back() -> None:
    clock = FakeClock(1000.5)
    backend = MemoryBackend(BackendConfig(), clock=clock)
    first = await backend.publish("c", b"1", "application/json")
    clock.now = 990.0
    second = await backend.publish("c", b"2", "application/json")
    clock.now = 1001.0
    third = await backend.publish("c", b"3", "application/json")
    assert [first.message.id, second.message.id, third.message.id] == [
        "1000:0",
        "1000:1",
        "1001:0",
    ]


async def test_memory_ttl_expiry_is_a_gap_only_for_what_was_missed() -> None:
    clock = FakeClock(1000.0)
    backend = MemoryBackend(BackendConfig(message_ttl=10), clock=clock)
    a = (await backend.publish("c", b"1", "application/json")).message
    clock.now = 1005.0
    b = (await backend.publish("c", b"2", "application/json")).message
    clock.now = 1012.0  # a has expired, b has not
    backlog = await backend.read_since("c", a.id, 10)
    assert (backlog.gap, [m.id for m in backlog.messages]) == (False, [b.id])
    backlog = await backend.read_since("c", "999:0", 10)
    assert (backlog.gap, [m.id for m in backlog.messages]) == (True, [b.id])
    clock.now = 1020.0
    assert await backend.info("c") is None  # nothing buffered, nobody subscribed


def test_tokens_are_hs256_jwts_carrying_a_display_name() -> None:
    clock = FakeClock()
    authority = TokenAuthority(b"k" * 32, "public-", clock=clock)
    token = authority.issue("player-7", ["t1", "t2"], ttl=60, name="Ronnie")
    assert jwt.get_unverified_header(token)["alg"] == "HS256"
    claims = authority.verify(token)
    assert (claims.sub, claims.name, claims.channels) == ("player-7", "Ronnie", ["t1", "t2"])
    assert (claims.iat, claims.exp) == (int(clock.now), int(clock.now) + 60)
    assert authority.verify(authority.issue("svc", [], 60, server=True)).name is None
    unsigned = jwt.encode({"sub": "x", "channels": ["t1"], "iat": 1, "exp": 2**40}, None, "none")
    with pytest.raises(AuthError) as refused:
        authority.verify(unsigned)
    assert refused.value.status == 401


ACCEPTED_JSON = [
    b"[" + b"[1]," * 200 + b"[]]",  # many brackets, two levels: the count alone would refuse
    b'["' + b"[" * 200 + b'"]',  # brackets inside a string are not nesting
    b"[" * MAX_DEPTH + b"]" * MAX_DEPTH,
    b'{"e": "1e999", "digits": "' + b"9" * 120 + b'"}',  # huge-looking text in strings only
    b"[1" + b"0" * 400 + b"]",  # a large integer stays an integer
    b"[1.5e308, -2e-400]",  # the largest finite floats and an underflow to 0.0
]
REFUSED_JSON = [
    (b"[" * (MAX_DEPTH + 1) + b"]" * (MAX_DEPTH + 1), "deeper than"),
    (b'[{"a": ' * 40 + b"1" + b"}]" * 40, "deeper than"),  # arrays and maps count alike
    (b"[1" + b"0" * 400 + b".0]", "infinity"),  # no exponent, yet too large a float
    (b'{"a": [2e308]}', "infinity"),
    (b"[Infinity]", "Infinity"),
    (b"[NaN]", "NaN"),
    (b"[1,]", "malformed JSON"),
    (b"[" * 70, "malformed JSON"),  # unbalanced: not nesting the parser can reach
    (b'["\\ud800"]', "malformed JSON"),  # a lone surrogate: no text a client could decode
    (b'["\xed\xa0\x80"]', "malformed JSON"),  # the same, encoded as (invalid) UTF-8
    (b"[1] [2]", "malformed JSON"),  # trailing text
]


@pytest.mark.parametrize("body", ACCEPTED_JSON)
def test_json_bodies_within_the_rules_are_accepted(body: bytes) -> None:
    assert decode(body, JSON) == json.loads(body)


@pytest.mark.parametrize(("body", "says"), REFUSED_JSON)
def test_json_bodies_outside_the_rules_are_refused_saying_why(body: bytes, says: str) -> None:
    with pytest.raises(PayloadError, match=says):
        decode(body, JSON)

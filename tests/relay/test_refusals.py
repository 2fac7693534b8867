"""Bad publishes get a clear error and change nothing: size, format, rate, tokens, public."""

from __future__ import annotations

import time

import jwt
import msgpack
import pytest

from server.relay.auth import TokenAuthority
from tests.relay.conftest import SECRET, RelayHarness, StartRelay


async def _post(
    relay: RelayHarness, body: bytes, content_type: str, channel: str = "game1", **headers: str
) -> tuple[int, str]:
    headers = {"Content-Type": content_type, **relay.auth(channel), **headers}
    response = await relay.client.post(f"/pub/{channel}", data=body, headers=headers)
    return response.status, await response.text()


@pytest.mark.parametrize(
    ("body", "content_type", "status", "says"),
    [
        (b'{"a": 1', "application/json", 400, "malformed JSON"),
        (b'{"a": NaN}', "application/json", 400, "NaN"),
        (b"[1e999]", "application/json", 400, "infinity"),
        (b"\xff\xfe", "application/json", 400, "malformed JSON"),
        (b"\xc1", "application/msgpack", 400, "malformed msgpack"),
        (msgpack.packb([1]) + b"\x01", "application/msgpack", 400, "extra data"),
        (msgpack.packb(float("inf")), "application/msgpack", 400, "infinite"),
        (msgpack.packb(b"raw"), "application/msgpack", 400, "bytes"),
        (b"hello", "text/plain", 415, "unsupported content type"),
    ],
)
async def test_malformed_bodies_are_refused_and_change_nothing(
    relay: RelayHarness, body: bytes, content_type: str, status: int, says: str
) -> None:
    await relay.publish_ok("game1", "before")
    before = await relay.info("game1")
    got_status, error = await _post(relay, body, content_type)
    assert got_status == status
    assert says in error
    assert await relay.info("game1") == before


async def test_oversized_message_is_refused_and_changes_nothing(
    start_relay: StartRelay,
) -> None:
    relay = await start_relay(max_message_bytes=1000)
    fits = b'"' + b"x" * 998 + b'"'
    assert (await _post(relay, fits, "application/json"))[0] == 202
    before = await relay.info("game1")
    status, error = await _post(relay, b'"' + b"x" * 999 + b'"', "application/json")
    assert status == 413
    assert "1000" in error
    assert await relay.info("game1") == before


async def test_default_size_limit_is_64_kib(relay: RelayHarness) -> None:
    big = b'"' + b"x" * (64 * 1024 - 1) + b'"'
    status, _ = await _post(relay, big, "application/json")
    assert status == 413
    assert await relay.info("game1") is None


async def test_invalid_channel_id_is_400(relay: RelayHarness) -> None:
    response = await relay.client.post(
        "/pub/" + "x" * 65, data=b"1", headers={"Content-Type": "application/json"}
    )
    assert response.status == 400
    response = await relay.client.get("/pub/bad.id")
    assert response.status == 400


async def test_over_rate_publishes_get_429_and_change_nothing(start_relay: StartRelay) -> None:
    relay = await start_relay(publish_rate=0.001, publish_burst=3)
    for n in range(3):
        assert (await relay.publish("game1", n)).status == 202
    before = await relay.info("game1")
    response = await relay.publish("game1", "one too many")
    assert response.status == 429
    assert "too fast" in (await response.json())["error"]
    assert await relay.info("game1") == before


async def test_publish_without_token_is_401(relay: RelayHarness) -> None:
    response = await relay.client.post(
        "/pub/game1", data=b"1", headers={"Content-Type": "application/json"}
    )
    assert response.status == 401
    assert response.headers["WWW-Authenticate"] == "Bearer"
    assert await relay.info("game1") is None


def _forgeries(relay: RelayHarness) -> dict[str, str]:
    """Tokens a hostile client could make from a genuine one for another channel."""
    header, claims, signature = relay.token("game2").split(".")
    wanted = relay.token("game1").split(".")[1]
    now = int(time.time())
    granted = {"sub": "x", "channels": ["game1"], "iat": now, "exp": now + 60}
    secret = SECRET.encode()
    return {
        "claims swapped, signature kept": f"{header}.{wanted}.{signature}",
        "signature altered": f"{header}.{claims}.{signature[:-4]}AAAA",
        "alg none": jwt.encode(granted, None, algorithm="none"),
        "alg HS512 with the same key": jwt.encode(granted, secret, algorithm="HS512"),
        "no exp": jwt.encode({**granted, "exp": None}, secret, algorithm="HS256"),
        "no iat": jwt.encode({k: v for k, v in granted.items() if k != "iat"}, secret),
        "channels not a list": jwt.encode({**granted, "channels": "game1"}, secret),
        "garbage": "garbage",
        "two parts": f"{header}.{claims}",
        "not ascii": "é.é.é",
    }


async def test_forged_or_malformed_token_is_401(relay: RelayHarness) -> None:
    for what, token in _forgeries(relay).items():
        response = await relay.publish("game1", 1, token=token)
        assert response.status == 401, what
        assert (await response.json())["status"] == 401
    assert await relay.info("game1") is None


async def test_token_signed_with_another_secret_is_401(relay: RelayHarness) -> None:
    other = TokenAuthority(b"another-secret-entirely-0123456789", "public-")
    response = await relay.publish("game1", 1, token=other.issue("x", ["game1"], 60))
    assert response.status == 401
    assert "signature" in (await response.json())["error"]


async def test_expired_token_is_401(relay: RelayHarness) -> None:
    expired = relay.relay.authority.issue("tester", ["game1"], ttl=-5)
    response = await relay.publish("game1", 1, token=expired)
    assert response.status == 401
    assert "expired" in (await response.json())["error"]
    assert await relay.info("game1") is None


async def test_token_for_another_channel_is_403(relay: RelayHarness) -> None:
    response = await relay.publish("game1", 1, token=relay.token("game2"))
    assert response.status == 403
    assert await relay.info("game1") is None


async def test_public_channels_are_read_only_for_clients(relay: RelayHarness) -> None:
    client_token = relay.token("public-lobby")  # even a token naming it
    response = await relay.publish("public-lobby", {"hi": 1}, token=client_token)
    assert response.status == 403
    assert "read-only" in (await response.json())["error"]
    assert await relay.info("public-lobby") is None
    server_token = relay.token(server=True)
    response = await relay.publish("public-lobby", {"table": 3}, token=server_token)
    assert response.status == 202
    ws = await relay.ws("/sub/public-lobby")  # anyone may read it
    await ws.close()

"""Bad bytes on the wire get a 4xx and one log line: an Authorization header that is not
ASCII (before: 500, `UnicodeEncodeError`), a request that is not HTTP (before: a traceback),
and the game API reads its token from the header alone (before: also `?token=`, which puts
tokens into access logs and browser history)."""

from __future__ import annotations

import asyncio
import logging

import pytest
from aiohttp.test_utils import TestClient

from tests.service.conftest import register


async def _raw(server: TestClient, request: bytes) -> bytes:
    """The server's whole answer to `request` sent as raw bytes (the connection then closed)."""
    reader, writer = await asyncio.open_connection(server.host, server.port)
    writer.write(request)
    await writer.drain()
    answer = await asyncio.wait_for(reader.read(65536), 30)
    writer.close()
    return answer


@pytest.mark.parametrize("value", [b"Bearer \xff\xfe", "Bearer é".encode(), b"\xc3\xa9"])
@pytest.mark.parametrize("path", [b"POST /pub/table-x", b"GET /api/me", b"POST /api/tables"])
async def test_an_authorization_header_not_ascii_is_a_4xx(
    server: TestClient, value: bytes, path: bytes
) -> None:
    request = (
        path + b" HTTP/1.1\r\nHost: x\r\nConnection: close\r\nContent-Type: application/json\r\n"
        b"Authorization: " + value + b"\r\nContent-Length: 2\r\n\r\n{}"
    )
    status = int((await _raw(server, request)).split(b" ", 2)[1])
    assert 400 <= status < 500


@pytest.mark.parametrize(
    "request_bytes",
    [b"GARBAGE\x00 / HTTP/9\r\n\r\n", b"GET / HTTP/1.1\r\nNo colon here\r\n\r\n"],
)
async def test_a_malformed_request_is_400_and_one_log_line(
    server: TestClient, caplog: pytest.LogCaptureFixture, request_bytes: bytes
) -> None:
    with caplog.at_level(logging.DEBUG):
        answer = await _raw(server, request_bytes)
    assert answer.split(b" ", 2)[1] == b"400"
    logged = [r for r in caplog.records if r.name == "aiohttp.server"]
    assert len(logged) == 1 and logged[0].exc_info is None, caplog.text
    assert "\n" not in logged[0].getMessage() and "bad request" in logged[0].getMessage()


async def test_a_body_that_stops_coming_is_refused_at_its_deadline(
    server: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A client that announces a body and sends part of it does not hold its request open:
    `408 request_timeout` once BODY_SECONDS have passed, and nothing was created."""
    monkeypatch.setattr("server.http.api.BODY_SECONDS", 0.3)
    ada = await register(server, "Ada")
    request = (
        b"POST /api/tables HTTP/1.1\r\nHost: x\r\nConnection: close\r\n"
        b"Content-Type: application/json\r\nAuthorization: "
        + ada.auth["Authorization"].encode()
        + b'\r\nContent-Length: 1000\r\n\r\n{"game":'
    )
    answer = await _raw(server, request)
    assert answer.split(b" ", 2)[1] == b"408"
    assert b'"code":"request_timeout"' in answer
    listed = await (await server.get("/api/tables")).json()
    assert listed["tables"] == []


async def test_the_game_api_takes_its_token_from_the_header_alone(server: TestClient) -> None:
    ada = await register(server, "Ada")
    assert (await server.get("/api/me", headers=ada.auth)).status == 200
    by_query = await server.get(f"/api/me?token={ada.token}")
    assert by_query.status == 401
    assert "Authorization" in (await by_query.json())["reason"]


@pytest.mark.parametrize(
    ("method", "path", "status", "allow"),
    [
        ("GET", "/api/nothing-here", 404, None),
        ("GET", "/api/tables/x/y/z%0Az", 404, None),
        ("DELETE", "/api/tables", 405, "GET,HEAD,POST"),
        ("PUT", "/api/me", 405, "GET,HEAD"),
    ],
)
async def test_a_request_no_api_route_takes_is_refused_as_json(
    server: TestClient, method: str, path: str, status: int, allow: str | None
) -> None:
    """Unknown paths and methods under /api/ get the API's JSON refusal, with `Allow` on a
    405; elsewhere the server's own 404 stays (the relay and the pages pass through no
    handling of the API's)."""
    answer = await server.request(method, path)
    assert answer.status == status and answer.headers.get("Allow") == allow
    assert (await answer.json())["code"] == ("not_found" if status == 404 else "bad_request")
    elsewhere = await server.get("/nothing-here")
    assert elsewhere.status == 404 and elsewhere.content_type != "application/json"


@pytest.mark.parametrize("path", ["/api/tables", "/api/bots", "/api/real-shots"])
async def test_every_api_read_answers_head_as_its_get(server: TestClient, path: str) -> None:
    """HEAD is GET without the body (HTTP asks it of every GET): same status and type."""
    got, head = await server.get(path), await server.head(path)
    assert (
        (head.status, head.content_type)
        == (got.status, got.content_type)
        == (
            200,
            "application/json",
        )
    )
    assert await head.read() == b""

"""Small HTTP helpers shared by the publisher and subscriber endpoints."""

from __future__ import annotations

from aiohttp import WSMessage, WSMsgType, web
from pydantic import BaseModel, ConfigDict

from server.relay.errors import RelayError, Unavailable
from server.relay.payloads import JSON, MSGPACK
from server.relay.relay import Relay

RELAY_KEY = web.AppKey("relay", Relay)


class ErrorBody(BaseModel):
    """The JSON body of every refusal."""

    model_config = ConfigDict(frozen=True)

    error: str
    status: int


def relay_of(request: web.Request) -> Relay:
    return request.app[RELAY_KEY]


def bearer_token(request: web.Request, *, query: bool = True) -> str | None:
    """The token from `Authorization: Bearer ...` or, with `query` and failing that, `?token=`.

    The relay reads `?token=` because a browser's WebSocket cannot send headers, and a
    WebSocket publishes with the token of its URL; the game API passes `query=False` (a token
    in a URL ends up in access logs and browser history). A header of bytes that are not
    ASCII is returned as it came (aiohttp keeps them as surrogates): `TokenAuthority.verify`
    refuses it as malformed (401), as any other token it cannot read."""
    header = request.headers.get("Authorization", "")
    scheme, _, value = header.partition(" ")
    if scheme.lower() == "bearer" and value.strip():
        return value.strip()
    return request.query.get("token") if query else None


def limit_socket_buffer(request: web.Request, high: int) -> None:
    """Make the connection's writes wait once `high` bytes are buffered in the process.

    asyncio's default of 64 KiB, plus the message being written, is per connection: with
    thousands of subscribers that never read, it alone would add up to hundreds of MB.
    """
    if request.transport is not None:
        request.transport.set_write_buffer_limits(high=high)


def error_body(error: RelayError) -> str:
    """The JSON that says why a request was refused."""
    return ErrorBody(error=error.reason, status=error.status).model_dump_json()


def error_response(error: RelayError) -> web.Response:
    """A refusal: the status and a JSON body that says why."""
    headers = {}
    if error.status == 401:
        headers["WWW-Authenticate"] = "Bearer"
    if isinstance(error, Unavailable):
        headers["Retry-After"] = str(error.retry_after)
    return web.Response(
        text=error_body(error),
        status=error.status,
        headers=headers,
        content_type="application/json",
    )


def frame_message(frame: WSMessage) -> tuple[str, bytes] | None:
    """(content type, body) a client's WebSocket frame publishes: text is JSON, binary msgpack.

    None for control frames, which publish nothing.
    """
    if frame.type == WSMsgType.TEXT:
        return JSON, frame.data.encode()
    if frame.type == WSMsgType.BINARY:
        return MSGPACK, frame.data
    return None


PREFLIGHT_HEADERS = {
    "Access-Control-Allow-Headers": "If-None-Match, If-Modified-Since, Content-Type, "
    "Cache-Control, X-EventSource-Event, Last-Event-ID",
    "Access-Control-Allow-Methods": "GET",
    "Allow": "GET",
}


def check_origin(request: web.Request, allowed: list[str]) -> None:
    """RelayError(403) for a page whose origin may not subscribe (no Origin: anyone may)."""
    origin = request.headers.get("Origin")
    if origin is not None and "*" not in allowed and origin not in allowed:
        raise RelayError(403, f"origin {origin!r} may not subscribe here")


async def add_cors_headers(request: web.Request, response: web.StreamResponse) -> None:
    """Every answer to a subscriber request with an `Origin` names that origin, as nchan's do,
    so that a page on another origin can read it (refused origins get 403 before this)."""
    origin = request.headers.get("Origin")
    if origin is None:
        return
    response.headers["Access-Control-Allow-Origin"] = origin
    response.headers["Access-Control-Allow-Credentials"] = "true"

"""Small HTTP helpers shared by the publisher and subscriber endpoints."""

from __future__ import annotations

from aiohttp import WSMessage, WSMsgType, web
from pydantic import BaseModel, ConfigDict

from server.relay.errors import RelayError
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


def bearer_token(request: web.Request) -> str | None:
    """The token from `Authorization: Bearer ...` or, failing that, `?token=`."""
    header = request.headers.get("Authorization", "")
    scheme, _, value = header.partition(" ")
    if scheme.lower() == "bearer" and value.strip():
        return value.strip()
    return request.query.get("token")


def error_body(error: RelayError) -> str:
    """The JSON that says why a request was refused."""
    return ErrorBody(error=error.reason, status=error.status).model_dump_json()


def error_response(error: RelayError) -> web.Response:
    """A refusal: the status and a JSON body that says why."""
    headers = {}
    if error.status == 401:
        headers["WWW-Authenticate"] = "Bearer"
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

"""The OpenAPI description of the relay's HTTP endpoints, its schemas taken from the models.

WebSocket and EventSource are described as what they are on HTTP (an upgrade, a text stream);
their framing is documented in the README (The message relay). `/sub/{channels}` is described
as the long-poll a plain HTTP client gets: one channel and a plain message id. WebSocket and
EventSource subscribers may also name several channels and resume from a cursor (README); that
is not plain HTTP, and describing it here would make the long-poll's answers to it (400) look
like refusals of valid requests. schemathesis checks this description against the server
(tests/relay/test_openapi.py).
"""

from __future__ import annotations

from functools import cache
from typing import Any

from pydantic.json_schema import models_json_schema

from server.relay.frames import CLOSED_TYPE, GAP_TYPE
from server.relay.http import ErrorBody
from server.relay.ids import CHANNEL_PATTERN, MESSAGE_ID_PATTERN
from server.relay.messages import CHANNEL_INFO, ChannelClosed, Gap
from server.relay.payloads import JSON, MSGPACK

_REF = "#/components/schemas/{model}"


def _ref(name: str) -> dict[str, str]:
    return {"$ref": _REF.format(model=name)}


def _error(description: str) -> dict[str, Any]:
    return {
        "description": description,
        "content": {"application/json": {"schema": _ref("ErrorBody")}},
    }


def _info(description: str) -> dict[str, Any]:
    return {
        "description": description,
        "content": {
            "application/json": {"schema": _ref("ChannelInfo")},
            "text/plain": {"schema": {"type": "string"}},
        },
    }


_CHANNEL = {
    "name": "channel",
    "in": "path",
    "required": True,
    "schema": {"type": "string", "pattern": CHANNEL_PATTERN},
}
_TOKEN = {"bearer": []}
_UNAVAILABLE = {"503": _error("the message store is unreachable: retry after Retry-After s")}
_BAD_CHANNEL = {"400": _error("malformed channel id")}
_REFUSALS = {
    "400": _error("malformed channel id or body"),
    "401": _error("missing, forged or expired token"),
    "403": _error("token grants no publishing here (public channels are read-only)"),
    "429": _error("publishing too fast"),
}


@cache
def openapi_document() -> dict[str, Any]:
    _, schemas = models_json_schema(
        [(model, "serialization") for model in (ErrorBody, Gap, ChannelClosed)],
        ref_template=_REF,
    )
    schemas["$defs"]["ChannelInfo"] = CHANNEL_INFO.json_schema(
        mode="serialization", ref_template=_REF
    )
    body_types = {"application/json": {"schema": {}}, "application/msgpack": {"schema": {}}}
    return {
        "openapi": "3.1.0",
        "info": {"title": "billiards relay", "version": "1.0.0"},
        "components": {
            "schemas": schemas["$defs"],
            "securitySchemes": {"bearer": {"type": "http", "scheme": "bearer"}},
        },
        "paths": {
            "/pub/{channel}": {
                "parameters": [_CHANNEL],
                "post": {
                    "summary": "Publish a message (JSON or msgpack body)",
                    "security": [_TOKEN],
                    "requestBody": {"required": True, "content": body_types},
                    "responses": {
                        "201": _info("published; subscribers were present"),
                        "202": _info("published; no subscribers were present"),
                        **_REFUSALS,
                        "413": _error("body larger than the configured limit"),
                        "415": _error("content type is neither JSON nor msgpack"),
                        **_UNAVAILABLE,
                    },
                },
                "get": {
                    "summary": "Channel info (JSON with Accept: application/json); with a "
                    "WebSocket upgrade, a publisher socket answering each frame with the info",
                    "responses": {
                        "101": {"description": "WebSocket publisher"},
                        "200": _info("channel info"),
                        **_BAD_CHANNEL,
                        "404": _error("no such channel"),
                        **_UNAVAILABLE,
                    },
                },
                "delete": {
                    "summary": "Delete a channel and close its subscribers",
                    "security": [_TOKEN],
                    "responses": {
                        "200": _info("deleted; its last info"),
                        "404": _error("no such channel"),
                        **_REFUSALS,
                        **_UNAVAILABLE,
                    },
                },
            },
            "/sub/{channels}": {
                "get": {
                    "summary": "Subscribe: WebSocket upgrade, EventSource or long-poll",
                    "parameters": [
                        {**_CHANNEL, "name": "channels"},
                        {
                            "name": "last_event_id",
                            "in": "query",
                            "description": "resume after this message id (empty: from the "
                            "start, per first_message)",
                            "schema": {"type": "string", "pattern": f"^$|{MESSAGE_ID_PATTERN}"},
                        },
                        {"name": "Last-Event-ID", "in": "header", "schema": {"type": "string"}},
                        {"name": "If-Modified-Since", "in": "header", "schema": {"type": "string"}},
                        {"name": "If-None-Match", "in": "header", "schema": {"type": "string"}},
                    ],
                    "responses": {
                        "101": {"description": "WebSocket (subprotocol ws+meta.nchan optional)"},
                        "200": {
                            "description": "long-poll: one message (Last-Modified, Etag, "
                            "X-Relay-Gap headers); EventSource: text/event-stream",
                            "content": {
                                "text/event-stream": {"schema": {"type": "string"}},
                                JSON: {"schema": {}},
                                MSGPACK: {"schema": {}},
                                GAP_TYPE: {"schema": _ref("Gap")},
                                CLOSED_TYPE: {"schema": _ref("ChannelClosed")},
                            },
                        },
                        "400": _error("malformed channel list or resume id"),
                        "403": _error("the request's Origin may not subscribe"),
                        "408": _error("long-poll: no message within the timeout"),
                        "410": _error("long-poll: the channel was deleted"),
                        "429": _error("the client's address holds its cap of connections"),
                        **_UNAVAILABLE,
                    },
                },
                "options": {
                    "summary": "CORS preflight of a subscriber request from another origin",
                    "parameters": [{**_CHANNEL, "name": "channels"}],
                    "responses": {
                        "200": {"description": "the allowed methods and headers"},
                        **_BAD_CHANNEL,
                        "403": _error("the request's Origin may not subscribe"),
                    },
                },
            },
        },
    }

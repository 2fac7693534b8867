"""The OpenAPI description of the relay's HTTP endpoints, its schemas taken from the models.

WebSocket and EventSource are described as what they are on HTTP (an upgrade, a text stream);
their framing is documented in the README (The message relay).
"""

from __future__ import annotations

from functools import cache
from typing import Any

from pydantic.json_schema import models_json_schema

from server.relay.frames import CLOSED_TYPE, GAP_TYPE
from server.relay.http import ErrorBody
from server.relay.ids import CHANNEL_PATTERN
from server.relay.messages import ChannelClosed, ChannelInfo, Gap

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
_REFUSALS = {
    "400": _error("malformed channel id or body"),
    "401": _error("missing, forged or expired token"),
    "403": _error("token grants no publishing here (public channels are read-only)"),
    "429": _error("publishing too fast"),
}


@cache
def openapi_document() -> dict[str, Any]:
    _, schemas = models_json_schema(
        [(model, "serialization") for model in (ChannelInfo, ErrorBody, Gap, ChannelClosed)],
        ref_template=_REF,
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
                    },
                },
                "get": {
                    "summary": "Channel info (JSON with Accept: application/json); with a "
                    "WebSocket upgrade, a publisher socket answering each frame with the info",
                    "responses": {
                        "101": {"description": "WebSocket publisher"},
                        "200": _info("channel info"),
                        "404": _error("no such channel"),
                    },
                },
                "delete": {
                    "summary": "Delete a channel and close its subscribers",
                    "security": [_TOKEN],
                    "responses": {
                        "200": _info("deleted; its last info"),
                        "404": _error("no such channel"),
                        **_REFUSALS,
                    },
                },
            },
            "/sub/{channels}": {
                "get": {
                    "summary": "Subscribe: WebSocket upgrade, EventSource or long-poll",
                    "parameters": [
                        {**_CHANNEL, "name": "channels", "schema": {"type": "string"}},
                        {"name": "last_event_id", "in": "query", "schema": {"type": "string"}},
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
                                GAP_TYPE: {"schema": _ref("Gap")},
                                CLOSED_TYPE: {"schema": _ref("ChannelClosed")},
                            },
                        },
                        "400": _error("malformed channel list or resume id"),
                        "408": _error("long-poll: no message within the timeout"),
                        "410": _error("long-poll: the channel was deleted"),
                    },
                }
            },
        },
    }

"""Mounting the relay on an aiohttp application."""

from __future__ import annotations

from aiohttp import web

from server.relay.http import RELAY_KEY, SUBSCRIBE_ROUTE, add_cors_headers
from server.relay.openapi import openapi_document
from server.relay.publisher import channel_info, delete_channel, publish
from server.relay.relay import Relay
from server.relay.subscriber import preflight, subscribe


async def _openapi(request: web.Request) -> web.Response:
    return web.json_response(openapi_document())


def mount_relay(app: web.Application, relay: Relay) -> None:
    """Add `/pub/{channel}`, `/sub/{channels}` and `/openapi.json` to `app`."""
    app[RELAY_KEY] = relay
    app.router.add_post("/pub/{channel}", publish)
    app.router.add_get("/pub/{channel}", channel_info, allow_head=False)
    app.router.add_delete("/pub/{channel}", delete_channel)
    app.router.add_get("/sub/{channels}", subscribe, allow_head=False, name=SUBSCRIBE_ROUTE)
    app.router.add_route("OPTIONS", "/sub/{channels}", preflight)
    app.on_response_prepare.append(add_cors_headers)
    app.router.add_get("/openapi.json", _openapi)

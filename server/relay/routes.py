"""Mounting the relay on an aiohttp application."""

from __future__ import annotations

import functools

from aiohttp import web

from server.relay.http import RELAY_KEY, add_cors_headers
from server.relay.openapi import openapi_document
from server.relay.publisher import channel_info, delete_channel, publish
from server.relay.relay import Relay
from server.relay.subscriber import preflight, subscribe


async def _openapi(request: web.Request) -> web.Response:
    return web.json_response(openapi_document())


def mount_relay(app: web.Application, relay: Relay) -> None:
    """Add `/pub/{channel}`, `/sub/{channels}` and `/openapi.json` to `app`.

    The subscriber endpoint is an application of its own, mounted at `/sub`, so that only its
    answers pass through the hook that adds CORS headers: aiohttp runs an application's
    response hooks for every answer it sends, the publishers' included (a cost measured
    within the noise on a quiet machine: this is the layering, not a speed-up).

    The publisher's handlers are bound to the relay here rather than finding it through the
    request's application (three calls of aiohttp's on every publish: 2,000 instructions of
    a publish's 346,000, counted by bench/relay_instructions.py)."""
    app[RELAY_KEY] = relay
    app.router.add_post("/pub/{channel}", functools.partial(publish, relay))
    app.router.add_get("/pub/{channel}", functools.partial(channel_info, relay), allow_head=False)
    app.router.add_delete("/pub/{channel}", functools.partial(delete_channel, relay))
    subscribers = web.Application()
    subscribers[RELAY_KEY] = relay
    subscribers.router.add_get("/{channels}", subscribe, allow_head=False)
    subscribers.router.add_route("OPTIONS", "/{channels}", preflight)
    subscribers.on_response_prepare.append(add_cors_headers)
    app.add_subapp("/sub", subscribers)
    app.router.add_get("/openapi.json", _openapi)

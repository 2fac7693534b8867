"""The subscriber endpoint `/sub/{channels}`: picks the transport as nchan does.

A WebSocket upgrade gets a WebSocket subscriber, `Accept: text/event-stream` an EventSource
subscriber, anything else a long-poll subscriber. `{channels}` is one channel id or several
joined by commas (multiplexing: WebSocket and EventSource only).
"""

from __future__ import annotations

from aiohttp import web

from server.relay.addresses import client_address
from server.relay.cursor import Cursor
from server.relay.errors import RelayError
from server.relay.eventsource import eventsource_subscriber
from server.relay.http import PREFLIGHT_HEADERS, check_origin, error_response, relay_of
from server.relay.longpoll import longpoll_subscriber
from server.relay.relay import check_channel
from server.relay.websocket import websocket_subscriber


def _channels(text: str, limit: int) -> list[str]:
    channels = text.split(",")
    if len(channels) > limit or len(set(channels)) != len(channels):
        raise RelayError(400, f"subscribe to at most {limit} distinct channels at once")
    return [check_channel(channel) for channel in channels]


async def subscribe(request: web.Request) -> web.StreamResponse:
    """A subscriber connection, counted against its client's address while it lasts."""
    relay = relay_of(request)
    address = client_address(request, relay.trusted_proxies)
    try:
        relay.connections.acquire(address)
    except RelayError as error:
        return error_response(error)
    try:
        return await _subscribe(request)
    finally:
        relay.connections.release(address)


async def _subscribe(request: web.Request) -> web.StreamResponse:
    relay = relay_of(request)
    is_websocket = request.headers.get("Upgrade", "").lower() == "websocket"
    is_eventsource = "text/event-stream" in request.headers.get("Accept", "")
    try:
        check_origin(request, relay.settings.allowed_origins)
        channels = _channels(request.match_info["channels"], relay.settings.max_multiplex)
        if not (is_websocket or is_eventsource):
            if len(channels) > 1:
                raise RelayError(400, "long-poll subscribes to one channel at a time")
            return await longpoll_subscriber(request, channels[0])
        last = request.headers.get("Last-Event-ID") if is_eventsource else None
        try:
            cursor = Cursor.parse(channels, last or request.query.get("last_event_id"))
        except ValueError as error:
            raise RelayError(400, str(error)) from None
        if is_websocket:
            if "pub" in request.query:
                check_channel(request.query["pub"])
            return await websocket_subscriber(request, channels, cursor)
    except RelayError as error:
        return error_response(error)
    return await eventsource_subscriber(request, channels, cursor)


async def preflight(request: web.Request) -> web.Response:
    """The answer to a browser's CORS preflight (`OPTIONS`) of a subscriber request."""
    relay = relay_of(request)
    try:
        check_origin(request, relay.settings.allowed_origins)
        _channels(request.match_info["channels"], relay.settings.max_multiplex)
    except RelayError as error:
        return error_response(error)
    headers = dict(PREFLIGHT_HEADERS)
    origin = request.headers.get("Origin")
    if origin is not None:
        headers["Access-Control-Allow-Origin"] = origin
        headers["Access-Control-Allow-Credentials"] = "true"
    return web.Response(status=200, headers=headers)

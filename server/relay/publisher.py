"""The publisher endpoint `/pub/{channel}`, with nchan's methods and status codes.

- POST publishes the body (JSON or msgpack by Content-Type) and answers the channel info:
  201 when subscribers were present, 202 when none were. `X-EventSource-Event: NAME` names
  the message's EventSource event. 503 with Retry-After if the message store is unreachable.
- GET answers the channel info (text, or JSON by Accept), 404 for an unknown channel.
- GET with a WebSocket upgrade opens a publisher socket: each frame (text: JSON, binary:
  msgpack) is published and answered with the channel info in the format the handshake's Accept
  asked for, or with the JSON error body of a refusal (nothing published, socket kept open).
- DELETE removes the channel and closes its subscribers: 200 with its last info, 404 if unknown.
"""

from __future__ import annotations

from aiohttp import web

from server.relay.errors import RelayError
from server.relay.frames import info_body, wants_json
from server.relay.http import bearer_token, error_body, error_response, frame_message
from server.relay.messages import ChannelInfo
from server.relay.relay import Relay, check_channel


def _info_response(request: web.Request, info: ChannelInfo, status: int) -> web.Response:
    content_type, body = info_body(info, wants_json(request.headers.get("Accept")))
    # A body of bytes: aiohttp adds no charset parameter to its type, and nchan sends none.
    return web.Response(status=status, body=body.encode(), content_type=content_type)


async def _read_limited(request: web.Request, limit: int) -> bytes:
    """The body, or RelayError(413) as soon as it is longer than `limit` (not read further).

    A body of a known length within the limit is read at once; a chunked one a chunk at a
    time, counted as it comes."""
    length = request.content_length
    if length is not None:
        if length > limit:
            raise RelayError(413, f"message of {length} bytes exceeds {limit}")
        return await request.read()
    chunks, size = [], 0
    async for chunk in request.content.iter_chunked(64 * 1024):
        size += len(chunk)
        if size > limit:
            raise RelayError(413, f"message exceeds the {limit}-byte limit")
        chunks.append(chunk)
    return b"".join(chunks)


async def publish(relay: Relay, request: web.Request) -> web.Response:
    channel = request.match_info["channel"]
    try:
        relay.admit(channel, bearer_token(request))
        data = await _read_limited(request, relay.settings.max_message_bytes)
        event = request.headers.get("X-EventSource-Event")
        canonical = relay.validate(request.headers.get("Content-Type"), data, event)
        published = await relay.backend.publish(channel, data, canonical, event)
    except RelayError as error:
        return error_response(error)
    return _info_response(request, published.info, 201 if published.had_subscribers else 202)


async def _websocket_publisher(
    relay: Relay, request: web.Request, channel: str
) -> web.WebSocketResponse:
    token = bearer_token(request)
    as_json = wants_json(request.headers.get("Accept"))
    ws = web.WebSocketResponse(
        heartbeat=relay.settings.keepalive, max_msg_size=relay.settings.max_message_bytes
    )
    await ws.prepare(request)
    async for frame in ws:
        if (message := frame_message(frame)) is None:
            continue
        try:
            published = await relay.publish(channel, token, *message)
        except RelayError as error:
            await ws.send_str(error_body(error))
            continue
        await ws.send_str(info_body(published.info, as_json)[1])
    return ws


async def channel_info(relay: Relay, request: web.Request) -> web.StreamResponse:
    try:
        channel = check_channel(request.match_info["channel"])
    except RelayError as error:
        return error_response(error)
    if request.headers.get("Upgrade", "").lower() == "websocket":
        return await _websocket_publisher(relay, request, channel)
    try:
        info = await relay.backend.info(channel)
    except RelayError as error:
        return error_response(error)
    if info is None:
        return error_response(RelayError(404, f"no channel {channel!r}"))
    return _info_response(request, info, 200)


async def delete_channel(relay: Relay, request: web.Request) -> web.Response:
    channel = request.match_info["channel"]
    try:
        relay.admit(channel, bearer_token(request))
        info = await relay.backend.info(channel)
        existed = await relay.backend.delete(channel)
    except RelayError as error:
        return error_response(error)
    if not existed:
        return error_response(RelayError(404, f"no channel {channel!r}"))
    if info is None:  # it existed but its messages had expired
        info = ChannelInfo(messages=0, requested=-1, subscribers=0, last_message_id=None)
    return _info_response(request, info, 200)

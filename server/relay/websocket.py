"""WebSocket subscribers (and publishers) at `/sub/{channels}`.

- Plain frames carry the message data: text frames for JSON, binary frames for msgpack.
- With the `ws+meta.nchan` subprotocol each frame starts with nchan's `id:` and `content-type:`
  lines, so the client can resume with `?last_event_id=<id>`.
- `/sub/a,b` subscribes one connection to several channels; ids are then cursors over all of
  them (see `server.relay.cursor`).
- Frames the client sends are published (text: JSON, binary: msgpack) to `?pub=<channel>`, by
  default the first subscribed channel, with the token of `?token=` or the Authorization header.
  A refused publish closes the connection with code 4000 + the HTTP status and the reason.
- Gaps arrive as frames of type `application/vnd.relay.gap+json`; a deleted channel closes the
  connection with 4410, an overflowing send queue with 1008, both with the reason.
"""

from __future__ import annotations

import asyncio

from aiohttp import WSMsgType, web

from server.relay.cursor import Cursor
from server.relay.errors import RelayError
from server.relay.frames import meta_header, notice
from server.relay.http import bearer_token, frame_message, relay_of
from server.relay.messages import DELETED, SHUTDOWN, ChannelClosed, Event, StoredMessage
from server.relay.payloads import MSGPACK
from server.relay.sendqueue import SendQueue
from server.relay.subscribing import subscribe_all, unsubscribe_all

META_PROTOCOL = "ws+meta.nchan"
CLOSE_DELETED = 4410
CLOSE_OVERFLOW = 1008  # policy violation: the client did not keep up
CLOSE_SHUTDOWN = 1001  # going away


def close_code(closed: ChannelClosed) -> int:
    if closed.reason == DELETED:
        return CLOSE_DELETED
    if closed.reason == SHUTDOWN:
        return CLOSE_SHUTDOWN
    return CLOSE_OVERFLOW


class _Writer:
    """Sends queued events to one WebSocket in the chosen framing."""

    def __init__(self, ws: web.WebSocketResponse, cursor: Cursor, meta: bool) -> None:
        self.ws = ws
        self.cursor = cursor
        self.meta = meta

    async def send(self, event: Event) -> None:
        if isinstance(event, StoredMessage):
            opcode = WSMsgType.BINARY if event.content_type == MSGPACK else WSMsgType.TEXT
            data = event.data
            if self.meta:
                message_id = self.cursor.advance(event.channel, event.id)
                data = meta_header(message_id, event.content_type) + data
            await self.ws.send_frame(data, opcode)
            return
        content_type, body = notice(event)
        if self.meta:
            body = meta_header(self.cursor.text(event.channel), content_type) + body
        await self.ws.send_frame(body, WSMsgType.TEXT)

    async def run(self, queue: SendQueue) -> None:
        try:
            while batch := await queue.take():
                for event in batch:
                    await self.send(event)
        except ConnectionError:
            return  # the client has gone; the handler cleans up
        if queue.closed is not None:
            reason = queue.closed.reason.encode()[:123]
            await self.ws.close(code=close_code(queue.closed), message=reason)


async def websocket_subscriber(
    request: web.Request, channels: list[str], cursor: Cursor
) -> web.WebSocketResponse:
    relay = relay_of(request)
    settings = relay.settings
    publish_to = request.query.get("pub", channels[0])  # checked by the caller
    ws = web.WebSocketResponse(
        protocols=(META_PROTOCOL,),
        heartbeat=settings.keepalive,
        max_msg_size=settings.max_message_bytes,
    )
    await ws.prepare(request)
    writer = _Writer(ws, cursor, ws.ws_protocol == META_PROTOCOL)
    queue = SendQueue(settings.send_queue_length)
    subscriptions = await subscribe_all(relay, channels, cursor, queue)
    writing = asyncio.create_task(writer.run(queue))
    token = bearer_token(request)
    try:
        async for frame in ws:
            if (message := frame_message(frame)) is None:
                continue
            try:
                await relay.publish(publish_to, token, *message)
            except RelayError as error:
                await ws.close(code=4000 + error.status, message=error.reason.encode()[:123])
    finally:
        writing.cancel()
        await unsubscribe_all(relay, subscriptions)
    return ws

"""WebSocket subscribers (and publishers) at `/sub/{channels}`.

- Plain frames carry the message data: text frames for JSON, binary frames for msgpack.
- With the `ws+meta.nchan` subprotocol each frame starts with nchan's `id:` and `content-type:`
  lines, so the client can resume with `?last_event_id=<id>`.
- `/sub/a,b` subscribes one connection to several channels; ids are then cursors over all of
  them (see `server.relay.cursor`).
- Frames the client sends are published (text: JSON, binary: msgpack) to `?pub=<channel>`, by
  default the first subscribed channel, with the token of `?token=` or the Authorization header.
  A refused publish closes the connection with code 4000 + the HTTP status and the reason.
- A message's frame is built once and written straight to every subscriber's socket whose
  buffer has room (see `server.relay.sendqueue`); the rest wait in their bounded queues.
- Gaps arrive as frames of type `application/vnd.relay.gap+json`; a deleted channel closes the
  connection with 1001 and the reason "410 Gone" (as nchan does), an overflowing send queue
  with 1008 and the reason, an unreachable message store with 1013 (try again later).
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable

from aiohttp import WSMsgType, web

from server.relay.cursor import Cursor
from server.relay.errors import RelayError
from server.relay.frames import (
    message_frame,
    message_opcode,
    meta_header,
    notice,
    websocket_frame,
)
from server.relay.http import bearer_token, frame_message, limit_socket_buffer, relay_of
from server.relay.messages import DELETED, SHUTDOWN, ChannelClosed, Event, StoredMessage
from server.relay.sendqueue import SendQueue
from server.relay.subscribing import subscribe_all, unsubscribe_all

META_PROTOCOL = "ws+meta.nchan"
CLOSE_GOING_AWAY = 1001  # deleted channel (nchan's "410 Gone") or server shutdown
CLOSE_OVERFLOW = 1008  # policy violation: the client did not keep up
CLOSE_TRY_LATER = 1013
DELETED_REASON = "410 Gone"


def close_frame(closed: ChannelClosed) -> tuple[int, bytes]:
    """The close code and reason that end a subscription, as nchan sends them."""
    if closed.reason == DELETED:
        return CLOSE_GOING_AWAY, DELETED_REASON.encode()
    code = CLOSE_GOING_AWAY if closed.reason == SHUTDOWN else CLOSE_OVERFLOW
    return code, closed.reason.encode()[:123]


class _Writer:
    """Sends one WebSocket's events in the chosen framing: at once when the socket can take
    them (`write_now`), else from the queue (`run`)."""

    def __init__(
        self, ws: web.WebSocketResponse, transport: asyncio.Transport, cursor: Cursor, meta: bool
    ) -> None:
        self.ws = ws
        self.transport = transport
        self.cursor = cursor
        self.meta = meta
        # Single-channel frames are the same for every subscriber of the channel: shared.
        self.shared = len(cursor.channels) == 1
        self.task: asyncio.Task[None] | None = None  # only while events wait (see `start`)
        self.high = transport.get_write_buffer_limits()[1]  # a full buffer, in bytes

    def payload(self, event: Event) -> tuple[bytes, WSMsgType]:
        """The frame's payload and type (advancing the cursor past a message)."""
        if isinstance(event, StoredMessage):
            data = event.data
            if self.meta:
                message_id = self.cursor.advance(event.channel, event.id)
                data = meta_header(message_id, event.content_type) + data
            return data, message_opcode(event.content_type)
        content_type, body = notice(event)
        if self.meta:
            body = meta_header(self.cursor.text(event.channel), content_type) + body
        return body, WSMsgType.TEXT

    def write_now(self, event: Event) -> bool:
        """Write the event's frame to the transport unless its buffer is full (or it closes).

        aiohttp's own frames (pings, pongs, close) are whole frames too, so they never split
        one of ours. A full buffer (the client reads slowly) leaves the event to the queue,
        whose writer waits for the buffer to drain.
        """
        transport = self.transport
        if self.ws.closed or transport.is_closing():
            return False
        if transport.get_write_buffer_size() >= self.high:
            return False
        if self.shared and type(event) is StoredMessage:  # one frame for every subscriber
            self.cursor.positions[event.channel] = event.id  # `advance`, without the text
            frame = message_frame(event, self.meta)
        else:
            frame = websocket_frame(*self.payload(event))
        transport.write(frame)
        return True

    def start(self, queue: SendQueue) -> None:
        """Send what waits in the queue, from a task that ends once it is empty."""
        if self.task is None or self.task.done():
            self.task = asyncio.ensure_future(self.run(queue))

    async def run(self, queue: SendQueue) -> None:
        try:
            while batch := queue.take_ready():
                for event in batch:
                    await self.ws.send_frame(*self.payload(event))
        except ConnectionError:
            return  # the client has gone; the handler cleans up
        if queue.closed is not None:
            code, reason = close_frame(queue.closed)
            await self.ws.close(code=code, message=reason)


def _direct_path(ws: web.WebSocketResponse, writer: _Writer) -> Callable[[Event], bool] | None:
    """The queue's shortcut to the socket, if frames can go out uncompressed as built."""
    if ws.compress:
        return None  # permessage-deflate: each connection compresses with its own state
    return writer.write_now


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
    transport = request.transport
    if transport is None:
        return ws  # the client left during the handshake
    limit_socket_buffer(request, settings.socket_buffer_bytes)
    writer = _Writer(ws, transport, cursor, ws.ws_protocol == META_PROTOCOL)
    queue = relay.send_queue(_direct_path(ws, writer), lambda: writer.start(queue))
    try:
        subscriptions = await subscribe_all(relay, channels, cursor, queue)
    except RelayError as error:
        queue.discard()
        await ws.close(code=CLOSE_TRY_LATER, message=error.reason.encode()[:123])
        return ws
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
        if writer.task is not None:
            writer.task.cancel()
        queue.discard()
        await unsubscribe_all(relay, subscriptions)
    return ws

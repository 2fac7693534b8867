"""EventSource (Server-Sent Events) subscribers at `/sub/{channels}`.

Chosen by `Accept: text/event-stream`. Each message is an event with an `id:` line (a cursor
for multiplexed channels), an `event:` line if its publisher named one (`X-EventSource-Event`),
and its data as `data:` lines; msgpack messages are sent as JSON text. A client resumes with
the `Last-Event-ID` header (browsers send it on reconnect) or `?last_event_id=`. A gap is an
event named `gap`; the end of a subscription (channel deleted, send queue overflowed) is an
event named `closed` before the stream ends. Comment lines keep an idle stream alive and reveal
clients that have gone.

Events are written one at a time, each after the socket has taken the one before (aiohttp's
drain), so a reader that stops reading holds at most one event beyond the transport's buffer.
"""

from __future__ import annotations

import asyncio

from aiohttp import web

from server.relay.cursor import Cursor
from server.relay.errors import RelayError
from server.relay.frames import notice, sse_event
from server.relay.http import error_response, limit_socket_buffer, relay_of
from server.relay.messages import Event, Gap, StoredMessage
from server.relay.payloads import as_text
from server.relay.subscribing import subscribe_all, unsubscribe_all

KEEPALIVE = b": keepalive\n\n"


def _encode(event: Event, cursor: Cursor) -> bytes:
    if isinstance(event, StoredMessage):
        message_id = cursor.advance(event.channel, event.id)
        return sse_event(as_text(event.data, event.content_type), message_id, event.event)
    _, body = notice(event)
    return sse_event(body.decode(), event="gap" if isinstance(event, Gap) else "closed")


async def eventsource_subscriber(
    request: web.Request, channels: list[str], cursor: Cursor
) -> web.StreamResponse:
    relay = relay_of(request)
    queue = relay.send_queue()
    try:
        subscriptions = await subscribe_all(relay, channels, cursor, queue)
    except RelayError as error:
        queue.discard()
        return error_response(error)
    response = web.StreamResponse(
        headers={
            "Content-Type": "text/event-stream; charset=utf-8",
            "Cache-Control": "no-cache",
            "X-Accel-Buffering": "no",
        }
    )
    keepalive = relay.settings.keepalive
    try:
        await response.prepare(request)
        limit_socket_buffer(request, relay.settings.socket_buffer_bytes)
        await response.write(KEEPALIVE)  # headers and a first byte: the stream is open
        while True:
            try:
                batch = await asyncio.wait_for(queue.take(), keepalive)
            except TimeoutError:
                await response.write(KEEPALIVE)
                continue
            if not batch:
                break
            for event in batch:
                await response.write(_encode(event, cursor))
        if queue.closed is not None:
            await response.write(_encode(queue.closed, cursor))
    except ConnectionError:
        pass  # the client went away; its subscriptions end below
    finally:
        queue.discard()
        await unsubscribe_all(relay, subscriptions)
    return response

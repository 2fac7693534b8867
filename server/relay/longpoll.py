"""Long-poll subscribers at `/sub/{channel}`: one message per request, walking the buffer.

As in nchan, a response carries the message's id split over two cache headers: `Last-Modified`
(its seconds, as an HTTP date) and `Etag` (its tag). The client sends them back as
`If-Modified-Since` and `If-None-Match` and gets the next message, at once if it is buffered,
else when it is published. Without them it gets the first message per `first_message`.
`?last_event_id=<id>` is accepted too (empty: as if absent). As HTTP says of conditional
requests, an `If-Modified-Since` that is not an HTTP date is ignored, and so is an
`If-None-Match` that is not a message tag. No message within the timeout: 408, try again.
A gap is reported in the `X-Relay-Gap` header (the id that expired) on the next message; a
channel deleted while waiting answers 410.
"""

from __future__ import annotations

import asyncio
from datetime import UTC, datetime
from email.utils import format_datetime, parsedate_to_datetime

from aiohttp import web

from server.relay.errors import RelayError
from server.relay.http import error_response, relay_of
from server.relay.ids import format_message_id, parse_message_id
from server.relay.messages import DELETED, Gap, StoredMessage
from server.relay.sendqueue import SendQueue
from server.relay.subscribing import unsubscribe_all

_WHOLE_SECOND = 10**12 - 1  # a tag after every tag: If-Modified-Since alone skips its second


def requested_id(request: web.Request) -> str | None:
    """The id the client has seen, from nchan's cache headers or `?last_event_id=`."""
    if request.query.get("last_event_id"):
        return request.query["last_event_id"]
    try:
        seconds = int(parsedate_to_datetime(request.headers.get("If-Modified-Since")).timestamp())
    except (TypeError, ValueError, IndexError, OverflowError):
        return None  # absent or not an HTTP date: ignored (RFC 9110, section 13.1.3)
    if seconds < 0:
        return None
    etag = request.headers.get("If-None-Match", "").strip().removeprefix("W/").strip('"')
    if not (etag.isascii() and etag.isdigit() and len(etag) <= 12):
        return format_message_id((seconds, _WHOLE_SECOND))
    return format_message_id((seconds, int(etag)))


def _message_response(message: StoredMessage, gap: Gap | None) -> web.Response:
    seconds, tag = parse_message_id(message.id)
    headers = {
        "Last-Modified": format_datetime(datetime.fromtimestamp(seconds, UTC), usegmt=True),
        "Etag": str(tag),
        "Cache-Control": "no-cache",
        "Access-Control-Expose-Headers": "Last-Modified, Etag, Content-Type, X-Relay-Gap",
    }
    if gap is not None:
        headers["X-Relay-Gap"] = gap.last_id
    return web.Response(body=message.data, content_type=message.content_type, headers=headers)


async def _first_message(queue: SendQueue) -> tuple[Gap | None, StoredMessage | None]:
    """The first message the subscription delivers (None once it is closed), and the gap
    notice before it, if any: a gap alone (a channel whose history is lost, and nothing new
    yet) is told with the next message, not instead of it."""
    gap = None
    while batch := await queue.take():
        gap = gap or next((event for event in batch if isinstance(event, Gap)), None)
        message = next((event for event in batch if isinstance(event, StoredMessage)), None)
        if message is not None:
            return gap, message
    return gap, None


async def longpoll_subscriber(request: web.Request, channel: str) -> web.Response:
    relay = relay_of(request)
    try:
        last_id = requested_id(request)
        if last_id is not None:
            parse_message_id(last_id)
    except (RelayError, ValueError) as error:
        reason = error.reason if isinstance(error, RelayError) else str(error)
        return error_response(RelayError(400, reason))
    queue = relay.send_queue()
    try:
        subscription = await relay.backend.subscribe(
            channel, queue, last_id, relay.settings.first_message
        )
    except RelayError as error:
        queue.discard()
        return error_response(error)
    try:
        waiting = _first_message(queue)
        gap, message = await asyncio.wait_for(waiting, relay.settings.longpoll_timeout)
    except TimeoutError:
        return error_response(RelayError(408, "no message yet: ask again"))
    finally:
        queue.discard()
        await unsubscribe_all(relay, [subscription])
    if message is not None:
        return _message_response(message, gap)
    closed = queue.closed
    if closed is not None and closed.reason == DELETED:
        return error_response(RelayError(410, f"channel {channel!r} was deleted"))
    return error_response(RelayError(503, closed.reason if closed else "subscription ended"))

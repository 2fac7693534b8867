"""How channel info and events look on the wire, for each transport, as nchan formats them.

- Channel info: nchan's plain-text block (CRLF line ends, no final one), or JSON with nchan's
  field names as `text/json`, chosen by `Accept`.
- `ws+meta.nchan` frames: `id: <id>\\ncontent-type: <type>\\n\\n<data>`.
- EventSource: `id:` and `data:` lines, one `data:` per line of the message.
- Gaps and closes (our additions) carry JSON of the `Gap` / `ChannelClosed` models, with their
  own content types so a client can tell them from messages.
- WebSocket frames of messages are built once and shared by every subscriber (see
  `message_frame`).
"""

from __future__ import annotations

import re
import struct
from functools import lru_cache

from aiohttp import WSMsgType

from server.relay.messages import CHANNEL_INFO, ChannelClosed, ChannelInfo, Gap, StoredMessage
from server.relay.payloads import MSGPACK

_LINE_END = re.compile(r"\r\n|\r|\n")  # what the EventSource specification counts as a line end
GAP_TYPE = "application/vnd.relay.gap+json"
CLOSED_TYPE = "application/vnd.relay.closed+json"


INFO_JSON_TYPE = "text/json"  # what nchan answers for `text/json` and `application/json`
_INFO_TEXT = "\r\n".join(  # one format per publish's answer
    (
        "queued messages: %d",
        "last requested: %d sec. ago",
        "active subscribers: %d",
        "last message id: %s",
    )
)


def wants_json(accept: str | None) -> bool:
    """nchan answers JSON for `Accept: text/json` or `application/json`, else text."""
    accept = (accept or "").lower()
    return "application/json" in accept or "text/json" in accept


def info_body(info: ChannelInfo, as_json: bool) -> tuple[str, str]:
    """(content type, body) of a channel info answer."""
    if as_json:
        return INFO_JSON_TYPE, CHANNEL_INFO.dump_json(info).decode()
    last = info.last_message_id if info.last_message_id is not None else ""
    return "text/plain", _INFO_TEXT % (info.messages, info.requested, info.subscribers, last)


@lru_cache(maxsize=4096)  # every subscriber of a channel sends the same header
def meta_header(message_id: str, content_type: str) -> bytes:
    """The `ws+meta.nchan` header that precedes a message's data."""
    return f"id: {message_id}\ncontent-type: {content_type}\n\n".encode()


def websocket_frame(payload: bytes, opcode: WSMsgType) -> bytes:
    """One whole, unmasked server-to-client WebSocket frame (RFC 6455, section 5.2).

    aiohttp's `send_frame` builds a frame per connection; a server's frames carry no mask, so
    the bytes are the same for every subscriber and the relay builds them once per message.
    """
    length = len(payload)
    first = 0x80 | opcode  # FIN: the message is not fragmented
    if length < 126:
        header = struct.pack("!BB", first, length)
    elif length < 1 << 16:
        header = struct.pack("!BBH", first, 126, length)
    else:
        header = struct.pack("!BBQ", first, 127, length)
    return header + payload


def message_opcode(content_type: str) -> WSMsgType:
    """Binary frames carry msgpack, text frames JSON."""
    return WSMsgType.BINARY if content_type == MSGPACK else WSMsgType.TEXT


# A fan-out asks for the same frame once per subscriber, all in one go (`Backend._fan_out`):
# the last message's frame, for meta subscribers and for plain ones, is kept to be reused.
# (A cache keyed by the message's fields hashed its data: 25 KB for an eight-ball break's
# outcome.)
_last_frames: dict[bool, tuple[StoredMessage, bytes]] = {}


def message_frame(message: StoredMessage, meta: bool) -> bytes:
    """The WebSocket frame of a message for single-channel subscribers, `ws+meta.nchan` or not."""
    last = _last_frames.get(meta)
    if last is not None and last[0] is message:
        return last[1]
    data = message.data
    payload = meta_header(message.id, message.content_type) + data if meta else data
    frame = websocket_frame(payload, message_opcode(message.content_type))
    _last_frames[meta] = (message, frame)
    return frame


def notice(event: Gap | ChannelClosed) -> tuple[str, bytes]:
    """(content type, JSON body) of a gap or close notice."""
    content_type = GAP_TYPE if isinstance(event, Gap) else CLOSED_TYPE
    return content_type, event.model_dump_json().encode()


def sse_event(data: str, message_id: str | None = None, event: str | None = None) -> bytes:
    """One EventSource event; multi-line data becomes several `data:` lines.

    Lines are split where the EventSource specification ends them (CRLF, CR or LF), so a
    conforming parser joins the `data:` lines back into the data with LF between them.
    """
    lines = []
    if event is not None:
        lines.append(f"event: {event}")
    if message_id is not None:
        lines.append(f"id: {message_id}")
    lines.extend(f"data: {line}" for line in _LINE_END.split(data))
    return ("\n".join(lines) + "\n\n").encode()

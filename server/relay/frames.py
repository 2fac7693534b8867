"""How channel info and events look on the wire, for each transport, as nchan formats them.

- Channel info: nchan's plain-text block, or JSON with nchan's field names, chosen by `Accept`.
- `ws+meta.nchan` frames: `id: <id>\\ncontent-type: <type>\\n\\n<data>`.
- EventSource: `id:` and `data:` lines, one `data:` per line of the message.
- Gaps and closes (our additions) carry JSON of the `Gap` / `ChannelClosed` models, with their
  own content types so a client can tell them from messages.
"""

from __future__ import annotations

from functools import lru_cache

from server.relay.messages import ChannelClosed, ChannelInfo, Gap

GAP_TYPE = "application/vnd.relay.gap+json"
CLOSED_TYPE = "application/vnd.relay.closed+json"


def wants_json(accept: str | None) -> bool:
    """nchan answers JSON for `Accept: text/json` or `application/json`, else text."""
    accept = (accept or "").lower()
    return "application/json" in accept or "text/json" in accept


def info_body(info: ChannelInfo, as_json: bool) -> tuple[str, str]:
    """(content type, body) of a channel info answer."""
    if as_json:
        return "application/json", info.model_dump_json()
    last = info.last_message_id if info.last_message_id is not None else ""
    text = (
        f"queued messages: {info.messages}\n"
        f"last requested: {info.requested} sec. ago\n"
        f"active subscribers: {info.subscribers}\n"
        f"last message id: {last}\n"
    )
    return "text/plain", text


@lru_cache(maxsize=4096)  # every subscriber of a channel sends the same header
def meta_header(message_id: str, content_type: str) -> bytes:
    """The `ws+meta.nchan` header that precedes a message's data."""
    return f"id: {message_id}\ncontent-type: {content_type}\n\n".encode()


def notice(event: Gap | ChannelClosed) -> tuple[str, bytes]:
    """(content type, JSON body) of a gap or close notice."""
    content_type = GAP_TYPE if isinstance(event, Gap) else CLOSED_TYPE
    return content_type, event.model_dump_json().encode()


def sse_event(data: str, message_id: str | None = None, event: str | None = None) -> bytes:
    """One EventSource event; multi-line data becomes several `data:` lines."""
    lines = []
    if event is not None:
        lines.append(f"event: {event}")
    if message_id is not None:
        lines.append(f"id: {message_id}")
    lines.extend(f"data: {line}" for line in data.split("\n"))
    return ("\n".join(lines) + "\n\n").encode()

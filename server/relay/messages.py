"""The relay's data models: what a backend stores and what it tells a subscriber.

These are shared by every backend and every transport, so they say nothing about HTTP or Redis.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, TypeAdapter

from server.relay.ids import ChannelId, MessageKey, parse_message_id

_FROZEN = ConfigDict(frozen=True)


# The four types below are made once or more per publish, so they are slotted dataclasses
# rather than pydantic models: nothing here comes from a client unchecked (the relay's
# transports check ids, bodies and names at the edge), and a model's validation cost as much
# as the rest of a publish's own work. Treat them as immutable: one message object goes to
# every subscriber of its channel.


@dataclass(slots=True)
class StoredMessage:
    """One published message as a channel's buffer holds it."""

    channel: str
    id: str  # nchan-style `<unix seconds>:<tag>`, increasing per channel
    content_type: str
    data: bytes
    time: float  # unix time (seconds) when the backend accepted it
    event: str | None = None  # EventSource event name (`X-EventSource-Event` on publish)
    #: (seconds, tag), the order of ids within a channel (parsed from `id` if not given).
    key: MessageKey = field(default=(-1, -1), compare=False, repr=False)

    def __post_init__(self) -> None:
        if self.key == (-1, -1):
            self.key = parse_message_id(self.id)


@dataclass(slots=True)
class ChannelInfo:
    """What `GET /pub/{channel}` reports, with nchan's field names. (The annotations'
    constraints and descriptions are its JSON schema, `CHANNEL_INFO`; nothing checks them
    when one is made.)"""

    messages: Annotated[int, Field(ge=0, description="messages buffered now")]
    requested: Annotated[
        int, Field(description="seconds since a client last asked for it (-1: never)")
    ]
    subscribers: Annotated[int, Field(ge=0, description="subscribers now (all processes)")]
    last_message_id: Annotated[
        str | None, Field(description="id of the newest message ever published")
    ]


#: ChannelInfo's JSON form and schema (pydantic serializes the dataclass).
CHANNEL_INFO = TypeAdapter(ChannelInfo)


@dataclass(slots=True)
class Published:
    """Result of a publish: the stored message and the channel's state right after."""

    message: StoredMessage
    info: ChannelInfo
    had_subscribers: bool  # someone was subscribed (nchan's 201 vs 202)


@dataclass(slots=True)
class Backlog:
    """Buffered messages after a given id, oldest first, and whether some were lost."""

    messages: list[StoredMessage]
    gap: bool  # a message newer than the given id has left the buffer
    more: bool = False  # newer buffered messages follow these


class Gap(BaseModel):
    """Told to a resuming subscriber whose last id has expired: it missed messages.

    nchan silently jumps to the oldest buffered message; we say so, so that a game client knows
    to fetch a full state instead of trusting an incomplete history.
    """

    model_config = _FROZEN

    channel: ChannelId
    last_id: str = Field(description="the id the subscriber resumed from")


DELETED = "deleted"
SHUTDOWN = "shutdown"


class ChannelClosed(BaseModel):
    """The end of a subscription that the subscriber did not ask for (delete, overflow)."""

    model_config = _FROZEN

    channel: ChannelId
    reason: str = Field(description=f"{DELETED!r}, {SHUTDOWN!r} or a sentence")


Event = StoredMessage | Gap | ChannelClosed

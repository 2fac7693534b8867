"""The relay's data models: what a backend stores and what it tells a subscriber.

These are shared by every backend and every transport, so they say nothing about HTTP or Redis.
"""

from __future__ import annotations

from functools import cached_property

from pydantic import BaseModel, ConfigDict, Field

from server.relay.ids import ChannelId, MessageKey, parse_message_id

_FROZEN = ConfigDict(frozen=True)


class StoredMessage(BaseModel):
    """One published message as a channel's buffer holds it."""

    model_config = _FROZEN

    channel: ChannelId
    id: str = Field(description="nchan-style `<unix seconds>:<tag>`, increasing per channel")
    content_type: str
    data: bytes
    time: float = Field(description="unix time (seconds) when the backend accepted it")
    event: str | None = Field(
        default=None, description="EventSource event name (`X-EventSource-Event` on publish)"
    )

    @cached_property
    def key(self) -> MessageKey:
        """(seconds, tag), the order of ids within a channel."""
        return parse_message_id(self.id)


class ChannelInfo(BaseModel):
    """What `GET /pub/{channel}` reports, with nchan's field names."""

    model_config = _FROZEN

    messages: int = Field(ge=0, description="messages buffered now")
    requested: int = Field(description="seconds since a client last asked for it (-1: never)")
    subscribers: int = Field(ge=0, description="subscribers now (all processes)")
    last_message_id: str | None = Field(description="id of the newest message ever published")


class Published(BaseModel):
    """Result of a publish: the stored message and the channel's state right after."""

    model_config = _FROZEN

    message: StoredMessage
    info: ChannelInfo
    had_subscribers: bool = Field(description="someone was subscribed (nchan's 201 vs 202)")


class Backlog(BaseModel):
    """Buffered messages after a given id, oldest first, and whether some were lost."""

    model_config = _FROZEN

    messages: list[StoredMessage]
    gap: bool = Field(description="a message newer than the given id has left the buffer")
    more: bool = Field(default=False, description="newer buffered messages follow these")


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

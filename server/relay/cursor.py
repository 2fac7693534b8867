"""Resume positions of subscriptions that may span several channels.

A single-channel subscriber resumes with a plain message id (`1700000000:3`), as nchan clients
send it. A multiplexed subscriber (`/sub/a,b`) gets, as the id of each message, the cursor of
the whole connection, `a/1700000000:3,b/1700000000:7`, with the message's own channel first:
whatever id a client last saw resumes every channel exactly.
"""

from __future__ import annotations

from server.relay.ids import is_channel_id, parse_message_id


class Cursor:
    """The newest id delivered per channel of one subscription."""

    def __init__(self, channels: list[str], positions: dict[str, str] | None = None) -> None:
        self.channels = channels
        self.positions: dict[str, str] = dict(positions or {})

    @classmethod
    def parse(cls, channels: list[str], text: str | None) -> Cursor:
        """The cursor a client resumes from; ValueError if `text` is malformed."""
        if not text:
            return cls(channels)
        if len(channels) == 1 and "/" not in text:
            parse_message_id(text)
            return cls(channels, {channels[0]: text})
        positions: dict[str, str] = {}
        for entry in text.split(","):
            channel, _, message_id = entry.partition("/")
            if not is_channel_id(channel) or channel not in channels:
                raise ValueError(f"cursor entry {entry!r} names no channel of this subscription")
            parse_message_id(message_id)
            positions[channel] = message_id
        return cls(channels, positions)

    def advance(self, channel: str, message_id: str) -> str:
        """Record a delivery and return the id to show the client for it."""
        self.positions[channel] = message_id
        return self.text(channel)

    def text(self, channel: str) -> str:
        """The resume position as the client sees it, `channel`'s entry first."""
        if len(self.channels) == 1:
            return self.positions.get(channel, "")
        own = self.positions.get(channel)
        rest = [f"{name}/{pos}" for name, pos in self.positions.items() if name != channel]
        return ",".join([f"{channel}/{own}", *rest] if own is not None else rest)

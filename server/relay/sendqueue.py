"""A connection's bounded send queue: the relay never buffers without bound for a slow reader.

Backends offer events without waiting; the connection's writer takes them in batches. When a
subscriber reads too slowly and the queue is full, the queue closes itself with a reason, the
connection is ended with that reason, and the client resumes from its last id.
"""

from __future__ import annotations

import asyncio
from collections import deque

from server.relay.messages import ChannelClosed, Event

OVERFLOW_REASON = "slow subscriber: send queue overflowed; resume with your last message id"


class SendQueue:
    """At most `limit` undelivered events; `closed` holds why it stopped taking more."""

    def __init__(self, limit: int) -> None:
        self.limit = limit
        self._events: deque[Event] = deque()
        self._wakeup = asyncio.Event()
        self.closed: ChannelClosed | None = None

    def offer(self, event: Event) -> None:
        """Queue one event (the `Sink` protocol); past the limit, close instead."""
        if self.closed is not None:
            return
        if isinstance(event, ChannelClosed):
            self.close(event)
        elif len(self._events) >= self.limit:
            self.close(ChannelClosed(channel=event.channel, reason=OVERFLOW_REASON))
        else:
            self._events.append(event)
            self._wakeup.set()

    def close(self, why: ChannelClosed) -> None:
        """Stop taking events; the writer sends what is queued, then `why`."""
        if self.closed is None:
            self.closed = why
            self._wakeup.set()

    async def take(self) -> list[Event]:
        """Wait for events and return all queued; [] once closed and drained."""
        while not self._events:
            if self.closed is not None:
                return []
            self._wakeup.clear()
            await self._wakeup.wait()
        batch = list(self._events)
        self._events.clear()
        return batch

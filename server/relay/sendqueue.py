"""A connection's bounded send queue: the relay never buffers without bound for a slow reader.

Backends offer events without waiting; the connection's writer takes them in batches. When a
subscriber reads too slowly and the queue is full, the queue closes itself with a reason, the
connection is ended with that reason, and the client resumes from its last id.

A connection that can write at once (WebSocket) passes `write_now`: while nothing is queued or
being sent, an offered event goes straight to the socket, without waking the writer task.
That is the common case of a fan-out, and it spares a task switch per subscriber and message.
`write_now` refuses when the transport's buffer is full, so a slow reader still fills the queue
and is closed; order is kept because the shortcut is taken only when nothing waits before it.
Such a connection needs a writer only while events wait: `on_pending` tells it to start one,
which sends with `take_ready` and ends when the queue is empty (an idle connection holds no
writer task).
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable

from server.relay.messages import ChannelClosed, Event

OVERFLOW_REASON = "slow subscriber: send queue overflowed; resume with your last message id"


class SendQueue:
    """At most `limit` undelivered events; `closed` holds why it stopped taking more."""

    def __init__(
        self,
        limit: int,
        write_now: Callable[[Event], bool] | None = None,
        on_pending: Callable[[], None] | None = None,
    ) -> None:
        self.limit = limit
        self._write_now = write_now
        self._on_pending = on_pending
        # A list and a bare future, not a deque and an asyncio.Event: an idle connection holds
        # them, and each of those two allocates a 64-slot block (about 0.7 KB) up front.
        self._events: list[Event] = []
        self._wakeup: asyncio.Future[None] | None = None
        self._sending = False  # the writer holds a batch it has not finished sending
        self.closed: ChannelClosed | None = None

    def offer(self, event: Event) -> None:
        """Queue one event (the `Sink` protocol); past the limit, close instead."""
        if self.closed is not None:
            return
        if isinstance(event, ChannelClosed):
            self.close(event)
        elif (
            not self._events
            and not self._sending
            and self._write_now is not None
            and self._write_now(event)
        ):
            return
        elif len(self._events) >= self.limit:
            self.close(ChannelClosed(channel=event.channel, reason=OVERFLOW_REASON))
        else:
            self._events.append(event)
            self._wake()

    def close(self, why: ChannelClosed) -> None:
        """Stop taking events; the writer sends what is queued, then `why`."""
        if self.closed is None:
            self.closed = why
            self._wake()

    def _wake(self) -> None:
        if self._wakeup is not None:
            if not self._wakeup.done():
                self._wakeup.set_result(None)
        elif self._on_pending is not None:
            self._on_pending()

    def take_ready(self) -> list[Event]:
        """All queued events without waiting ([] if none); the next call says they were sent."""
        batch, self._events = self._events, []
        self._sending = bool(batch)
        return batch

    async def take(self) -> list[Event]:
        """Wait for events and return all queued; [] once closed and drained.

        Calling it again tells the queue that the previous batch has been sent.
        """
        self._sending = False
        while not self._events:
            if self.closed is not None:
                return []
            self._wakeup = asyncio.get_running_loop().create_future()
            try:
                await self._wakeup
            finally:
                self._wakeup = None
        batch, self._events = self._events, []
        self._sending = True
        return batch

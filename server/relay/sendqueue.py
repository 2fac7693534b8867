"""A connection's bounded send queue: the relay never buffers without bound for a slow reader.

Backends offer events without waiting; the connection's writer takes them in batches. When a
subscriber reads too slowly and the queue is full, the queue closes itself with a reason, the
connection is ended with that reason, and the client resumes from its last id.

Full means either bound: `limit` events, or `max_bytes` of message data waiting or being sent
(one message is always let in, so no message is too large for an idle queue). Beyond each
connection's own bound, every queue of the process draws on one `OutputBudget`: when the sum
over all connections would pass it, the connection asking for more is closed instead, so a
crowd of readers that never read cannot hold more than the budget between them. The budget
counts what a queue really holds: a live message is one object handed to every subscriber of
the channel (its data counted once, by nobody's queue), a backlog page is read for this
subscriber alone (its data counted in full).

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

from server.relay.messages import ChannelClosed, Event, StoredMessage

OVERFLOW_REASON = "slow subscriber: send queue overflowed; resume with your last message id"
BUDGET_REASON = "server send buffers are full: resume with your last message id later"
EVENT_OVERHEAD = 256  # bytes an event costs beside its data (its model, the queue's slot)


def event_size(event: Event) -> int:
    """The bytes of a queued event, as the connection's own bound counts them."""
    return EVENT_OVERHEAD + (len(event.data) if isinstance(event, StoredMessage) else 0)


class OutputBudget:
    """Bytes that all send queues of a process may hold between them."""

    def __init__(self, total: int) -> None:
        self.total = total
        self.used = 0

    def take(self, size: int) -> bool:
        """Reserve `size` bytes; False (nothing reserved) if that would pass the total."""
        if self.used + size > self.total:
            return False
        self.used += size
        return True

    def give(self, size: int) -> None:
        self.used -= size


class SendQueue:
    """At most `limit` undelivered events and `max_bytes` of them (one event always fits),
    drawn from `budget`; `closed` holds why it stopped taking more. Call `discard` when the
    connection ends, to return what it still holds to the budget."""

    def __init__(
        self,
        limit: int,
        max_bytes: int,
        budget: OutputBudget,
        write_now: Callable[[Event], bool] | None = None,
        on_pending: Callable[[], None] | None = None,
    ) -> None:
        self.limit = limit
        self.max_bytes = max_bytes
        self._budget = budget
        self._write_now = write_now
        self._on_pending = on_pending
        # A list and a bare future, not a deque and an asyncio.Event: an idle connection holds
        # them, and each of those two allocates a 64-slot block (about 0.7 KB) up front.
        self._events: list[Event] = []
        self._wakeup: asyncio.Future[None] | None = None
        self._drained: asyncio.Future[bool] | None = None
        self._sending = False  # the writer holds a batch it has not finished sending
        self._queued_bytes = 0  # of `_events`
        self._sending_bytes = 0  # of the batch the writer holds
        self._queued_charge = 0  # what `_events` draw on the budget
        self._sending_charge = 0  # what the writer's batch draws on it
        self._discarded = False
        self.closed: ChannelClosed | None = None

    @property
    def held_bytes(self) -> int:
        """Bytes of events waiting or being sent (what the byte bounds count)."""
        return self._queued_bytes + self._sending_bytes

    def offer(self, event: Event, shared: bool = True) -> None:
        """Queue one event (the `Sink` protocol); past a bound, close instead. `shared`: the
        same object goes to other subscribers too (a live message), False for a backlog's."""
        if self.closed is not None or self._discarded:
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
        else:
            self._queue(event, shared)

    def _queue(self, event: Event, shared: bool) -> None:
        size = event_size(event)
        charge = EVENT_OVERHEAD if shared else size
        held = self.held_bytes
        if len(self._events) >= self.limit or (held and held + size > self.max_bytes):
            self.close(ChannelClosed(channel=event.channel, reason=OVERFLOW_REASON))
        elif not self._budget.take(charge):
            self.close(ChannelClosed(channel=event.channel, reason=BUDGET_REASON))
        else:
            self._events.append(event)
            self._queued_bytes += size
            self._queued_charge += charge
            self._wake()

    def close(self, why: ChannelClosed) -> None:
        """Stop taking events; the writer sends what is queued, then `why`."""
        if self.closed is None:
            self.closed = why
            self._wake()
            self._settle(False)

    def discard(self) -> None:
        """The connection has ended: drop what it holds and return it to the budget."""
        self._budget.give(self._queued_charge + self._sending_charge)
        self._events, self._queued_bytes, self._sending_bytes = [], 0, 0
        self._queued_charge = self._sending_charge = 0
        self._discarded = True
        self._settle(False)

    async def drained(self) -> bool:
        """Wait until nothing is queued or being sent; False once the queue is closed."""
        if self.closed is None and not self._discarded and (self._events or self._sending):
            if self._drained is None:
                self._drained = asyncio.get_running_loop().create_future()
            await asyncio.shield(self._drained)
        return self.closed is None and not self._discarded

    def _settle(self, drained: bool) -> None:
        waiter, self._drained = self._drained, None
        if waiter is not None and not waiter.done():
            waiter.set_result(drained)

    def _sent(self) -> None:
        """The writer has sent the batch it took."""
        self._budget.give(self._sending_charge)
        self._sending_bytes = self._sending_charge = 0
        self._sending = False
        if not self._events:
            self._settle(True)

    def _hand_over(self) -> list[Event]:
        batch, self._events = self._events, []
        self._sending_bytes, self._queued_bytes = self._queued_bytes, 0
        self._sending_charge, self._queued_charge = self._queued_charge, 0
        self._sending = bool(batch)
        return batch

    def _wake(self) -> None:
        if self._wakeup is not None:
            if not self._wakeup.done():
                self._wakeup.set_result(None)
        elif self._on_pending is not None:
            self._on_pending()

    def take_ready(self) -> list[Event]:
        """All queued events without waiting ([] if none); the next call says they were sent."""
        self._sent()
        return self._hand_over()

    async def take(self) -> list[Event]:
        """Wait for events and return all queued; [] once closed and drained.

        Calling it again tells the queue that the previous batch has been sent.
        """
        self._sent()
        while not self._events:
            if self.closed is not None:
                return []
            self._wakeup = asyncio.get_running_loop().create_future()
            try:
                await self._wakeup
            finally:
                self._wakeup = None
        return self._hand_over()

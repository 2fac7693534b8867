"""The send queue's shortcut to the socket never reorders events and still bounds the queue."""

from __future__ import annotations

import asyncio

from server.relay.messages import ChannelClosed, StoredMessage
from server.relay.sendqueue import (
    BUDGET_REASON,
    EVENT_OVERHEAD,
    OVERFLOW_REASON,
    OutputBudget,
    SendQueue,
)

ROOMY = 1 << 30


class Socket:
    """Takes events at once while `open`, like a transport whose buffer has room."""

    def __init__(self) -> None:
        self.open = True
        self.written: list[int] = []

    def write_now(self, event: StoredMessage) -> bool:
        if self.open:
            self.written.append(int(event.data))
        return self.open


def message(n: int, size: int = 0) -> StoredMessage:
    data = b"%d" % n + b" " * size
    return StoredMessage(
        channel="c", id=f"1700000000:{n}", content_type="application/json", data=data, time=0
    )


def queue_of(limit: int, write_now=None, on_pending=None, **bounds: int) -> SendQueue:
    budget = OutputBudget(bounds.get("budget", ROOMY))
    return SendQueue(limit, bounds.get("max_bytes", ROOMY), budget, write_now, on_pending)


def numbers(events: list) -> list[int]:
    return [int(event.data) for event in events]


async def test_events_wait_behind_queued_ones_even_when_the_socket_has_room() -> None:
    socket = Socket()
    queue = queue_of(10, socket.write_now)
    queue.offer(message(0))  # room: written at once
    socket.open = False
    queue.offer(message(1))  # full socket: queued
    socket.open = True
    queue.offer(message(2))  # room again, but 1 waits: queued behind it
    assert socket.written == [0]
    assert numbers(await queue.take()) == [1, 2]
    queue.offer(message(3))  # the writer still holds 1 and 2: queued
    assert socket.written == [0]
    assert numbers(await queue.take()) == [3]
    waiting = asyncio.ensure_future(queue.take())  # the writer sent 3 and waits again
    await asyncio.sleep(0)
    queue.offer(message(4))  # nothing queued, nothing being sent: written at once
    assert socket.written == [0, 4]
    assert not waiting.done()
    waiting.cancel()


async def test_a_full_queue_closes_even_with_a_shortcut() -> None:
    socket = Socket()
    socket.open = False
    queue = queue_of(2, socket.write_now)
    for n in range(3):
        queue.offer(message(n))
    assert queue.closed is not None and queue.closed.reason == OVERFLOW_REASON
    assert numbers(await queue.take()) == [0, 1]
    assert await queue.take() == []


def test_a_writer_is_asked_for_only_when_events_wait() -> None:
    """Idle connections hold no writer task: the queue asks for one when it must hold events
    (or close), and `take_ready` hands them over without waiting."""
    socket, calls = Socket(), []
    queue = queue_of(4, socket.write_now, lambda: calls.append(1))
    queue.offer(message(0))
    assert (socket.written, calls) == ([0], [])  # written at once: no writer needed
    socket.open = False
    queue.offer(message(1))
    assert calls == [1]
    assert numbers(queue.take_ready()) == [1]
    assert queue.take_ready() == []  # sent: the writer may end
    socket.open = True
    queue.offer(message(2))
    assert (socket.written, calls) == ([0, 2], [1])
    queue.close(ChannelClosed(channel="c", reason="deleted"))
    assert calls == [1, 1]  # the writer sends the close


async def test_a_queue_is_bounded_in_bytes_but_always_takes_one_message() -> None:
    queue = queue_of(100, max_bytes=10_000)
    queue.offer(message(0, 50_000))  # larger than the bound, but alone: taken
    assert queue.closed is None and queue.held_bytes == 50_000 + 1 + EVENT_OVERHEAD
    queue.offer(message(1, 10))  # anything more is past the bound
    assert queue.closed is not None and queue.closed.reason == OVERFLOW_REASON
    assert numbers(await queue.take()) == [0]


async def test_every_queue_draws_on_one_budget_and_gives_back_what_it_sent() -> None:
    budget = OutputBudget(3 * (EVENT_OVERHEAD + 1001))
    first, second = (SendQueue(100, ROOMY, budget) for _ in range(2))
    first.offer(message(0, 1000), shared=False)
    first.offer(message(1, 1000), shared=False)
    second.offer(message(2, 1000), shared=False)
    assert budget.used == budget.total
    second.offer(message(3, 1000), shared=False)  # over the budget: this connection closes
    assert second.closed is not None and second.closed.reason == BUDGET_REASON
    assert numbers(await first.take()) == [0, 1]
    waiting = asyncio.ensure_future(first.take())  # the batch was sent: its bytes come back
    await asyncio.sleep(0)
    assert budget.used == EVENT_OVERHEAD + 1001
    second.discard()  # the closed connection ends and returns the rest
    assert budget.used == 0
    waiting.cancel()


async def test_drained_waits_until_the_writer_has_sent_everything() -> None:
    queue = queue_of(10)
    assert await queue.drained()  # nothing queued
    queue.offer(message(0))
    drained = asyncio.ensure_future(queue.drained())
    await asyncio.sleep(0)
    assert numbers(await queue.take()) == [0]
    assert not drained.done()  # taken, not yet sent
    taking = asyncio.ensure_future(queue.take())  # the writer comes back: it was sent
    assert await asyncio.wait_for(drained, 5) is True
    queue.close(ChannelClosed(channel="c", reason="deleted"))
    assert not await queue.drained()
    assert await taking == []


def test_a_live_message_handed_to_many_queues_is_charged_once_not_per_queue() -> None:
    """A fan-out gives the same object to every subscriber's queue: the budget counts each
    queue's slot, not the data again, so a burst to many slow sockets does not close them."""
    budget = OutputBudget(100 * (EVENT_OVERHEAD + 10_000))
    queues = [SendQueue(10, ROOMY, budget) for _ in range(1000)]
    shared = message(0, 10_000)
    for queue in queues:
        queue.offer(shared)
    assert all(queue.closed is None for queue in queues)
    assert budget.used == 1000 * EVENT_OVERHEAD

"""The send queue's shortcut to the socket never reorders events and still bounds the queue."""

from __future__ import annotations

import asyncio

from server.relay.messages import ChannelClosed, StoredMessage
from server.relay.sendqueue import OVERFLOW_REASON, SendQueue


class Socket:
    """Takes events at once while `open`, like a transport whose buffer has room."""

    def __init__(self) -> None:
        self.open = True
        self.written: list[int] = []

    def write_now(self, event: StoredMessage) -> bool:
        if self.open:
            self.written.append(int(event.data))
        return self.open


def message(n: int) -> StoredMessage:
    return StoredMessage(
        channel="c", id=f"1700000000:{n}", content_type="application/json", data=b"%d" % n, time=0
    )


def numbers(events: list) -> list[int]:
    return [int(event.data) for event in events]


async def test_events_wait_behind_queued_ones_even_when_the_socket_has_room() -> None:
    socket = Socket()
    queue = SendQueue(limit=10, write_now=socket.write_now)
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
    queue = SendQueue(limit=2, write_now=socket.write_now)
    for n in range(3):
        queue.offer(message(n))
    assert queue.closed is not None and queue.closed.reason == OVERFLOW_REASON
    assert numbers(await queue.take()) == [0, 1]
    assert await queue.take() == []


def test_a_writer_is_asked_for_only_when_events_wait() -> None:
    """Idle connections hold no writer task: the queue asks for one when it must hold events
    (or close), and `take_ready` hands them over without waiting."""
    socket, calls = Socket(), []
    queue = SendQueue(limit=4, write_now=socket.write_now, on_pending=lambda: calls.append(1))
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

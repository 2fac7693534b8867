"""The in-memory backend: the embedded default for one server process.

Each channel is a deque bounded by the buffer length and by the bytes of its data; expired
messages are dropped lazily when the channel is next touched. `publish` fans out directly, so
the "feed" of the interface is the publish call itself. A channel's state stays until it is
deleted (the game service deletes a table's channel when the table expires): forgetting it
earlier would forget which ids expired, and a late resume would then miss its gap notice.

Buffered messages are kept as plain tuples, not `StoredMessage` models: about 0.26 KB each
instead of 1.3 KB (tracemalloc), and CPython's garbage collector stops tracking a tuple of
immutable values, so full buffers add nothing to the walk of each full collection (which
paused the benchmark's server for 35-125 ms). Models are made again for a resume.
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

from server.relay.backend import Backend, BackendConfig, unknown_history
from server.relay.ids import MessageKey, format_message_id, parse_message_id
from server.relay.messages import DELETED, Backlog, ChannelInfo, Published, StoredMessage

_Entry = tuple[MessageKey, str, str, bytes, float, str | None]  # key, id, type, data, time, event


@dataclass
class _Channel:
    messages: deque[_Entry] = field(default_factory=deque)
    last_key: MessageKey | None = None
    born_key: MessageKey | None = None  # the first id of this incarnation (invariant 4)
    evicted_key: MessageKey | None = None
    requested_at: float | None = None
    data_bytes: int = 0  # of the buffered messages' data


class MemoryBackend(Backend):
    """Channels in this process's memory; `clock` (unix seconds) is injectable for tests."""

    def __init__(self, config: BackendConfig, clock: Callable[[], float] = time.time) -> None:
        super().__init__(config)
        self._clock = clock
        self._channels: dict[str, _Channel] = {}

    def _expire(self, channel: str, state: _Channel, now: float) -> None:
        config = self.config
        oldest_allowed = now - config.message_ttl
        messages = state.messages
        length = config.length_of(channel)
        while messages and (
            len(messages) > length
            or (state.data_bytes > config.buffer_bytes and len(messages) > 1)
            or messages[0][4] < oldest_allowed
        ):
            gone = messages.popleft()
            state.evicted_key = gone[0]
            state.data_bytes -= len(gone[3])

    async def publish(
        self, channel: str, data: bytes, content_type: str, event: str | None = None
    ) -> Published:
        now = self._clock()
        state = self._channels.get(channel)
        if state is None:
            state = self._channels[channel] = _Channel()
        seconds = int(now)
        if state.last_key is None or seconds > state.last_key[0]:
            key = (seconds, 0)
        else:  # same second, or the clock stepped back: stay after the previous id
            key = (state.last_key[0], state.last_key[1] + 1)
        message_id = format_message_id(key)
        message = StoredMessage(channel, message_id, content_type, data, now, event, key)
        state.last_key = key
        if state.born_key is None:
            state.born_key = key
        state.messages.append((key, message_id, content_type, data, now, event))
        state.data_bytes += len(data)
        self._expire(channel, state, now)
        subscribers = self.local_subscribers(channel)
        self._fan_out(channel, message)
        info = self._info(state, now, subscribers, message_id)
        return Published(message, info, subscribers > 0)

    async def read_since(self, channel: str, last_id: str | None, limit: int) -> Backlog:
        state = self._channels.get(channel)
        after = parse_message_id(last_id) if last_id is not None else None
        if state is None:
            return Backlog(messages=[], gap=unknown_history(after, None))
        now = self._clock()
        state.requested_at = now
        self._expire(channel, state, now)
        newer = [entry for entry in state.messages if after is None or entry[0] > after]
        page = [
            StoredMessage(channel, id_, type_, data, time_, event, key)
            for key, id_, type_, data, time_, event in newer[:limit]
        ]
        evicted = after is not None and state.evicted_key is not None and state.evicted_key > after
        gap = evicted or unknown_history(after, state.born_key)
        return Backlog(messages=page, gap=gap, more=len(newer) > limit)

    def _info(
        self, state: _Channel, now: float, subscribers: int, last: str | None = None
    ) -> ChannelInfo:
        """The channel's info; `last`: its last message id, if the caller has it formatted."""
        requested = -1 if state.requested_at is None else int(now - state.requested_at)
        if last is None and state.last_key is not None:
            last = format_message_id(state.last_key)
        return ChannelInfo(len(state.messages), requested, subscribers, last)

    async def info(self, channel: str) -> ChannelInfo | None:
        subscribers = self.local_subscribers(channel)
        state = self._channels.get(channel)
        if state is None:
            state = _Channel() if subscribers else None
        if state is None:
            return None
        now = self._clock()
        self._expire(channel, state, now)
        if not state.messages and not subscribers:
            return None
        return self._info(state, now, subscribers)

    async def _open_feed(self, channel: str) -> None:
        """Nothing to start: `publish` fans out itself, in this process."""

    async def _close_feed(self, channel: str) -> None:
        """Nothing to stop (see `_open_feed`)."""

    async def _subscribers_changed(self, channel: str, delta: int) -> None:
        """Nothing to record: the local count is the global one in a single process."""

    async def delete(self, channel: str) -> bool:
        state = self._channels.pop(channel, None)
        closed = await self._end_local(channel, DELETED)
        return state is not None or closed > 0

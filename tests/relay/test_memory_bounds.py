"""Clients that never read cannot make the relay hold memory without bound.

A real relay process, a channel whose buffer holds 100 messages of 60 KiB, and 100 EventSource
plus 100 WebSocket clients that connect and then read nothing (real sockets with small receive
buffers). The server's RSS, read from /proc, must grow by less than 64 MB over the backlog it
already holds; afterwards each client reads what it was sent, which must be either the whole
backlog in order (served) or a prefix of it and then a close that says why. No timing is
asserted: the waits only let the server settle.
"""

from __future__ import annotations

import asyncio
import base64
import json
import os
import re
import socket
import struct
import time
from collections.abc import Awaitable, Callable

import aiohttp
import pytest

from server.relay.auth import TokenAuthority
from tests.relay.conftest import SECRET
from tests.relay.process import RelayProcess

BACKLOG = 100
MESSAGE = 60 * 1024
READERS = 100  # of each kind
BOUND = 64 * 1024 * 1024
SETTLE_S = 60.0  # at most, for the server to stop growing (not a timing claim)
READ_S = 120.0
_NUMBER = re.compile(rb"\[(\d+),")


async def _silent_connection(port: int) -> tuple[asyncio.StreamReader, asyncio.StreamWriter]:
    """A connection with a small receive buffer whose reader is never read until asked."""
    sock = socket.socket()
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    sock.setblocking(False)
    await asyncio.get_running_loop().sock_connect(sock, ("127.0.0.1", port))
    return await asyncio.open_connection(sock=sock, limit=2 * MESSAGE)


async def _eventsource(port: int) -> tuple[asyncio.StreamReader, asyncio.StreamWriter]:
    reader, writer = await _silent_connection(port)
    writer.write(b"GET /sub/big HTTP/1.0\r\nHost: relay\r\nAccept: text/event-stream\r\n\r\n")
    return reader, writer


async def _websocket(port: int) -> tuple[asyncio.StreamReader, asyncio.StreamWriter]:
    reader, writer = await _silent_connection(port)
    key = base64.b64encode(os.urandom(16)).decode()
    writer.write(
        (
            "GET /sub/big HTTP/1.1\r\nHost: relay\r\nUpgrade: websocket\r\n"
            f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\n"
            "Sec-WebSocket-Version: 13\r\n\r\n"
        ).encode()
    )
    return reader, writer


async def _next_eventsource(reader: asyncio.StreamReader) -> int | str | None:
    """The next message's number, a `closed` event's reason, or None for anything else."""
    event = await reader.readuntil(b"\n\n")
    if event.startswith(b"event: closed"):
        return json.loads(event.split(b"data: ", 1)[1])["reason"]
    found = _NUMBER.search(event[:200])
    return None if found is None else int(found[1])


async def _next_websocket(reader: asyncio.StreamReader) -> int | str | None:
    """The same for a WebSocket frame: a text frame's number, a close frame's reason."""
    first, second = await reader.readexactly(2)
    length = second & 0x7F
    if length == 126:
        (length,) = struct.unpack("!H", await reader.readexactly(2))
    elif length == 127:
        (length,) = struct.unpack("!Q", await reader.readexactly(8))
    payload = await reader.readexactly(length)
    if first & 0x0F == 0x8:
        return payload[2:].decode()
    return int(_NUMBER.match(payload)[1]) if first & 0x0F == 0x1 else None


async def _outcome(
    reader: asyncio.StreamReader, next_event: Callable[[asyncio.StreamReader], Awaitable]
) -> tuple[list[int], str | None]:
    """The message numbers a client was sent, and the reason it was closed with (None: none)."""
    await reader.readuntil(b"\r\n\r\n")  # the response's or the handshake's headers
    numbers: list[int] = []
    while len(numbers) < BACKLOG:
        try:
            event = await next_event(reader)
        except asyncio.IncompleteReadError:
            return numbers, None
        if isinstance(event, str):
            return numbers, event
        if event is not None:
            numbers.append(event)
    return numbers, None


async def _publish_backlog(base: str) -> None:
    token = TokenAuthority(SECRET.encode(), "public-").issue("test", [], 600, server=True)
    headers = {"Authorization": f"Bearer {token}", "Content-Type": "application/json"}
    async with aiohttp.ClientSession() as session:
        for n in range(BACKLOG):
            body = json.dumps([n, "x" * (MESSAGE - 16)])
            async with session.post(f"{base}/pub/big", data=body, headers=headers) as response:
                assert response.status in (201, 202), await response.text()
        # One reader of each kind takes the whole backlog: code paths warm, nothing left over.
        async with session.get(f"{base}/sub/big", headers={"Accept": "text/event-stream"}) as r:
            for _ in range(BACKLOG):
                await r.content.readuntil(b"\n\n")
        async with session.ws_connect(f"{base}/sub/big") as ws:
            for _ in range(BACKLOG):
                await ws.receive()


async def _settled_peak(server: RelayProcess) -> int:
    """Sample the server's RSS until it has stopped growing; the highest sample."""
    peak, steady, deadline = server.rss, 0, time.monotonic() + SETTLE_S
    while steady < 8 and time.monotonic() < deadline:
        await asyncio.sleep(0.25)
        rss = server.rss
        steady = steady + 1 if rss <= peak + 256 * 1024 else 0
        peak = max(peak, rss)
    return peak


@pytest.mark.parametrize("backend", ["memory", "redis"])
async def test_readers_that_never_read_hold_bounded_memory(
    backend: str, request: pytest.FixtureRequest
) -> None:
    redis_url = request.getfixturevalue("redis_url") if backend == "redis" else None
    with RelayProcess(redis_url) as server:
        await _publish_backlog(f"http://127.0.0.1:{server.port}")
        await asyncio.sleep(1.0)
        baseline = server.rss
        eventsource = [await _eventsource(server.port) for _ in range(READERS)]
        websockets = [await _websocket(server.port) for _ in range(READERS)]
        peak = await _settled_peak(server)
        growth = peak - baseline
        print(f"{backend}: RSS {baseline / 2**20:.0f} MB -> peak {peak / 2**20:.0f} MB")
        assert growth < BOUND, f"RSS grew by {growth / 2**20:.0f} MB"

        outcomes = await asyncio.wait_for(
            asyncio.gather(
                *(_outcome(reader, _next_eventsource) for reader, _ in eventsource),
                *(_outcome(reader, _next_websocket) for reader, _ in websockets),
            ),
            READ_S,
        )
        for numbers, reason in outcomes:
            assert numbers == list(range(len(numbers)))  # in order, none missing
            assert len(numbers) == BACKLOG or reason, (len(numbers), reason)
        served = sum(len(numbers) == BACKLOG for numbers, _ in outcomes)
        print(f"{backend}: {served} of {len(outcomes)} served in full, the others closed")
        for _, writer in eventsource + websockets:
            writer.close()

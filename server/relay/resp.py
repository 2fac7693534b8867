"""A lean Redis connection for the relay's two hot round trips: publishing and reading the news.

redis-py's asyncio client costs about 90-120 us of CPU per round trip on these machines (the
pool's checkout and health check, a timeout context and a coroutine per reply, its Python-side
reply callbacks), against about 25-30 us for the same bytes through a bare asyncio protocol
(most of which is the two system calls). Under the relay's 1,000 x 2 pairs load a replica makes
one publish pipeline and one news read for every 10-20 messages, and those round trips were the
larger part of what the Redis backend cost beyond the memory backend. So these two paths talk
to Redis through `Connection`: commands packed by hiredis in one piece and written with one
write, replies parsed by hiredis as the bytes arrive and handed to their waiters from
`data_received`, in order, with no coroutine per reply. Everything else the backend asks of
Redis (positions, backlog pages, counts, heartbeats) is rare and stays on redis-py.

What the connection guarantees, which the batcher and the reader rely on:

1. Replies come back to the requests in the order the requests were written; an error reply
   (a Redis `-ERR ...`) is returned in its place as a `ResponseError`, not raised.
2. Nothing is ever written twice. If the connection fails, every request whose reply had not
   arrived gets `ConnectionError`; the connection is then closed for good, and its owner opens
   a new one for later requests.
3. `round_trip` waits at most `timeout` seconds for all of its replies, then fails the
   connection as in 2 (a reply that came late would belong to nobody).

URLs are read as redis-py reads them (`redis://[[user]:password@]host[:port][/db]`,
`rediss://` for TLS with the system's default certificate checks, `unix://path?db=N`); the
connection authenticates and selects its database once, when it opens.
"""

from __future__ import annotations

import asyncio
import socket
import ssl
from collections import deque
from typing import Any

import hiredis
from redis.asyncio.connection import parse_url
from redis.exceptions import ConnectionError as RedisConnectionError
from redis.exceptions import InvalidResponse, ResponseError
from redis.exceptions import TimeoutError as RedisTimeoutError

DEFAULT_PORT = 6379


def pack(*command: Any) -> bytes:
    """One command in Redis' wire format (hiredis does the packing, in C)."""
    return hiredis.pack_command(command)


class _Protocol(asyncio.Protocol):
    """Feeds the socket's bytes to hiredis and each complete reply to the oldest waiter."""

    def __init__(self) -> None:
        self.parser = hiredis.Reader(protocolError=InvalidResponse, replyError=ResponseError)
        self.waiters: deque[asyncio.Future[Any]] = deque()
        self.transport: asyncio.Transport | None = None
        self.lost: Exception | None = None

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self.transport = transport

    def data_received(self, data: bytes) -> None:
        self.parser.feed(data)
        waiters = self.waiters
        try:
            while (reply := self.parser.gets()) is not False:
                if not waiters:  # a reply nobody asked for: the stream is out of step
                    raise InvalidResponse("Redis sent a reply that no request was waiting for")
                waiter = waiters.popleft()
                if not waiter.done():
                    waiter.set_result(reply)
        except InvalidResponse as error:
            self.fail(error)

    def connection_lost(self, exc: Exception | None) -> None:
        self.fail(RedisConnectionError(f"connection to Redis lost ({exc or 'closed by Redis'})"))

    def fail(self, error: Exception) -> None:
        """Fail every waiting request and close: nothing more is read or written (guarantee 2)."""
        if self.lost is None:
            self.lost = error
        while self.waiters:
            waiter = self.waiters.popleft()
            if not waiter.done():
                waiter.set_exception(self.lost)
        if self.transport is not None:
            self.transport.abort()


class Connection:
    """One connection to Redis; see the module docstring for what it guarantees."""

    def __init__(self, protocol: _Protocol) -> None:
        self._protocol = protocol

    @classmethod
    async def open(cls, url: str, timeout: float) -> Connection:
        """Connect, authenticate and select the URL's database, within `timeout` seconds."""
        options = parse_url(url)
        loop = asyncio.get_running_loop()
        try:
            async with asyncio.timeout(timeout):
                if "path" in options:
                    _, protocol = await loop.create_unix_connection(_Protocol, options["path"])
                else:
                    tls = ssl.create_default_context() if url.startswith("rediss:") else None
                    _, protocol = await loop.create_connection(
                        _Protocol,
                        options.get("host", "localhost"),
                        options.get("port", DEFAULT_PORT),
                        ssl=tls,
                    )
                    sock = protocol.transport.get_extra_info("socket")
                    sock.setsockopt(socket.SOL_SOCKET, socket.SO_KEEPALIVE, 1)
                connection = cls(protocol)
                await connection._hello(options)
        except TimeoutError:
            raise RedisTimeoutError(f"no connection to Redis within {timeout} s") from None
        except OSError as error:
            raise RedisConnectionError(f"cannot connect to Redis ({error})") from None
        return connection

    async def _hello(self, options: dict[str, Any]) -> None:
        setup = []
        if "password" in options:
            auth = ("AUTH", options["username"]) if "username" in options else ("AUTH",)
            setup.append(pack(*auth, options["password"]))
        if options.get("db"):
            setup.append(pack("SELECT", options["db"]))
        for reply in self.send(b"".join(setup), len(setup)):
            answer = await reply
            if isinstance(answer, ResponseError):
                self.close()
                raise RedisConnectionError(f"Redis refused the connection's set-up: {answer}")

    @property
    def closed(self) -> bool:
        return self._protocol.lost is not None

    def send(self, packed: bytes, count: int) -> list[asyncio.Future[Any]]:
        """Write `packed` (`count` commands) at once; a future per reply, in order."""
        protocol = self._protocol
        loop = asyncio.get_running_loop()
        replies = [loop.create_future() for _ in range(count)]
        if protocol.lost is not None:
            for reply in replies:
                reply.set_exception(protocol.lost)
            return replies
        protocol.waiters.extend(replies)
        assert protocol.transport is not None
        protocol.transport.write(packed)
        return replies

    async def round_trip(self, packed: bytes, count: int, timeout: float) -> list[Any]:
        """The replies of `count` packed commands, in order: each reply, error reply or, from
        the first one missing on, the exception that failed the connection (guarantees 1-3)."""
        replies = self.send(packed, count)
        if not replies:
            return []
        deadline = asyncio.get_running_loop().call_later(timeout, self._expire, timeout)
        try:
            await replies[-1]  # replies come in order: the last one done, all are
        except (RedisConnectionError, RedisTimeoutError, InvalidResponse):
            pass  # each reply says what became of it
        finally:
            deadline.cancel()
        return [reply.exception() or reply.result() for reply in replies]

    def _expire(self, timeout: float) -> None:
        self._protocol.fail(RedisTimeoutError(f"Redis did not answer within {timeout} s"))

    def close(self) -> None:
        """Close at once; requests still waiting get ConnectionError."""
        self._protocol.fail(RedisConnectionError("connection closed"))

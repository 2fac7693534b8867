"""Lean clients for bench/relay.py's load generator: WebSocket subscribers and HTTP publishers
on bare asyncio protocols.

Through aiohttp's client the load generator spent about as much CPU per delivered message as
the relay server itself (120-130 us in the 1,000 x 2 pairs phase: one POST and two WebSocket
receives per message) and ran 93-95% busy on one of the machine's two cores. So the benchmark
measured its own client nearly as much as the server; on Redis targets a third busy process,
redis-server, had to take its CPU from those two. These clients do only what the benchmark
needs, in a few microseconds per message:

- `Subscriber`: one WebSocket (RFC 6455) reading a channel. Each data frame's payload goes to
  a callback; pings are answered; nothing is compressed (no extension is offered).
- `Publishers`: keep-alive HTTP/1.1 connections, one request at a time on each, made as
  needed and reused; a response with `Connection: close` retires its connection.

Neither follows redirects, retries, or keeps anything but what the benchmark reads (the
status). A server that breaks the protocol fails the call with `ProtocolError`.
"""

from __future__ import annotations

import asyncio
import base64
import hashlib
import os
from collections.abc import Callable

WEBSOCKET_GUID = b"258EAFA5-E914-47DA-95CA-C5AB0DC85B11"
HEAD_END = b"\r\n\r\n"
CONTINUATION, TEXT, BINARY, CLOSE, PING, PONG = 0x0, 0x1, 0x2, 0x8, 0x9, 0xA
CHUNKED_END = b"0\r\n\r\n"  # a chunked body ends with an empty chunk and no trailers


class ProtocolError(Exception):
    """The server answered something this client does not understand."""


def _masked_frame(opcode: int, payload: bytes) -> bytes:
    """A client frame (clients mask theirs); only short control frames are ever sent."""
    mask = os.urandom(4)
    body = bytes(byte ^ mask[i % 4] for i, byte in enumerate(payload))
    return bytes((0x80 | opcode, 0x80 | len(payload))) + mask + body


def _headers(head: bytes) -> dict[bytes, bytes]:
    """A response head's header fields, names in lower case (the status line left out)."""
    fields = {}
    for line in head.split(b"\r\n")[1:]:
        key, _, value = line.partition(b":")
        fields[key.strip().lower()] = value.strip()
    return fields


class Subscriber(asyncio.Protocol):
    """A WebSocket subscriber; `await Subscriber.open(...)` returns once it is upgraded."""

    def __init__(self, request: bytes, accept: bytes, on_message: Callable[[bytes], None]):
        self._request = request
        self._accept = accept
        self._on_message = on_message
        self._buffer = bytearray()
        self._fragments = bytearray()
        self._transport: asyncio.Transport | None = None
        self.upgraded: asyncio.Future[None] = asyncio.get_running_loop().create_future()

    @classmethod
    async def open(
        cls, host: str, port: int, path: str, on_message: Callable[[bytes], None]
    ) -> Subscriber:
        key = base64.b64encode(os.urandom(16))
        accept = base64.b64encode(hashlib.sha1(key + WEBSOCKET_GUID).digest())
        request = (
            (
                f"GET {path} HTTP/1.1\r\nHost: {host}:{port}\r\nUpgrade: websocket\r\n"
                "Connection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
            ).encode()
            + b"Sec-WebSocket-Key: "
            + key
            + HEAD_END
        )
        loop = asyncio.get_running_loop()
        _, subscriber = await loop.create_connection(
            lambda: cls(request, accept, on_message), host, port
        )
        try:
            await subscriber.upgraded
        except BaseException:
            subscriber.close()
            raise
        return subscriber

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self._transport = transport
        transport.write(self._request)

    def connection_lost(self, exc: Exception | None) -> None:
        if not self.upgraded.done():
            self.upgraded.set_exception(ConnectionError(f"closed before the upgrade ({exc})"))

    def data_received(self, data: bytes) -> None:
        self._buffer += data
        if not self.upgraded.done() and not self._read_head():
            return
        try:
            self._read_frames()
        except ProtocolError:
            self.close()

    def _read_head(self) -> bool:
        end = self._buffer.find(HEAD_END)
        if end < 0:
            return False
        head = bytes(self._buffer[:end])
        del self._buffer[: end + len(HEAD_END)]
        accepted = _headers(head).get(b"sec-websocket-accept") == self._accept
        if not head.startswith(b"HTTP/1.1 101") or not accepted:
            self.upgraded.set_exception(ProtocolError(head.split(b"\r\n", 1)[0].decode()))
            self.close()
            return False
        self.upgraded.set_result(None)
        return True

    def _read_frames(self) -> None:
        buffer = self._buffer
        while len(buffer) >= 2:
            first, second = buffer[0], buffer[1]
            if second & 0x80:
                raise ProtocolError("a server frame was masked")
            length, start = second & 0x7F, 2
            if length >= 126:
                start = 4 if length == 126 else 10
                if len(buffer) < start:
                    return
                length = int.from_bytes(buffer[2:start], "big")
            if len(buffer) < start + length:
                return
            payload = bytes(buffer[start : start + length])
            del buffer[: start + length]
            self._frame(first & 0x80 != 0, first & 0x0F, payload)

    def _frame(self, final: bool, opcode: int, payload: bytes) -> None:
        if opcode in (TEXT, BINARY, CONTINUATION):
            if final and not self._fragments:
                self._on_message(payload)
            elif final:
                self._on_message(bytes(self._fragments) + payload)
                self._fragments.clear()
            else:
                self._fragments += payload
        elif opcode == PING:
            self._send(PONG, payload)
        elif opcode == CLOSE:
            self._send(CLOSE, payload[:2])
            self.close()

    def _send(self, opcode: int, payload: bytes) -> None:
        if self._transport is not None and not self._transport.is_closing():
            self._transport.write(_masked_frame(opcode, payload))

    def close(self) -> None:
        """Say goodbye (close code 1000) and close the connection."""
        if self._transport is not None and not self._transport.is_closing():
            if self.upgraded.done() and not self.upgraded.exception():
                self._send(CLOSE, (1000).to_bytes(2, "big"))
            self._transport.close()


class _Exchange(asyncio.Protocol):
    """One keep-alive HTTP/1.1 connection; `request` sends one and waits for its status."""

    def __init__(self) -> None:
        self._transport: asyncio.Transport | None = None
        self._buffer = bytearray()
        self._head: bytes | None = None
        self._body_end = -1  # Content-Length's end of the body; -1 chunked
        self._reply: asyncio.Future[int] | None = None
        self.closed = False
        self.retire = False  # the server said it closes the connection after this response

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self._transport = transport

    def connection_lost(self, exc: Exception | None) -> None:
        self.closed = True
        if self._reply is not None and not self._reply.done():
            self._reply.set_exception(ConnectionError(f"connection lost ({exc})"))

    async def request(self, packed: bytes) -> int:
        assert self._transport is not None and self._reply is None
        self._reply = asyncio.get_running_loop().create_future()
        self._transport.write(packed)
        try:
            return await self._reply
        finally:
            self._reply = None

    def data_received(self, data: bytes) -> None:
        self._buffer += data
        try:
            status = self._response()
        except (ProtocolError, ValueError) as error:
            self.closed = True
            assert self._transport is not None
            self._transport.close()
            if self._reply is not None and not self._reply.done():
                self._reply.set_exception(ProtocolError(str(error)))
            return
        if status is not None and self._reply is not None and not self._reply.done():
            self._reply.set_result(status)

    def _response(self) -> int | None:
        """The status once the whole response is in (then the buffer is emptied of it)."""
        buffer = self._buffer
        if self._head is None:
            end = buffer.find(HEAD_END)
            if end < 0:
                return None
            self._head = bytes(buffer[:end])
            del buffer[: end + len(HEAD_END)]
            headers = _headers(self._head)
            length = headers.get(b"content-length")
            chunked = headers.get(b"transfer-encoding") == b"chunked"
            if length is None and not chunked:
                raise ProtocolError("a response with neither Content-Length nor chunks")
            self._body_end = -1 if chunked else int(length or 0)
            self.retire = headers.get(b"connection") == b"close"
        if self._body_end >= 0:
            if len(buffer) < self._body_end:
                return None
            del buffer[: self._body_end]
        else:
            end = buffer.find(CHUNKED_END)
            if end < 0:
                return None
            del buffer[: end + len(CHUNKED_END)]
        status = int(self._head[9:12])
        self._head = None
        return status

    def close(self) -> None:
        self.closed = True
        if self._transport is not None:
            self._transport.close()


class Publishers:
    """POSTs over a pool of keep-alive connections: as many as there are requests at once."""

    def __init__(self, host: str, port: int, headers: dict[str, str]) -> None:
        self._host = host
        self._port = port
        fixed = "".join(f"{name}: {value}\r\n" for name, value in headers.items())
        self._fixed = f"Host: {host}:{port}\r\n{fixed}"
        self._idle: list[_Exchange] = []

    async def post(self, path: str, body: bytes) -> int:
        """The response's status code."""
        packed = (
            f"POST {path} HTTP/1.1\r\n{self._fixed}Content-Length: {len(body)}\r\n\r\n".encode()
            + body
        )
        exchange = self._idle.pop() if self._idle else None
        while exchange is not None and exchange.closed:
            exchange = self._idle.pop() if self._idle else None
        if exchange is None:
            _, exchange = await asyncio.get_running_loop().create_connection(
                _Exchange, self._host, self._port
            )
        status = await exchange.request(packed)
        if exchange.retire:
            exchange.close()
        else:
            self._idle.append(exchange)
        return status

    def close(self) -> None:
        for exchange in self._idle:
            exchange.close()
        self._idle.clear()

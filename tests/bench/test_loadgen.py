"""bench/loadgen.py's lean clients, held against aiohttp's server and the relay itself.

The relay benchmark's figures are only as true as its clients: a frame parsed wrongly would
count a delivery that never came (or lose one), a response read wrongly would leave a
keep-alive connection out of step. So each path the clients take is exercised here against a
real server: the three WebSocket length encodings, a fragmented message, a ping, a close, a
refused upgrade; Content-Length and chunked responses, and a response that closes its
connection.
"""

from __future__ import annotations

import asyncio
import importlib.util
import json
from collections.abc import AsyncIterator
from pathlib import Path

import pytest
from aiohttp import web
from aiohttp.test_utils import TestServer

from tests.relay.conftest import StartRelay, wait_subscribers

_PATH = Path(__file__).resolve().parents[2] / "bench" / "loadgen.py"
_SPEC = importlib.util.spec_from_file_location("loadgen", _PATH)
assert _SPEC is not None and _SPEC.loader is not None
loadgen = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(loadgen)

WAIT_S = 10.0
CONNECTIONS = web.AppKey("connections", set[object])
SIZES = (5, 125, 126, 4_000, 65_535, 65_536, 70_000)  # each WebSocket length encoding's edges


async def _collected(received: list[bytes], count: int) -> list[bytes]:
    async with asyncio.timeout(WAIT_S):
        while len(received) < count:
            await asyncio.sleep(0.01)
    return received


async def _websocket(request: web.Request) -> web.WebSocketResponse:
    """Sends each length of SIZES, one message in three fragments, pings, and closes."""
    ws = web.WebSocketResponse(autoping=False)
    await ws.prepare(request)
    for size in SIZES:
        await ws.send_bytes(bytes([size % 251]) * size)
    # aiohttp sends no fragments of its own: a text message in three frames, written raw
    # (first frame: FIN clear, opcode text; then continuation; the last one with FIN set).
    assert request.transport is not None
    request.transport.write(b"\x01\x04one \x00\x04two \x80\x05three")
    await ws.ping(b"are you there")
    reply = await ws.receive()
    await ws.send_str(f"{reply.type.name} {reply.data.decode()}")
    await ws.close(code=1000)
    return ws


@pytest.fixture
async def plain_server() -> AsyncIterator[TestServer]:
    """An aiohttp server with the WebSocket above and three ways to answer a POST."""

    async def closing(request: web.Request) -> web.Response:
        await request.read()
        response = web.Response(status=201, text="bye")
        response.force_close()
        return response

    async def chunked(request: web.Request) -> web.StreamResponse:
        await request.read()
        response = web.StreamResponse(status=202)
        response.enable_chunked_encoding()
        await response.prepare(request)
        await response.write(b"first ")
        await response.write(b"second")
        await response.write_eof()
        return response

    async def echo_length(request: web.Request) -> web.Response:
        return web.Response(status=200, text=str(len(await request.read())))

    connections: set[object] = set()

    @web.middleware
    async def count(request: web.Request, handler):  # type: ignore[no-untyped-def]
        connections.add(request.transport)
        return await handler(request)

    app = web.Application(middlewares=[count])
    app[CONNECTIONS] = connections
    app.router.add_get("/ws", _websocket)
    app.router.add_post("/closing", closing)
    app.router.add_post("/chunked", chunked)
    app.router.add_post("/length", echo_length)
    server = TestServer(app, host="127.0.0.1")
    await server.start_server()
    yield server
    await server.close()


async def test_subscriber_reads_every_length_fragments_pings_and_closes(
    plain_server: TestServer,
) -> None:
    received: list[bytes] = []
    subscriber = await loadgen.Subscriber.open(
        "127.0.0.1", plain_server.port, "/ws", received.append
    )
    expected = [bytes([size % 251]) * size for size in SIZES]
    expected += [b"one two three", b"PONG are you there"]
    assert await _collected(received, len(expected)) == expected
    async with asyncio.timeout(WAIT_S):
        while not subscriber._transport.is_closing():  # the server's close was answered
            await asyncio.sleep(0.01)


async def test_subscriber_refused_upgrade_raises(plain_server: TestServer) -> None:
    with pytest.raises(loadgen.ProtocolError, match="404"):
        await loadgen.Subscriber.open("127.0.0.1", plain_server.port, "/nowhere", print)


async def test_publishers_read_each_response_shape_and_reuse_connections(
    plain_server: TestServer,
) -> None:
    publishers = loadgen.Publishers("127.0.0.1", plain_server.port, {"X-Test": "1"})
    connections = plain_server.app[CONNECTIONS]
    try:
        for size in (0, 10, 5_000):
            assert await publishers.post("/length", b"x" * size) == 200
        assert len(connections) == 1  # one request at a time: one keep-alive connection
        assert await publishers.post("/chunked", b"{}") == 202
        assert await publishers.post("/length", b"after chunks") == 200
        assert len(connections) == 1  # the chunked body was read to its end
        assert await publishers.post("/closing", b"{}") == 201
        assert await publishers.post("/length", b"{}") == 200
        assert len(connections) == 2  # `Connection: close` retired the first one
        statuses = await asyncio.gather(*(publishers.post("/length", b"{}") for _ in range(5)))
        assert statuses == [200] * 5
        assert len(connections) == 6  # five at once: four more connections
    finally:
        publishers.close()


async def test_subscriber_counts_relay_deliveries(start_relay: StartRelay) -> None:
    """Against the relay on each backend, as bench/relay.py uses them."""
    harness = await start_relay()
    port = harness.client.server.port
    assert port is not None
    received: list[bytes] = []
    subscriber = await loadgen.Subscriber.open("127.0.0.1", port, "/sub/bench", received.append)
    await wait_subscribers(harness, "bench", 1)  # the handshake can finish before it counts
    headers = {"Content-Type": "application/json", **harness.auth("bench")}
    publishers = loadgen.Publishers("127.0.0.1", port, headers)
    bodies = [json.dumps({"n": n, "pad": "x" * 200 * n}).encode() for n in range(5)]
    try:
        for body in bodies:
            assert await publishers.post("/pub/bench", body) == 201
        assert await _collected(received, len(bodies)) == bodies
        assert await publishers.post("/pub/bench", b"{not json") == 400
    finally:
        subscriber.close()
        publishers.close()

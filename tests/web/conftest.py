"""A test client for an app made of some of the server's mounts (web pages, diagrams)."""

from __future__ import annotations

from collections.abc import AsyncIterator, Awaitable, Callable

import pytest
from aiohttp import web
from aiohttp.test_utils import TestClient, TestServer

Mount = Callable[[web.Application], None]


@pytest.fixture
async def serve() -> AsyncIterator[Callable[[Mount], Awaitable[TestClient]]]:
    """serve(mount) -> a started client of an app with just that mount."""
    clients: list[TestClient] = []

    async def serve_(mount: Mount) -> TestClient:
        app = web.Application()
        mount(app)
        client = TestClient(TestServer(app))
        await client.start_server()
        clients.append(client)
        return client

    yield serve_
    for client in clients:
        await client.close()

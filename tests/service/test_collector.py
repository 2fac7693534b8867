"""server.http.collector: the started application's heap is frozen; what is made later is still
collected (a closed connection's cycles must be freed)."""

from __future__ import annotations

import gc
import weakref

from aiohttp.test_utils import TestClient, TestServer

from server.http import collector
from server.http.app import create_app


class Cycle:
    """An object that refers to itself, as a connection's transport and protocol do."""

    def __init__(self) -> None:
        self.me = self


def tracked(thing: object) -> bool:
    """`thing` is visited by collections (frozen objects are not)."""
    return any(other is thing for other in gc.get_objects())


async def test_started_heap_is_frozen_and_later_cycles_are_freed() -> None:
    app = create_app()
    collector.install(app)
    assert tracked(app)
    try:
        async with TestClient(TestServer(app)) as client:
            assert not tracked(app)
            response = await client.get("/pub/table-1")  # a request after startup
            assert response.status < 500
            cycle = Cycle()
            freed = weakref.ref(cycle)
            assert tracked(cycle)
            del cycle
            gc.collect()
            assert freed() is None
    finally:
        gc.unfreeze()

"""Background loops that live exactly as long as the service (lobby batching, shot clock)."""

from __future__ import annotations

import asyncio
import contextlib
from collections.abc import AsyncIterator, Awaitable, Callable


@contextlib.asynccontextmanager
async def running(loop: Callable[[], Awaitable[None]]) -> AsyncIterator[None]:
    """Run `loop()` as a task while the context is open; cancel it on the way out."""
    task = asyncio.create_task(loop())
    try:
        yield
    finally:
        # Cancel until it ends: a library call racing a timeout can swallow one cancellation
        # (seen with the table expiry sweep's first storage call), and the loop would go on.
        while not task.done():
            task.cancel()
            await asyncio.wait({task}, timeout=1.0)
        with contextlib.suppress(asyncio.CancelledError):
            await task

"""The server's garbage-collector policy, installed by `billiards serve`: `install(app)`.

CPython's cyclic collector stops the event loop for a full collection over every tracked object
whenever enough objects have survived into its oldest generation; every connection waits that
long. In bench/relay.py a full collection of the server took 212-405 ms with 2,000 WebSocket
subscribers (some 245,000 tracked objects), and one such pause in a 4 s paced run decided the
p99 latency; the Redis backend allocates more per message, so its full collections came
sooner.

A good part of that heap is the application itself: its modules, pydantic schemas, routes,
the worker pool, set up at startup and alive as long as the process. Measured on the
relay's application (`bench/relay.py`'s, in memory) once started: 67,935 tracked objects, and
one full collection of them alone took 131-195 ms (median of 5, load average 2.2-2.8 on
2 cores); frozen, 0 ms. So once the application has started, `gc.collect()` and then
`gc.freeze()` move what is alive then to the permanent generation, which no collection visits.
Only what survived a full collection is frozen, so no garbage is kept.

What is created later is left to the collector: connections' objects refer to each other in
cycles (transport and protocol, a handler's task and its frames), so a frozen connection would
never be freed after it closed. The thresholds stay CPython's own: a larger young generation
(10,000, 10, 100) made full collections rarer but young collections paused up to 94-121 ms and
middle ones up to 400-588 ms, and it left about 550,000 tracked objects at the end of a
benchmark run instead of 160,000 (the cycles of closed connections waiting for a full
collection), so it was not kept.

The game service runs in the same process and follows the same policy; its simulation runs
in worker processes (started by a fork server), which keep CPython's defaults.
"""

from __future__ import annotations

import gc

from aiohttp import web


def install(app: web.Application) -> None:
    """Freeze the started application's heap once `app` has started (after every startup
    hook and cleanup context registered before this call)."""
    app.on_startup.append(_freeze_startup_heap)


async def _freeze_startup_heap(app: web.Application) -> None:
    gc.collect()
    gc.freeze()

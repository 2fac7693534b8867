"""Expiry: finished and abandoned tables leave the live store, so a long-running server's
storage and relay hold the recent tables, not every table ever played.

Every `SWEEP` seconds each process asks the storage to drop the tables whose `expires` has
passed (storage invariant 12: a finished table `tables.KEEP_FINISHED` after its last change, an
unfinished one nobody changes `tables.KEEP_IDLE`), with their inputs and heartbeats, and then
deletes their relay channels (buffer and bookkeeping; a subscriber still there is told the
channel was deleted). What stays for good is in the replay store: every rack's replay (and so
its record), the breaks and the ratings. The same sweep deletes the guests who were last seen
`identity.GUEST_KEPT` ago and never played a rated match (invariant 15): a server that anyone
can register on would otherwise keep every name ever made. A `GET` of an expired table
answers 404. Replicas may sweep at once: the storage drops each table once, and deleting a
channel twice is harmless.
"""

from __future__ import annotations

import asyncio
import logging
import time
from collections.abc import Callable
from contextlib import AbstractAsyncContextManager

from server.game.background import running
from server.game.identity import GUEST_KEPT
from server.game.publisher import Publisher
from server.protocol.ids import table_channel
from server.storage import Storage

log = logging.getLogger(__name__)

#: Seconds between two sweeps.
SWEEP = 60.0
#: Most tables dropped per storage call (a sweep repeats the call until fewer come back).
BATCH = 100


async def sweep(storage: Storage, publisher: Publisher, now: float) -> list[str]:
    """Drop every table expired at `now` and its channel, then the guests unused since
    `now - GUEST_KEPT`; the ids of the tables dropped."""
    dropped: list[str] = []
    while True:
        ids = await storage.expire_tables(now, BATCH)
        for table_id in ids:
            await publisher.delete(table_channel(table_id))
        dropped += ids
        if len(ids) < BATCH:
            break
    while len(await storage.expire_players(now - GUEST_KEPT, BATCH)) == BATCH:
        pass
    return dropped


def running_expiry(
    storage: Storage, publisher: Publisher, forget: Callable[[str], None]
) -> AbstractAsyncContextManager[None]:
    """Sweep expired tables while the context is open; `forget(table_id)` drops what this
    process keeps about each one dropped."""

    async def loop() -> None:
        while True:
            try:
                for table_id in await sweep(storage, publisher, time.time()):
                    forget(table_id)
            except Exception:  # storage or relay trouble: the next sweep tries again
                log.exception("table expiry sweep failed")
            await asyncio.sleep(SWEEP)

    return running(loop)

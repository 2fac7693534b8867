"""The shot clock: a seat that has not had an input accepted by its deadline loses the shot.

Every stored change of a table with a clock restarts it for the seat then to act
(`tables.next_deadline`): deadlines are wall-clock times stored with the table, so every
replica sees them and a restart neither pauses nor extends a running clock; a deadline that
passed while the server was down is ruled as soon as it is back. Each process looks for due
tables every `TICK` seconds and tells their actors `ClockExpiry`: the actor plays the timeout
input (`refereeing.timeout_input`, a dead-slow stroke that hits no ball, or the first option of
a pending choice) through the ordinary match path, under the input id `clock:<version>` (an id
no client can send: server/game/commands.py), so the referee rules it as each game's rules rule a
shot that hits nothing (pool and snooker: a foul, three-cushion: the turn passes) and the
record holds it like any input. There is no warning first; clients show the deadline from
`next.deadline`.
"""

from __future__ import annotations

import asyncio
import logging
import time
from contextlib import AbstractAsyncContextManager

from server.game.actor import Matches
from server.game.background import running
from server.game.commands import ClockExpiry
from server.storage import Storage

log = logging.getLogger(__name__)

#: Seconds between two looks for tables whose clock ran out.
TICK = 0.5
#: Most tables ruled per look.
BATCH = 200


def running_clock(storage: Storage, matches: Matches) -> AbstractAsyncContextManager[None]:
    """Rule expired shot clocks while the context is open."""

    async def tick() -> None:
        while True:
            try:
                for table_id in await storage.due_tables(time.time(), BATCH):
                    matches.owner(table_id).tell(ClockExpiry())
            except Exception:  # storage trouble: the next tick tries again
                log.exception("shot clock tick failed")
            await asyncio.sleep(TICK)

    return running(tick)

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
#: Most tables ruled per look (besides those waiting to be told again, below).
BATCH = 200
#: Longest wait (s) before a table still due is told again. A table is told at once when it
#: falls due, then after TICK, 2 TICK, 4 TICK ... while it stays due: one whose clock input
#: fails (a bug) costs a look now and then, and the oldest deadlines, which `due_tables`
#: answers first, cannot hide the others' (before, 200 such tables stopped every clock).
RETRY_MAX = 60.0


def running_clock(storage: Storage, matches: Matches) -> AbstractAsyncContextManager[None]:
    """Rule expired shot clocks while the context is open."""

    async def tick() -> None:
        retry: dict[str, tuple[float, int]] = {}  # a due table: not told before, times told
        while True:
            try:
                now = time.time()
                waiting = sum(1 for at, _ in retry.values() if at > now)
                due = await storage.due_tables(now, BATCH + waiting)
                retry = {table_id: retry[table_id] for table_id in due if table_id in retry}
                for table_id in due:
                    at, told = retry.get(table_id, (0.0, 0))
                    if at <= now:
                        retry[table_id] = (
                            now + min(RETRY_MAX, TICK * 2 ** min(told, 16)),
                            told + 1,
                        )
                        matches.owner(table_id).tell(ClockExpiry())
            except Exception:  # storage trouble: the next tick tries again
                log.exception("shot clock tick failed")
            await asyncio.sleep(TICK)

    return running(tick)

"""What storing a refereed shot costs: `accept` then `resolve`, through the game's own storage.

    .venv/bin/python bench/storage.py [--racks 12] [--repeat 7]

Plays `--racks` nine-ball racks with the shot pickers first (outside the timing), as the table
actor would: each shot's accepted record, its played record, its input with the outcome and
the outcome's JSON as the worker encodes it (`tables.outcome_json`). Then, on a fresh
database each repeat, stores every shot the way the actor does (`accept` with the input
pending, `resolve` with the outcome) and prints per shot the CPU time of this process (all
its threads: aiosqlite's included) and the wall time, as the median and the minimum over the
repeats. The storage is SQLite, a file in a temporary directory, as `billiards serve` keeps it
by default (and as bench/match_load.py runs it). Racks are drawn from fixed seeds, so every run
stores the same shots.
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import sys
import tempfile
import time
from collections.abc import Awaitable, Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from server.game import refereeing
from server.game.tables import InputEntry, TableRecord, join, new_table, outcome_json, played
from server.protocol.models import PlayerInfo, TableCreate
from server.storage import Storage
from server.storage.sqlite import SqliteStorage

#: One shot as the actor stores it: accepted record, played record, logged input, outcome JSON.
Shot = tuple[TableRecord, TableRecord, InputEntry, bytes]
ADA = PlayerInfo(id="p_ada", name="Ada")
BOB = PlayerInfo(id="p_bob", name="Bob")


def rack(n: int) -> tuple[TableRecord, list[Shot]]:
    """Table `n`, new, and the shots of its first rack played by the pickers."""
    first = join(new_table(f"{n:020x}", TableCreate(game="nineball"), ADA, seed=n), BOB)
    record, shots = first, []
    while record.rack == 1 and record.status.value == "playing":
        action = refereeing.bot_input(record.state, "picker")
        entry = InputEntry(
            shot_id=f"shot{n:06d}x{len(shots):04d}",
            seat=record.state.turn,
            input=action,
            version=record.version,
            rack=record.rack,
            accepted_at=0.0,
        )
        accepted = record.model_copy(update={"pending": entry})
        result = refereeing.referee(record.state, action)
        after, outcome = played(accepted, entry, result)
        logged = entry.model_copy(update={"outcome": outcome})
        shots.append((accepted, after, logged, outcome_json(outcome, result)))
        record = after
    return first, shots


async def store(
    storage: Storage, racks: list[tuple[TableRecord, list[Shot]]]
) -> tuple[float, float]:
    """CPU and wall seconds to accept and resolve every shot of `racks` (tables made first)."""
    for first, _ in racks:
        await storage.create_table(first)
    cpu, wall = time.process_time(), time.perf_counter()
    for _, shots in racks:
        for accepted, after, logged, encoded in shots:
            await storage.accept(accepted)
            if not await storage.resolve(after, logged, encoded):
                raise SystemExit("a resolve was refused: the bench's shots are inconsistent")
    return time.process_time() - cpu, time.perf_counter() - wall


async def measure(
    label: str, opened: Callable[[int], Awaitable[Storage]], racks: list, repeat: int
) -> str:
    shots = sum(len(s) for _, s in racks)
    cpu, wall = [], []
    for i in range(repeat):
        storage = await opened(i)
        c, w = await store(storage, racks)
        await storage.close()
        cpu.append(1e6 * c / shots)
        wall.append(1e6 * w / shots)
        print(f"  {label} repeat {i + 1}/{repeat}: {cpu[-1]:.0f} us CPU a shot", file=sys.stderr)
    return (
        f"| {label:<7} | {shots:5d} | {statistics.median(cpu):6.0f} / {min(cpu):6.0f} "
        f"| {statistics.median(wall):6.0f} / {min(wall):6.0f} |"
    )


async def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--racks", type=int, default=12)
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    racks = [rack(n) for n in range(args.racks)]
    print("| storage | shots | CPU us/shot: median / min | wall us/shot: median / min |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as directory:

        async def sqlite(i: int) -> Storage:
            return await SqliteStorage.open(f"{directory}/bench{i}.sqlite3")

        print(await measure("sqlite", sqlite, racks, args.repeat), flush=True)


if __name__ == "__main__":
    asyncio.run(main())

"""The game service's refereed shots counted in instructions: a figure the machine's speed
does not sway.

    .venv/bin/python bench/match_instructions.py [--tables 8] [--racks 5] [--workers 2]
                                                 [--race-to 1] [--keep FILE]

bench/match_load.py measures the server's CPU time per refereed shot, and on a shared 2-core
machine the same code's figure moves by a fifth between runs (the workers' CPU for the same
physics moves with it): a change worth a few percent cannot be seen in one run. Here the server
runs under valgrind's callgrind (bench/callgrind.py), which counts the instructions its process
executes (user space: the kernel's share of socket reads and writes is not counted), and plays
match_load's load with match_load's clients: `--tables` nine-ball tables at once, one rack
each (a race to one), two players and a spectator per table, the rules' pickers choosing and
every player shooting as soon as it is its turn; each table's players rack a new table when
one ends, `--racks` times. The simulation workers are programs of their own, which callgrind
does not follow: they run at full speed, uncounted (match_load reports their CPU apart).

The counted window starts after a warm-up rack on every table (code paths and caches warm)
and ends when the last counted rack ends; instructions per shot are the window's count, less
what the idle server runs in as long (its timers: the lobby, the shot clock, measured in a
quiet window of `IDLE_SECONDS`, as bench/relay_instructions.py does), over the shots
refereed in it. The tables' seeds are the server's own, so each run plays other racks: the
figure moves with the racks' lengths and breaks (a rack's end and its break cost more than
its other shots); `--racks` more narrows it. `--keep FILE` keeps the window's callgrind
dump, for `callgrind_annotate FILE` (the interpreter's and the libraries' own functions).

`--race-to N` makes each of those tables a match of a race to N racks (the warm-up stays one
rack): a match's own cost (creating and joining its table, its subscriptions, rating it and
recording its result) is then spread over N times as many shots, which, set beside the
default's figure, splits a shot's instructions into the match's share and the shot's own.
"""

from __future__ import annotations

import argparse
import asyncio
import math
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import aiohttp
from callgrind import Callgrind, available
from match_load import SECRET, Pace, Samples, free_port, play_rack, wait_ready

from server.client.api_client import GameClient

IDLE_SECONDS = 5.0
START_TIMEOUT_S = 300.0  # the server imports and starts under valgrind
WATCH_TIMEOUT_S = 120.0  # a spectator's last outcome after its players' (under valgrind)


class Players:
    """One table's two players and spectator, racking table after table."""

    def __init__(self, base: str, session: aiohttp.ClientSession, n: int) -> None:
        self.n = n
        self.players = [GameClient(base, session) for _ in range(2)]
        self.spectator = GameClient(base, session)
        self.racks = 0

    async def register(self) -> None:
        for seat, player in enumerate(self.players):
            await player.register(f"count{self.n}s{seat}r{os.getpid() % 1000}")

    async def play(self, racks: int, samples: Samples, race_to: int = 1) -> None:
        for _ in range(racks):
            watcher = await play_rack(
                self.players, self.spectator, self.racks, samples, Pace(None), math.inf, race_to
            )
            self.racks += 1
            await asyncio.wait_for(watcher, WATCH_TIMEOUT_S)


async def count(
    tables: int, racks: int, workers: int, keep: str | None, race_to: int = 1
) -> tuple[int, float, Samples]:
    """The window's instructions, its idle background and the shots refereed in it (the
    window's dump copied to `keep`)."""
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    with tempfile.TemporaryDirectory(prefix="callgrind-") as directory:
        command = [sys.executable, "-m", "server.cli", "serve", "--port", str(port)]
        command += ["--workers", str(workers), "--db", f"{directory}/load.sqlite3"]
        command += ["--names-per-address", "100000"]
        env = {**os.environ, "BILLIARDS_RELAY_SECRET": SECRET}
        server = Callgrind(command, Path(directory), env)
        try:
            await wait_ready(base, START_TIMEOUT_S)
            timeout = aiohttp.ClientTimeout(total=START_TIMEOUT_S)
            async with aiohttp.ClientSession(timeout=timeout) as session:
                everyone = [Players(base, session, n) for n in range(tables)]
                for players in everyone:
                    await players.register()
                print("  warm-up: a rack on every table", file=sys.stderr)
                await asyncio.gather(*(p.play(1, Samples()) for p in everyone))
                server.zero()
                await asyncio.sleep(IDLE_SECONDS)
                idle_rate = server.dump() / IDLE_SECONDS
                print(f"  counting {tables} x {racks} matches", file=sys.stderr)
                samples = Samples()
                server.zero()
                start = time.monotonic()
                await asyncio.gather(*(p.play(racks, samples, race_to) for p in everyone))
                instructions = server.dump()
                background = idle_rate * (time.monotonic() - start)
                if keep is not None:
                    shutil.copy(server.last_dump, keep)
        finally:
            server.stop()
    return instructions, background, samples


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tables", type=int, default=8, help="tables played at once")
    parser.add_argument(
        "--racks", type=int, default=5, help="matches (at a race to one, racks) counted per table"
    )
    parser.add_argument("--race-to", type=int, default=1, help="racks won to win a match")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--keep", metavar="FILE", help="keep the window's callgrind dump")
    args = parser.parse_args()
    if not available():
        print("valgrind not found: apt-get install -y valgrind", file=sys.stderr)
        return 1
    instructions, background, samples = asyncio.run(
        count(args.tables, args.racks, args.workers, args.keep, args.race_to)
    )
    shots, matches = samples.shots, args.tables * args.racks
    per_shot = (instructions - background) / max(shots, 1)
    print(
        f"{args.tables} tables x {args.racks} nine-ball matches, a race to {args.race_to}, "
        f"{args.workers} workers"
    )
    print(
        f"{'matches':>7} {'shots':>6} {'instructions/shot':>18} {'background/shot':>16} "
        f"{'player p50 ms':>14}"
    )
    median = statistics.median(samples.player_ms) if samples.player_ms else math.nan
    print(
        f"{matches:>7} {shots:>6} {per_shot:>18,.0f} {background / max(shots, 1):>16,.0f} "
        f"{median:>14.0f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())

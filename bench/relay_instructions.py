"""The relay's pairs load counted in instructions: a figure the machine's speed does not sway.

    .venv/bin/python bench/relay_instructions.py [--publishes N] [--targets memory,bare]

bench/relay.py measures CPU time, and on a shared 2-core machine the same code's CPU per
delivery swings by a third between runs (the bare forwarder's pairs figure went from 62 to 97
us within minutes): a change worth a few percent cannot be seen there without many runs. Here
each target's server runs under valgrind's callgrind, which counts the instructions the
process executes (user space: the kernel's share of socket reads and writes is not counted,
and is the same for every target). The load is bench/relay.py's pairs load, scaled down
(valgrind runs a program some 50 times slower): 100 channels with 2 WebSocket subscribers
each, `--publishes` HTTP publishes spread over them, 64 in flight.

For each target: callgrind's counters are zeroed once every subscription is live, the
publishes are made, and the counters are dumped once all are delivered; the instructions of
that window divided by the publishes and by the deliveries are the figures. The relay also
runs the game service, whose timers (the lobby, the shot clock) wake up a few times a second
whether or not anything is published; under valgrind the window lasts seconds, so those
wake-ups would weigh some fifty times what they weigh at full speed. So the server's idle
instructions per second are measured first (a quiet window of `IDLE_SECONDS`) and that rate
times the window's length is taken off ("background").

The same code, the same load and the same interpreter give the same count to within a few
hundredths of a percent (seen here: 205,833 and 205,661 instructions per delivery).
"""

from __future__ import annotations

import argparse
import asyncio
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import relay as wall  # bench/relay.py, beside this file
from callgrind import Callgrind, available

CHANNELS = 100
IDLE_SECONDS = 5.0
START_TIMEOUT_S = 300.0  # the server imports and starts under valgrind


@dataclass(frozen=True)
class Counted:
    """What one target's window cost."""

    publishes: int
    delivered: int
    instructions: int
    background: float  # instructions the idle server would have run in the window

    def per(self, count: int) -> float:
        return (self.instructions - self.background) / max(count, 1)


async def count(kind: str, publishes: int) -> Counted:
    """Start `kind`'s server under callgrind and count one window of the pairs load."""
    wall.CONNECT_TIMEOUT_S = wall.DELIVERY_TIMEOUT_S = START_TIMEOUT_S
    with tempfile.TemporaryDirectory(prefix="callgrind-") as directory:
        port = wall.free_port()
        command = [sys.executable, wall.__file__, "--serve", kind, "--port", str(port)]
        server = Callgrind(command, Path(directory))
        wall.START_TIMEOUT_S = START_TIMEOUT_S
        wall.wait_for_port(port, server.process, kind)
        load = wall.Load(port, wall.FULL)
        try:
            await load.subscribe([f"pair-{i // 2}" for i in range(2 * CHANNELS)])
            await load.saturate(channel_of, CHANNELS, 2)  # every subscription live
            await load.saturate(channel_of, 4 * CHANNELS, 2)  # code paths warm
            server.zero()
            await asyncio.sleep(IDLE_SECONDS)
            idle_rate = server.dump() / IDLE_SECONDS
            load.receiver.reset()
            server.zero()
            start = time.monotonic()
            await load.saturate(channel_of, publishes, 2)
            instructions = server.dump()
            background = idle_rate * (time.monotonic() - start)
            return Counted(publishes, load.receiver.count, instructions, background)
        finally:
            load.close()
            load.publishers.close()
            server.stop()


def channel_of(index: int) -> str:
    return f"pair-{index % CHANNELS}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--publishes", type=int, default=2000, help="publishes counted")
    parser.add_argument("--targets", default="memory,bare", help="memory and/or bare")
    args = parser.parse_args()
    if not available():
        print("valgrind not found: apt-get install -y valgrind", file=sys.stderr)
        return 1
    wall.raise_fd_limit()
    counted: dict[str, Counted] = {}
    for target in args.targets.split(","):
        kind = {"memory": "relay", "bare": "bare"}[target]
        print(f"  {target}: counting {args.publishes} publishes under callgrind", file=sys.stderr)
        counted[target] = asyncio.run(count(kind, args.publishes))
    bare = counted.get("bare")
    print(f"pairs load: {CHANNELS} channels x 2 WebSocket subscribers, {args.publishes} publishes")
    print(
        f"{'target':>8} {'instructions/publish':>21} {'/delivery':>10} {'background':>11} "
        f"{'delivered':>10} {'x bare':>7}"
    )
    for target, got in counted.items():
        per_delivery = got.per(got.delivered)
        ratio = f"{per_delivery / bare.per(bare.delivered):.3f}" if bare else "-"
        print(
            f"{target:>8} {got.per(got.publishes):>21,.0f} {per_delivery:>10,.0f} "
            f"{got.background / got.publishes:>11,.0f} {got.delivered:>10,} {ratio:>7}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())

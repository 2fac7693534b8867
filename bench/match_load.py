"""Load on the game service: N concurrent matches of API clients against one server process.

    .venv/bin/python bench/match_load.py [--matches 16] [--seconds 20] [--workers 2] [--quick]

Starts `billiards serve` (SQLite, `--workers` simulation processes) on a free loopback port,
then plays N nine-ball matches at once with the command-line client's code
(server/client/api_client.py: two players and one spectator per table, the rules' shot
pickers choosing), racking a new table whenever one ends. Two runs: flat out (every player
shoots as soon as it is its turn), then paced at half the refereed rate the first run reached.
Each prints:

- refereed shots per second, in all and per server process (the server and its workers);
- accepted -> outcome delivered (ms, p50 / p99): from the `202 accepted` answer to the outcome
  arriving on the player's and on the spectator's relay WebSocket;
- relay p99 (ms): a probe publishes a timestamped message on its own channel every 20 ms
  through `POST /pub/` and a subscriber times its delivery, beside the matches;
- CPU ms per refereed shot, load-independent where shots/s is not: of the server process, of
  its workers (every process under it: the fork server and the simulation workers), and of
  this process (the clients), from /proc during the run.

The clients run in this process and compete with the server for the same cores; on a shared
machine the figures are noisy. Medians and ratios from one run are the figures to quote.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import socket
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

import aiohttp

from server.client.api_client import GameClient, Refused
from server.game import refereeing
from server.protocol.errors import ErrorCode
from server.protocol.models import OutcomeMessage, Status, TableView
from server.relay.auth import TokenAuthority

SECRET = "match-load-bench-secret-0123456789"
CREATE_WAIT_S = 0.5  # a host refused a new table for its rate waits this long, then asks again


@dataclass
class Samples:
    shots: int = 0
    cpu: tuple[float, float, float] = (0.0, 0.0, 0.0)  # s: server, its workers, the clients
    player_ms: list[float] = field(default_factory=list)
    spectator_ms: list[float] = field(default_factory=list)
    relay_ms: list[float] = field(default_factory=list)
    accepted_at: dict[tuple[str, int], float] = field(default_factory=dict)


class Pace:
    """Spaces shots 1/rate apart across all matches (None: no pacing)."""

    def __init__(self, rate: float | None) -> None:
        self.gap = None if rate is None else 1.0 / rate
        self.next = time.perf_counter()

    async def wait(self) -> None:
        if self.gap is None:
            return
        now = time.perf_counter()
        slot, self.next = max(now, self.next), max(now, self.next) + self.gap
        await asyncio.sleep(slot - now)


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def process_cpu(pid: int) -> float:
    """CPU seconds (user + system) a live process has used so far; 0 once it is gone."""
    try:
        with open(f"/proc/{pid}/stat") as stat:
            fields = stat.read().rpartition(")")[2].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def descendants(pid: int) -> list[int]:
    """Every live process under `pid` (the server's fork server and workers)."""
    children: dict[int, list[int]] = {}
    for entry in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{entry}/stat") as stat:
                parent = int(stat.read().rpartition(")")[2].split()[1])
        except OSError:
            continue
        children.setdefault(parent, []).append(int(entry))
    found, todo = [], [pid]
    while todo:
        below = children.get(todo.pop(), [])
        found += below
        todo += below
    return found


def cpu_now(server: int | None) -> tuple[float, float, float]:
    """CPU seconds so far of the server, of everything under it, and of this process."""
    mine = sum(os.times()[:2])
    if server is None:
        return 0.0, 0.0, mine
    return process_cpu(server), sum(map(process_cpu, descendants(server))), mine


def percentile(values: list[float], q: float) -> float:
    if not values:
        return float("nan")
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


async def spectate(client: GameClient, view: TableView, samples: Samples, stop: float) -> None:
    async for change in client.follow(view):
        if isinstance(change, OutcomeMessage):
            accepted = samples.accepted_at.get((view.id, change.version))
            if accepted is not None:
                samples.spectator_ms.append((time.perf_counter() - accepted) * 1000)
        if change.status is not Status.PLAYING or time.perf_counter() > stop:
            return


async def play_table(players: list[GameClient], view: TableView, samples: Samples,
                     pace: Pace, stop: float) -> None:  # fmt: skip
    """Both players' loop on one table (they share this task: one feed, the player to act
    shoots) until the rack ends or time is up."""
    by_id = {p.player.id: p for p in players}
    current: TableView | OutcomeMessage = view
    feed = players[0].follow(view)
    while current.status is Status.PLAYING and time.perf_counter() < stop:
        shooter = by_id[current.next.player]
        await pace.wait()
        action = refereeing.bot_input(current.state, "picker").model_dump(mode="json")
        try:
            ack = await shooter.send(view.id, current.version, action)
        except Refused:
            return
        samples.accepted_at[(view.id, ack.version)] = time.perf_counter()
        async for change in feed:
            current = change
            if isinstance(change, OutcomeMessage) and change.version == ack.version:
                samples.shots += 1
                accepted = samples.accepted_at[(view.id, change.version)]
                samples.player_ms.append((time.perf_counter() - accepted) * 1000)
                break
            if not isinstance(change, OutcomeMessage):
                break


async def match_loop(base: str, session: aiohttp.ClientSession, n: int, samples: Samples,
                     pace: Pace, stop: float) -> None:  # fmt: skip
    players = [GameClient(base, session) for _ in range(2)]
    spectator = GameClient(base, session)
    for seat, player in enumerate(players):
        await player.register(f"load{n}s{seat}r{os.getpid() % 1000}t{int(stop) % 100000}")
    rack = 0
    while time.perf_counter() < stop:
        watcher = await play_rack(players, spectator, rack, samples, pace, stop)
        rack += 1
        watcher.cancel()


async def new_table(host: GameClient, race_to: int = 1) -> TableView:
    """A nine-ball table created by `host`, a match of a race to `race_to` racks. Creating is
    rate-limited per player (1 a second after a burst of 20), and short racks run a pair of
    players past it (`--quick`'s four tables did within seconds): a refused host waits
    `CREATE_WAIT_S` and asks again."""
    while True:
        try:
            return await host.create("nineball", race_to=race_to)
        except Refused as refused:
            if refused.code != ErrorCode.RATE_LIMITED.value:
                raise
            await asyncio.sleep(CREATE_WAIT_S)


async def play_rack(players: list[GameClient], spectator: GameClient, rack: int,
                    samples: Samples, pace: Pace, stop: float,
                    race_to: int = 1) -> asyncio.Task[None]:  # fmt: skip
    """One table, created by one player and joined by the other (turn about by `rack`:
    tables are rate-limited per creator), played until its match (`race_to` racks won; one
    rack by default) ends or time is up; the spectator's task, which follows it, is
    returned."""
    host, guest = players[rack % 2], players[1 - rack % 2]
    view = await guest.join((await new_table(host, race_to)).id)
    watcher = asyncio.create_task(spectate(spectator, view, samples, stop))
    await play_table(players, view, samples, pace, stop)
    return watcher


async def relay_probe(base: str, session: aiohttp.ClientSession, samples: Samples,
                      stop: float) -> None:  # fmt: skip
    channel = f"probe-{time.time_ns()}"  # a fresh channel: no backlog from an earlier run
    token = TokenAuthority(SECRET.encode(), "public-").issue("probe", [channel], 3600)
    headers = {"Authorization": f"Bearer {token}", "Content-Type": "application/json"}
    async with session.ws_connect(f"{base.replace('http', 'ws')}/sub/{channel}") as ws:

        async def receive() -> None:
            async for frame in ws:
                sent = float(frame.data)
                samples.relay_ms.append((time.perf_counter() - sent) * 1000)

        reader = asyncio.create_task(receive())
        while time.perf_counter() < stop:
            body = repr(time.perf_counter())
            async with session.post(f"{base}/pub/{channel}", data=body, headers=headers) as r:
                await r.read()
            await asyncio.sleep(0.02)
        reader.cancel()


async def run(
    base: str, matches: int, seconds: float, rate: float | None, server: int | None
) -> Samples:
    samples = Samples()
    before = cpu_now(server)
    stop = time.perf_counter() + seconds
    pace = Pace(rate)
    connector = aiohttp.TCPConnector(limit=0)
    async with aiohttp.ClientSession(connector=connector) as session:
        tasks = [match_loop(base, session, n, samples, pace, stop) for n in range(matches)]
        await asyncio.gather(relay_probe(base, session, samples, stop), *tasks)
    samples.cpu = tuple(b - a for a, b in zip(before, cpu_now(server), strict=True))
    return samples


def start_server(port: int, workers: int, directory: str) -> subprocess.Popen[bytes]:
    env = {**os.environ, "BILLIARDS_RELAY_SECRET": SECRET}
    command = [sys.executable, "-m", "server.cli", "serve", "--port", str(port)]
    command += ["--workers", str(workers), "--db", f"{directory}/load.sqlite3"]
    command += ["--names-per-address", "100000"]  # every bench player comes from loopback
    return subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


async def wait_ready(base: str, seconds: float = 30.0) -> None:
    async with aiohttp.ClientSession() as session:
        for _ in range(int(seconds / 0.1)):
            try:
                async with session.get(f"{base}/api/tables") as response:
                    if response.status == 200:
                        return
            except aiohttp.ClientError:
                pass
            await asyncio.sleep(0.1)
    raise SystemExit("the server did not start")


def row(label: str, samples: Samples, seconds: float, processes: int) -> str:
    rate = samples.shots / seconds
    return (
        f"| {label:<22} | {rate:7.1f} | {rate / processes:6.1f} "
        f"| {percentile(samples.player_ms, 0.5):6.1f} / {percentile(samples.player_ms, 0.99):6.1f} "
        f"| {percentile(samples.spectator_ms, 0.5):6.1f} / "
        f"{percentile(samples.spectator_ms, 0.99):6.1f} "
        f"| {percentile(samples.relay_ms, 0.99):6.1f} "
        f"| {' / '.join(f'{1000 * cpu / max(1, samples.shots):5.2f}' for cpu in samples.cpu)} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--matches", type=int, default=16)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--quick", action="store_true", help="4 matches, 5 s per run")
    parser.add_argument("--url", help="use this running server (started with the bench's key)")
    args = parser.parse_args()
    if args.quick:
        args.matches, args.seconds = 4, 5.0
    port = free_port()
    base = args.url or f"http://127.0.0.1:{port}"
    with tempfile.TemporaryDirectory() as directory:
        server = None if args.url else start_server(port, args.workers, directory)
        try:
            asyncio.run(wait_ready(base))
            processes = 1 + args.workers
            print(f"{args.matches} matches, {args.seconds:g} s per run, {args.workers} workers")
            print("| run                    | shots/s | /proc  | player p50 / p99 ms "
                  "| spectator p50 / p99 ms | relay p99 ms "
                  "| CPU ms/shot: server / workers / clients |")  # fmt: skip
            print("|---|---|---|---|---|---|---|")
            pid = None if server is None else server.pid
            full = asyncio.run(run(base, args.matches, args.seconds, None, pid))
            print(row("flat out", full, args.seconds, processes), flush=True)
            half_rate = max(1.0, full.shots / args.seconds / 2)
            half = asyncio.run(run(base, args.matches, args.seconds, half_rate, pid))
            print(row(f"paced at {half_rate:.0f}/s", half, args.seconds, processes), flush=True)
        finally:
            if server is not None:
                server.terminate()
                server.wait(timeout=10)


if __name__ == "__main__":
    main()

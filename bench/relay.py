"""Relay benchmark: the relay (memory and Redis backends) beside a bare aiohttp forwarder and nchan.

    .venv/bin/python bench/relay.py [--quick] [--repeat N] [--targets memory,redis,bare,...]

Every target runs as its own server process on 127.0.0.1 (one process / one nginx worker);
this process is the load generator, on the lean WebSocket and HTTP clients of
bench/loadgen.py (through aiohttp's client it cost as much CPU per message as the server).
Where the machine has two cores or more, the server gets one of them to itself and the load
generator and Redis share the others (`pin`), the load generator at a lower priority (nice 10,
`measure_apart`): in production the clients and Redis run on other machines. When the three
competed for two cores, Redis waited for a core about a fifth of the time and the server a
tenth; pinned but at equal priority, Redis still waited 11-18% of the time behind the load
generator (and the p99 latency at half load on Redis swung from 14 to 48 ms); niced, 4-5%.
For each target, on a freshly started server:

1. capacity: open up to `capacity` idle WebSocket subscribers, spread over channels; the RSS
   growth of the server divided by the connections is the memory per idle connection; then one
   message per channel checks that every connection is really held (delivered = held).
2. fan-out: 1 publisher (HTTP POST, 64 requests in flight) -> 1,000 subscribers of one
   channel, as fast as it goes: messages delivered per second.
3. pairs: 1,000 channels x 2 subscribers, publishes spread round-robin over the channels.
   Both run for seconds, and report the server's CPU time per delivered message (and, on
   Redis, Redis' own), which the other processes on the machine sway less than the rates.
4. For 2 and 3, a paced run at half the measured delivery rate gives the p50/p99
   publish-to-deliver latency (the payload carries its send time; one clock, one process).

Between phases the bench waits until the server's CPU time stops growing, so that closing one
phase's connections does not slow the next; before each measurement one message per channel
checks that every subscription is live. Then the load generator collects its garbage, freezes
what is left (`gc.freeze`) and turns its collector off until the phase's measurements are
done: a full collection over its thousands of client sockets stopped it for tens of
milliseconds, and even its young collections for 7-13 ms about every 0.8 s, which it counted
as the server's latency (the same for every target). The relay servers' collectors follow
`server.http.collector` (their started heap frozen) as `billiards serve`'s do, pauses included; the
bare forwarder's runs untouched.

On Redis targets, the server's Redis connections are counted (CLIENT LIST) while 1 channel and
while 1,000 channels have subscribers: a replica's count must not grow with its channels (one
reader per replica).

The relay runs with every feature on (token check, payload validation, bounded send queues,
Redis AOF with fsync on every write) except that the publish rate limit is raised: the load
generator is one publisher. The bare forwarder is the ceiling of this stack: an aiohttp app that
only copies POSTed bytes to the channel's WebSockets. nchan is Debian's nginx +
libnginx-mod-nchan with a generated config; its row reads "unavailable" if nginx is missing.
Ratios compare each relay with the bare forwarder and nchan, and Redis with memory.

The machine is shared and small: figures are noisy, compare columns of one run only.
"""

from __future__ import annotations

import argparse
import asyncio
import concurrent.futures
import gc
import json
import multiprocessing
import os
import resource
import shutil
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from contextlib import AbstractContextManager, ExitStack
from dataclasses import dataclass, field
from pathlib import Path

import msgpack
from aiohttp import web
from loadgen import ProtocolError, Publishers, Subscriber  # bench/loadgen.py, beside this file

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

SECRET = "bench-relay-secret-0123456789-0123456789"
HOST = "127.0.0.1"
RELAYS = ("memory", "redis")
REFERENCES = ("bare", "nchan")
TARGETS = ("memory", "redis", "bare", "nchan")
NGINX = "/usr/sbin/nginx"
NCHAN_MODULE = "/usr/lib/nginx/modules/ngx_nchan_module.so"
FD_LIMIT = 20_000
START_TIMEOUT_S = 15.0
DELIVERY_TIMEOUT_S = 20.0  # after the last publish, waiting for stragglers
CONNECT_CONCURRENCY = 200
CONNECT_TIMEOUT_S = 10.0
SETTLE_TIMEOUT_S = 30.0
LOADGEN_NICE = 10  # the load generator's priority below the servers' and Redis' (see pin)
PAD = "x" * 64
#: glibc's allocator, fixed for the Python servers. By default it maps a block above its mmap
#: threshold (128 KiB) with mmap, and raises that threshold only when such a block is freed at
#: its full size. asyncio reads a socket into a 256 KiB buffer, shrinks it to what came
#: (mremap) and frees it (munmap): three more system calls a read, until something has freed a
#: large block and the threshold has risen. Whether it had depended on what the server did
#: before: the bare forwarder took 39-43 us of CPU a pairs delivery from a fresh start and 31-35
#: after the capacity phase (docs/operations.md). Fixed thresholds put every server in the
#: second state from its start.
MALLOC_ENV = {"MALLOC_MMAP_THRESHOLD_": str(1 << 20), "MALLOC_TRIM_THRESHOLD_": str(8 << 20)}


@dataclass(frozen=True)
class Sizes:
    """How much load each phase applies (see the module docstring)."""

    capacity: int
    capacity_channels: int
    fanout_subscribers: int
    fanout_messages: int
    pair_channels: int
    pair_messages: int
    paced_seconds: float
    # A game server has many tables publishing at once. With Redis fsync'ing every write,
    # throughput is publishes in flight per fsync: 8 would measure the disk, not the relay.
    publishers_in_flight: int = 64


FULL = Sizes(10_000, 1_000, 1_000, 200, 1_000, 24_000, 4.0)
QUICK = Sizes(2_000, 200, 1_000, 40, 1_000, 1_500, 1.5)


# ----- servers -------------------------------------------------------------------------------
def free_port() -> int:
    with socket.socket() as sock:
        sock.bind((HOST, 0))
        return sock.getsockname()[1]


def bare_app() -> web.Application:
    """The ceiling: POST /pub/{channel} copies the body to the channel's WebSockets, nothing
    else (no ids, no buffer, no validation, no auth)."""
    channels: dict[str, set[web.WebSocketResponse]] = {}

    async def subscribe(request: web.Request) -> web.WebSocketResponse:
        ws = web.WebSocketResponse()
        await ws.prepare(request)
        subscribers = channels.setdefault(request.match_info["channel"], set())
        subscribers.add(ws)
        try:
            async for _ in ws:
                pass
        finally:
            subscribers.discard(ws)
        return ws

    async def publish(request: web.Request) -> web.Response:
        text = (await request.read()).decode()
        subscribers = tuple(channels.get(request.match_info["channel"], ()))
        for ws in subscribers:
            await ws.send_str(text)
        return web.Response(status=201 if subscribers else 202)

    app = web.Application()
    app.router.add_get("/sub/{channel}", subscribe)
    app.router.add_post("/pub/{channel}", publish)
    return app


def relay_app(redis_url: str | None) -> web.Application:
    """The real relay, every feature on; only the per-publisher rate limits are lifted."""
    from server.http.app import AppSettings, create_app
    from server.relay.settings import RelaySettings

    relay = RelaySettings(
        auth_secret=SECRET,
        publish_rate=1e9,
        publish_burst=10**9,
        server_publish_rate=1e9,
        server_publish_burst=10**9,
    )
    return create_app(AppSettings(relay=relay, redis_url=redis_url))


def serve(kind: str, port: int, redis_url: str | None) -> None:
    """Entry point of a server process (`--serve`)."""
    from server.http import collector

    app = bare_app() if kind == "bare" else relay_app(redis_url)
    if kind == "relay":
        collector.install(app)  # as `billiards serve` does
    web.run_app(app, host=HOST, port=port, print=None, access_log=None)


def wait_for_port(port: int, process: subprocess.Popen[bytes], what: str) -> None:
    deadline = time.monotonic() + START_TIMEOUT_S
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise RuntimeError(f"{what} exited with {process.returncode}")
        with socket.socket() as sock:
            if sock.connect_ex((HOST, port)) == 0:
                return
        time.sleep(0.05)
    raise RuntimeError(f"{what} did not listen on {port} within {START_TIMEOUT_S} s")


def rss_kb(pid: int) -> int:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return 0


def cpu_seconds(pid: int) -> float:
    """User + system CPU time of a process (fields 14 and 15 of /proc/PID/stat)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def children(pid: int) -> list[int]:
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return [int(child) for child in path.read_text().split()] if path.exists() else []


@dataclass(frozen=True)
class Watched:
    """What the load generator reads of a running target: its port, and the processes whose
    RSS and CPU time count (from /proc, so a separate process can read them)."""

    port: int
    pids: tuple[int, ...]
    redis_url: str | None = None
    redis_pid: int | None = None

    def rss_kb(self) -> int:
        return sum(rss_kb(pid) for pid in self.pids)

    def cpu_seconds(self) -> float:
        return sum(cpu_seconds(pid) for pid in self.pids)

    def redis_cpu_seconds(self) -> float:
        return cpu_seconds(self.redis_pid) if self.redis_pid is not None else 0.0

    async def settle(self) -> None:
        """Wait until the server is idle (done closing the last phase's connections)."""
        deadline = time.monotonic() + SETTLE_TIMEOUT_S
        used = self.cpu_seconds()
        while time.monotonic() < deadline:
            await asyncio.sleep(0.5)
            used, before = self.cpu_seconds(), used
            if used - before < 0.05:
                return


class ServerProcess(AbstractContextManager["ServerProcess"]):
    """A server subprocess on a free port; `measured_pids` are those whose RSS counts."""

    def __init__(
        self,
        args: list[str],
        what: str,
        port: int,
        redis_url: str | None = None,
        redis_pid: int | None = None,
        env: dict[str, str] | None = None,
    ) -> None:
        self.port = port
        self.what = what
        self.redis_url = redis_url
        self.redis_pid = redis_pid
        self.process = subprocess.Popen(args, stdout=subprocess.DEVNULL, env=env)
        wait_for_port(port, self.process, what)

    def measured_pids(self) -> list[int]:
        return [self.process.pid]

    def watched(self) -> Watched:
        return Watched(self.port, tuple(self.measured_pids()), self.redis_url, self.redis_pid)

    def __exit__(self, *exc_info: object) -> None:
        self.process.send_signal(signal.SIGINT if self.what != "nchan" else signal.SIGQUIT)
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()


class NginxProcess(ServerProcess):
    """nginx + nchan: the worker processes are measured, not the master."""

    def measured_pids(self) -> list[int]:
        return children(self.process.pid)


NCHAN_CONF = """
load_module {module};
{user}
daemon off;
master_process on;
worker_processes 1;
worker_rlimit_nofile {fds};
pid {dir}/nginx.pid;
error_log {dir}/error.log warn;
events {{ worker_connections {fds}; }}
http {{
    access_log off;
    client_body_temp_path {dir}/body;
    proxy_temp_path {dir}/proxy;
    fastcgi_temp_path {dir}/fastcgi;
    uwsgi_temp_path {dir}/uwsgi;
    scgi_temp_path {dir}/scgi;
    nchan_shared_memory_size 256M;
    server {{
        listen {host}:{port};
        location ~ ^/pub/([A-Za-z0-9_-]+)$ {{
            nchan_publisher;
            nchan_channel_id $1;
            nchan_message_buffer_length 100;
            nchan_message_timeout 3600s;
        }}
        location ~ ^/sub/([A-Za-z0-9_-]+)$ {{
            nchan_subscriber;
            nchan_channel_id $1;
        }}
    }}
}}
"""


CORES = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else []


def pin(server: ServerProcess) -> str:
    """Give the server the last core to itself; this process (so the load generator it forks)
    and Redis get the others (see the module docstring). Says where each runs."""
    if len(CORES) < 2:
        return f"nothing pinned (fewer than 2 cores); load generator at nice {LOADGEN_NICE}"
    own, rest = {CORES[-1]}, set(CORES[:-1])
    for pid in server.measured_pids():
        os.sched_setaffinity(pid, own)
    os.sched_setaffinity(0, rest)
    if server.redis_pid is not None:
        os.sched_setaffinity(server.redis_pid, rest)
    return (
        f"server on core {CORES[-1]}, load generator (nice {LOADGEN_NICE}) and Redis "
        f"on {sorted(rest)}"
    )


def measure_apart(target: str, server: Watched, sizes: Sizes) -> dict[str, float]:
    """`measure` in a forked child at a lower priority (`LOADGEN_NICE`): the load generator
    stands in for clients on other machines, so where it shares a core with Redis, Redis
    goes first. The child is forked after the servers started, so they keep this process'
    priority (an unprivileged process cannot raise a priority it has lowered)."""
    context = multiprocessing.get_context("fork")
    with concurrent.futures.ProcessPoolExecutor(1, mp_context=context) as pool:
        return pool.submit(_measure_niced, target, server, sizes).result()


def _measure_niced(target: str, server: Watched, sizes: Sizes) -> dict[str, float]:
    os.nice(LOADGEN_NICE)
    return asyncio.run(measure(target, server, sizes))


def start_target(target: str, stack: ExitStack) -> ServerProcess | None:
    """Start one target's server (and its Redis); None if it cannot run here."""
    port = free_port()
    if target == "nchan":
        if not (Path(NGINX).exists() and Path(NCHAN_MODULE).exists()):
            return None
        directory = Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="nchan-")))
        conf = directory / "nginx.conf"
        user = "user root;" if os.geteuid() == 0 else ""
        conf.write_text(
            NCHAN_CONF.format(
                module=NCHAN_MODULE, user=user, fds=FD_LIMIT, dir=directory, host=HOST, port=port
            )
        )
        args = [NGINX, "-p", str(directory), "-c", str(conf), "-e", str(directory / "error.log")]
        return stack.enter_context(NginxProcess(args, "nchan", port))
    redis_url, redis_pid = None, None
    if target == "redis":
        from tests.redis_server import RedisServer

        redis = RedisServer(Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="r-"))))
        redis.start()
        stack.callback(redis.stop)
        redis_url = redis.url
        assert redis.process is not None
        redis_pid = redis.process.pid
    kind = "bare" if target == "bare" else "relay"
    args = [sys.executable, __file__, "--serve", kind, "--port", str(port)]
    args += ["--redis", redis_url] if redis_url else []
    env = {**os.environ, **MALLOC_ENV}
    return stack.enter_context(ServerProcess(args, target, port, redis_url, redis_pid, env))


# ----- load generator ------------------------------------------------------------------------
def sent_at(data: str | bytes) -> int:
    """The send time (monotonic ns) a payload carries, whatever frame type brought it."""
    if isinstance(data, bytes) and data[:1] != b"{":
        return int(msgpack.unpackb(data)["t"])
    text = data.decode() if isinstance(data, bytes) else data
    start = text.index('"t":') + 4
    return int(text[start : text.index(",", start)])


@dataclass
class Receiver:
    """Counts deliveries; records latencies while `recording`."""

    count: int = 0
    last_ns: int = 0
    recording: bool = False
    latencies_ms: list[float] = field(default_factory=list)

    def reset(self) -> None:
        self.count, self.last_ns, self.recording = 0, 0, False
        self.latencies_ms.clear()

    def take(self, data: str | bytes) -> None:
        now = time.monotonic_ns()
        self.count += 1
        self.last_ns = now
        if self.recording:
            self.latencies_ms.append((now - sent_at(data)) / 1e6)

    async def wait_for(self, count: int, timeout: float) -> None:
        deadline = time.monotonic() + timeout
        while self.count < count and time.monotonic() < deadline:
            await asyncio.sleep(0.02)


class Load:
    """The load generator's side of one target: subscribers and publishers (bench/loadgen.py)."""

    def __init__(self, port: int, sizes: Sizes) -> None:
        self.sizes = sizes
        self.port = port
        self.receiver = Receiver()
        self.sockets: list[Subscriber] = []
        from server.relay.auth import TokenAuthority

        token = TokenAuthority(SECRET.encode(), "public-").issue("bench", [], 3600, server=True)
        headers = {"Content-Type": "application/json", "Authorization": f"Bearer {token}"}
        self.publishers = Publishers(HOST, port, headers)

    async def subscribe(self, channels: list[str]) -> int:
        """Open one WebSocket subscriber per entry of `channels`; how many opened."""
        gate = asyncio.Semaphore(CONNECT_CONCURRENCY)

        async def one(channel: str) -> None:
            async with gate:
                try:
                    subscriber = await asyncio.wait_for(
                        Subscriber.open(HOST, self.port, f"/sub/{channel}", self.receiver.take),
                        CONNECT_TIMEOUT_S,
                    )
                except (OSError, ProtocolError, TimeoutError):
                    return
            self.sockets.append(subscriber)

        await asyncio.gather(*(one(channel) for channel in channels))
        return len(self.sockets)

    def close(self) -> None:
        """Close every subscriber (the publishers' connections stay for the next phase)."""
        for subscriber in self.sockets:
            subscriber.close()
        self.sockets.clear()
        self.receiver.reset()

    async def publish(self, channel: str) -> None:
        body = json.dumps({"t": time.monotonic_ns(), "pad": PAD}).encode()
        status = await self.publishers.post(f"/pub/{channel}", body)
        if status not in (200, 201, 202):
            raise RuntimeError(f"publish to {channel}: HTTP {status}")

    async def saturate(self, channel_of: Callable[[int], str], messages: int, fanout: int) -> float:
        """Publish `messages` with a few in flight; deliveries per second until the last."""
        start = time.monotonic_ns()
        next_index = iter(range(messages))

        async def worker() -> None:
            for index in next_index:
                await self.publish(channel_of(index))

        await asyncio.gather(*(worker() for _ in range(self.sizes.publishers_in_flight)))
        await self.receiver.wait_for(messages * fanout, DELIVERY_TIMEOUT_S)
        return self.receiver.count / max(self.receiver.last_ns - start, 1) * 1e9

    async def paced(
        self, channel_of: Callable[[int], str], deliveries_per_s: float, fanout: int
    ) -> tuple[float, float]:
        """Publish at a steady rate for `paced_seconds`; p50 and p99 latency in ms."""
        rate = max(deliveries_per_s / fanout, 1.0)
        count = max(int(rate * self.sizes.paced_seconds), 10)
        expected = self.receiver.count + count * fanout
        self.receiver.recording = True
        gate = asyncio.Semaphore(64)
        start = time.monotonic()
        tasks = []

        async def one(index: int) -> None:
            async with gate:
                await self.publish(channel_of(index))

        for index in range(count):
            await asyncio.sleep(max(0.0, start + index / rate - time.monotonic()))
            tasks.append(asyncio.create_task(one(index)))
        await asyncio.gather(*tasks)
        await self.receiver.wait_for(expected, DELIVERY_TIMEOUT_S)
        self.receiver.recording = False
        latencies = self.receiver.latencies_ms
        if len(latencies) < 2:
            return float("nan"), float("nan")
        cuts = statistics.quantiles(latencies, n=100)
        return cuts[49], cuts[98]


async def redis_connections(redis_url: str) -> int:
    """Connections to Redis other than this one (the server's, as the bench opens none)."""
    import redis.asyncio as aioredis

    admin = aioredis.from_url(redis_url)
    try:
        return len(await admin.client_list()) - 1
    finally:
        await admin.aclose()


async def measure(target: str, server: Watched, sizes: Sizes) -> dict[str, float]:
    """All phases against one running server."""
    result: dict[str, float] = {}
    load = Load(server.port, sizes)
    try:
        # Warm up code paths, then measure idle connections.
        await load.subscribe([f"warm-{i}" for i in range(50)])
        load.close()
        await server.settle()
        before = server.rss_kb()
        channels = [f"cap-{i % sizes.capacity_channels}" for i in range(sizes.capacity)]
        opened = await load.subscribe(channels)
        await asyncio.sleep(1.0)
        result["kb_per_conn"] = (server.rss_kb() - before) / max(opened, 1)
        held_before = load.receiver.count
        for i in range(sizes.capacity_channels):
            await load.publish(f"cap-{i}")
        await load.receiver.wait_for(held_before + opened, DELIVERY_TIMEOUT_S)
        result["held"] = load.receiver.count - held_before
        load.close()
        await server.settle()
        print(f"  {target}: capacity done ({result['held']:.0f} held)", file=sys.stderr)

        for name, subscribers, channel_of, messages in (
            ("fanout", ["fan"] * sizes.fanout_subscribers, lambda i: "fan", sizes.fanout_messages),
            (
                "pairs",
                [f"pair-{i // 2}" for i in range(sizes.pair_channels * 2)],
                lambda i: f"pair-{i % sizes.pair_channels}",
                sizes.pair_messages,
            ),
        ):
            fanout = sizes.fanout_subscribers if name == "fanout" else 2
            await load.subscribe(subscribers)
            # One message per channel first: a WebSocket handshake can complete before the
            # server has set the subscription up, and the measurement starts once all are live.
            await load.saturate(channel_of, len(set(subscribers)), fanout)
            gc.collect()
            gc.freeze()
            gc.disable()
            if server.redis_url is not None:
                result[f"{name}_redis"] = await redis_connections(server.redis_url)
            load.receiver.reset()
            cpu, redis_cpu = server.cpu_seconds(), server.redis_cpu_seconds()
            rate = await load.saturate(channel_of, messages, fanout)
            result[f"{name}_rate"] = rate
            delivered = max(load.receiver.count, 1)
            result[f"{name}_cpu"] = (server.cpu_seconds() - cpu) / delivered * 1e6
            if server.redis_pid is not None:
                result[f"{name}_redis_cpu"] = (
                    (server.redis_cpu_seconds() - redis_cpu) / delivered * 1e6
                )
            result[f"{name}_p50"], result[f"{name}_p99"] = await load.paced(
                channel_of, rate / 2, fanout
            )
            gc.enable()
            load.close()
            gc.unfreeze()
            await server.settle()
            print(f"  {target}: {name} done ({rate:,.0f} msg/s)", file=sys.stderr)
    finally:
        load.close()
        load.publishers.close()
    return result


# ----- report --------------------------------------------------------------------------------
ROWS = (
    ("fanout_rate", "fan-out 1->1000, delivered msg/s", "{:,.0f}", True),
    ("fanout_cpu", "  server CPU per delivery, us", "{:.1f}", False),
    ("fanout_redis_cpu", "  Redis CPU per delivery, us", "{:.1f}", False),
    ("fanout_p50", "  p50 latency at half load, ms", "{:.1f}", False),
    ("fanout_p99", "  p99 latency at half load, ms", "{:.1f}", False),
    ("pairs_rate", "1000 channels x 2, delivered msg/s", "{:,.0f}", True),
    ("pairs_cpu", "  server CPU per delivery, us", "{:.1f}", False),
    ("pairs_redis_cpu", "  Redis CPU per delivery, us", "{:.1f}", False),
    ("pairs_p50", "  p50 latency at half load, ms", "{:.1f}", False),
    ("pairs_p99", "  p99 latency at half load, ms", "{:.1f}", False),
    ("kb_per_conn", "memory per idle WebSocket, KB", "{:.1f}", False),
    ("held", "WebSocket subscribers held", "{:,.0f}", True),
    ("fanout_redis", "Redis connections, 1 channel", "{:.0f}", False),
    ("pairs_redis", "Redis connections, 1000 channels", "{:.0f}", False),
)


def ratio(value: float | None, reference: float | None) -> str:
    if value is None or reference is None or reference == 0:
        return "-"
    return f"{value / reference:.2f}"


def compared(names: list[str]) -> list[tuple[str, str]]:
    """(relay, reference) pairs to show as ratios: each relay against each reference, and
    Redis against memory."""
    return [
        (relay, reference)
        for relay in RELAYS
        for reference in REFERENCES
        if relay in names and reference in names
    ] + ([("redis", "memory")] if {"redis", "memory"} <= set(names) else [])


def print_table(header: list[str], lines: list[list[str]]) -> None:
    widths = [max(len(row[i]) for row in [header, *lines]) for i in range(len(header))]
    for row in [header, *lines]:
        print("  ".join(cell.rjust(width) for cell, width in zip(row, widths, strict=True)))


def report(results: dict[str, dict[str, float] | None], sizes: Sizes) -> None:
    names = list(results)
    pairs = compared(names)
    values, ratios = [], []
    for key, label, fmt, _ in ROWS:
        got = {name: (results[name] or {}).get(key) for name in names}
        values.append(
            [label, *(fmt.format(v) if v is not None else "unavailable" for v in got.values())]
        )
        ratios.append([label, *(ratio(got[a], got[b]) for a, b in pairs)])
    print_table(["metric", *names], values)
    if pairs:
        print()
        print_table(["ratio", *(f"{a}/{b}" for a, b in pairs)], ratios)
    for name in RELAYS:
        got = results.get(name)
        bare = results.get("bare")
        if not got:
            continue
        redis_bars = []
        if name == "redis":
            memory = results.get("memory")
            redis_bars = [
                "pairs >= 80% of memory: "
                + (ratio(got["pairs_rate"], memory["pairs_rate"]) if memory else "-"),
                "pairs CPU <= 1.2 x (memory + Redis's own): "
                + (
                    ratio(got["pairs_cpu"], memory["pairs_cpu"] + got["pairs_redis_cpu"])
                    if memory
                    else "-"
                ),
                f"Redis connections {got['fanout_redis']:.0f} at 1 channel, "
                f"{got['pairs_redis']:.0f} at 1,000",
            ]
        bars = [
            f"fan-out >= 80% of bare aiohttp: "
            f"{ratio(got['fanout_rate'], bare['fanout_rate']) if bare else '-'}",
            f"pairs CPU per delivery <= 1.25 x bare: "
            f"{ratio(got['pairs_cpu'], bare['pairs_cpu']) if bare else '-'}",
            f"pairs msg/s >= 0.8 of bare: "
            f"{ratio(got['pairs_rate'], bare['pairs_rate']) if bare else '-'}",
            f"{sizes.capacity:,} subscribers held: {got['held']:,.0f}, "
            f"{got['kb_per_conn']:.1f} KB each (bar 20 KB)",
            f"p99 at half load: fan-out {got['fanout_p99']:.1f} ms, "
            f"pairs {got['pairs_p99']:.1f} ms (bar 20 ms)",
            *redis_bars,
        ]
        print(f"bars, {name}: " + "; ".join(bars))


def raise_fd_limit() -> None:
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    wanted = FD_LIMIT if hard == resource.RLIM_INFINITY else min(FD_LIMIT, hard)
    if soft < wanted:
        resource.setrlimit(resource.RLIMIT_NOFILE, (wanted, hard))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smaller loads, shorter runs")
    parser.add_argument("--targets", default=",".join(TARGETS), help="comma-separated subset")
    parser.add_argument("--repeat", type=int, default=1, help="runs per target (medians)")
    parser.add_argument("--serve", choices=("bare", "relay"), help=argparse.SUPPRESS)
    parser.add_argument("--port", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--redis", help=argparse.SUPPRESS)
    args = parser.parse_args()
    raise_fd_limit()
    if args.serve:
        serve(args.serve, args.port, args.redis)
        return 0
    sizes = QUICK if args.quick else FULL
    targets = [t for t in args.targets.split(",") if t]
    unknown = set(targets) - set(TARGETS)
    if unknown:
        parser.error(f"unknown targets: {', '.join(sorted(unknown))}")
    if "nchan" in targets and shutil.which("nginx") is None and not Path(NGINX).exists():
        print("nginx not found: apt-get install -y nginx libnginx-mod-nchan", file=sys.stderr)
    runs: dict[str, list[dict[str, float]]] = {target: [] for target in targets}
    placement, started = "no target ran", cpu_times()
    for round_ in range(args.repeat):
        # Rotate the order so that a slow spell of the shared machine hits every target.
        shift = round_ % len(targets)
        for target in targets[shift:] + targets[:shift]:
            with ExitStack() as stack:
                server = start_target(target, stack)
                if server is not None:
                    placement = pin(server)
                    runs[target].append(measure_apart(target, server.watched(), sizes))
    print(f"sizes: {sizes}, medians of {args.repeat} run(s) per target")
    print(machine_load(started))
    print(f"placement: {placement}")
    report({target: median_run(measured) for target, measured in runs.items()}, sizes)
    return 0


def median_run(measured: list[dict[str, float]]) -> dict[str, float] | None:
    """Each metric's median over the runs of one target (None: the target never ran)."""
    if not measured:
        return None
    return {key: statistics.median(run[key] for run in measured) for key in measured[0]}


def machine_load(since: tuple[int, int]) -> str:
    """The 1-minute load average, the core count, and the share of the machine's CPU time that
    its hypervisor gave to other guests since `since` (a `cpu_times()`): how busy the shared
    machine was."""
    total, steal = (now - then for now, then in zip(cpu_times(), since, strict=True))
    stolen = f"{steal / total:.0%}" if total else "-"
    return (
        f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; "
        f"CPU time stolen by the hypervisor during the run: {stolen}"
    )


def cpu_times() -> tuple[int, int]:
    """All CPU time and stolen CPU time so far, in ticks (/proc/stat's `cpu` line)."""
    fields = [int(field) for field in Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]]
    return sum(fields[:8]), fields[7]  # user nice system idle iowait irq softirq steal


if __name__ == "__main__":
    sys.exit(main())

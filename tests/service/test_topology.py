"""docker-compose.yml's topology run for real, without containers: one redis-server (AOF on),
three `billiards serve --redis URL` replicas sharing one BILLIARDS_RELAY_SECRET, and nginx in
front of them, configured from deploy/nginx.conf itself at test time.

`loopback_config` rewrites only what a loopback run needs: the upstream servers become the
replicas' loopback ports, `listen 80` a free loopback port, and nginx's own files (pid, logs,
request bodies) go to a temporary directory. Everything that decides how requests are forwarded
(proxy headers, the WebSocket upgrade, buffering, body size, retries) is the file that
docker-compose mounts, so a mistake there fails these tests. Every request goes through nginx's
port, the players are the real `billiards play`. Left unverified: the image (deploy/Dockerfile)
and compose itself, as no Docker engine runs here (deploy/SCALING.md).
"""

from __future__ import annotations

import asyncio
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import time
from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import dataclass
from pathlib import Path

import aiohttp
import pytest
from aiohttp import web
from aiohttp.test_utils import TestServer

from server.client.api_client import GameClient
from server.client.play import names_of, outcome_line
from server.protocol.ids import MAX_RECORD_BODY
from server.protocol.models import OutcomeMessage, Status
from tests.redis_server import free_port
from tests.service.conftest import WAIT_S
from tests.service.test_cli import run
from tests.service.test_leaderboard import _record
from tests.service.test_replicas import Replica

ROOT = Path(__file__).resolve().parents[2]
NGINX_CONF = ROOT / "deploy" / "nginx.conf"
NGINX_BINARY = os.environ.get("NGINX", "/usr/sbin/nginx")
REPLICAS = 3
START_TIMEOUT_S = 10.0
#: nginx's access log line: the status, the request (its query too: a feed's resume id), and
#: every replica it was sent to in order (more than one when nginx passed it on to the next),
#: so the test sees where requests went.
ACCESS_LOG = "$status $request_method $request_uri $upstream_addr"
#: An outcome line of `billiards play` (server.client.play.outcome_line): the version, then who
#: played (a resync prints `vN table <status>: ...` instead).
OUTCOME_LINE = re.compile(r"^v(\d+)\s+(?!table )\S[^:]*: ")


# ----- nginx, configured from deploy/nginx.conf ----------------------------------------------
def loopback_config(conf: str, upstreams: list[int], port: int, directory: Path) -> str:
    """deploy/nginx.conf for a loopback run: the upstream servers become `upstreams` (ports on
    127.0.0.1) and `listen 80` becomes `port`. Added are only the run's own files in
    `directory` (pid, logs, temporary bodies: nginx's defaults are system paths), `daemon off`
    (the test owns the process) and, as root, `user root` (nginx's default user could not
    enter the temporary directory). Nothing that forwards requests changes."""
    ports = iter(upstreams)
    conf, servers = re.subn(
        r"^(\s*server\s+)[\w.-]+:\d+", lambda m: f"{m[1]}127.0.0.1:{next(ports)}", conf, flags=re.M
    )
    assert servers == len(upstreams), f"deploy/nginx.conf has {servers} upstream servers"
    conf, listens = re.subn(r"\blisten\s+80;", f"listen 127.0.0.1:{port};", conf)
    assert listens == 1, "deploy/nginx.conf should listen on port 80, once"
    main = ["daemon off;", f"pid {directory}/nginx.pid;", f"error_log {directory}/error.log;"]
    if os.geteuid() == 0:
        main.append("user root;")
    files = [f"log_format topology '{ACCESS_LOG}';", f"access_log {directory}/access.log topology;"]
    kinds = ("client_body", "proxy", "fastcgi", "uwsgi", "scgi")
    files += [f"{kind}_temp_path {directory}/{kind};" for kind in kinds]
    conf, blocks = re.subn(r"^http\s*\{", "http {\n    " + "\n    ".join(files), conf, flags=re.M)
    assert blocks == 1, "deploy/nginx.conf should have one http block"
    return "\n".join(main) + "\n" + conf


def nginx_binary() -> str:
    """The nginx to run; a missing one fails the test (the suite never skips for it)."""
    binary = shutil.which(NGINX_BINARY) or shutil.which("nginx")
    if binary is None:
        raise RuntimeError(
            f"nginx not found at {NGINX_BINARY} nor on PATH: install the Debian package 'nginx' "
            "(bash dev.sh test does)"
        )
    return binary


def accepts_connections(port: int) -> bool:
    """Whether something listens on the loopback `port` yet (nginx, once it has started)."""
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=0.5):
            return True
    except OSError:
        return False


@dataclass
class Logged:
    """One request in nginx's access log."""

    status: int
    method: str
    path: str  # with its query, if any
    upstreams: list[str]  # every replica it was sent to, in order; the last one answered


class Nginx:
    """nginx on a free loopback port in front of `upstreams`, configured from NGINX_CONF."""

    def __init__(self, directory: Path, upstreams: list[int]) -> None:
        directory.mkdir()
        self.directory = directory
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        config = directory / "nginx.conf"
        config.write_text(loopback_config(NGINX_CONF.read_text(), upstreams, self.port, directory))
        command = [nginx_binary(), "-p", str(directory), "-e", str(directory / "error.log")]
        self.output = open(directory / "output.log", "wb")  # noqa: SIM115
        self.process = subprocess.Popen(
            [*command, "-c", str(config)], stdout=self.output, stderr=self.output
        )
        deadline = time.monotonic() + START_TIMEOUT_S
        while not accepts_connections(self.port):
            if self.process.poll() is not None or time.monotonic() > deadline:
                self.stop()
                raise RuntimeError(f"nginx did not start: {self.errors()}")
            time.sleep(0.02)

    def errors(self) -> str:
        """What nginx said on its way out, for the failure message of a start that failed."""
        logs = (self.directory / name for name in ("output.log", "error.log"))
        return "\n".join(log.read_text() for log in logs if log.exists())

    def log(self) -> list[Logged]:
        """The requests nginx has logged so far (a WebSocket's once it has closed)."""
        lines = (self.directory / "access.log").read_text().splitlines()
        entries = [line.split(" ", 3) for line in lines]
        return [
            Logged(int(status), method, path, [] if tried == "-" else tried.split(", "))
            for status, method, path, tried in entries
        ]

    async def logged(self, matches: Callable[[Logged], bool]) -> Logged:
        """The first logged request that `matches`, once nginx has logged it."""
        deadline = time.monotonic() + WAIT_S
        while not (found := [entry for entry in self.log() if matches(entry)]):
            assert time.monotonic() < deadline, "nginx logged no such request"
            await asyncio.sleep(0.01)
        return found[0]

    def stop(self) -> None:
        """SIGTERM, nginx's fast shutdown (a graceful one would wait for open WebSockets)."""
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=START_TIMEOUT_S)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.output.close()


@dataclass
class Topology:
    """The running deployment: what a test may kill (replicas) or read (nginx's log)."""

    replicas: list[Replica]
    nginx: Nginx
    http: aiohttp.ClientSession  # for the test's own requests, all through nginx

    @property
    def url(self) -> str:
        return self.nginx.url


@pytest.fixture
async def topology(redis_url: str, tmp_path: Path) -> AsyncIterator[Topology]:
    """Three replicas on one Redis behind nginx; every process is stopped at the end."""
    replicas: list[Replica] = []
    nginx: Nginx | None = None
    try:
        for _ in range(REPLICAS):
            replicas.append(Replica(redis_url, tmp_path))
        # Its own session, closed before the test: its connections to the replicas would
        # otherwise look like nginx's subscribers to `long_lived_connections`.
        async with aiohttp.ClientSession() as ready:
            for replica in replicas:
                await replica.wait_ready(ready)
        nginx = Nginx(tmp_path / "nginx", [replica.port for replica in replicas])
        async with aiohttp.ClientSession() as http:
            yield Topology(replicas, nginx, http)
    finally:
        if nginx is not None:
            nginx.stop()
        for replica in replicas:
            replica.stop()


# ----- the command-line players ---------------------------------------------------------------
class Cli:
    """One `billiards` command (test_cli's `run`), its output read as it comes so that the
    test can act on a line: the table once seated, the match under way."""

    def __init__(self, process: asyncio.subprocess.Process) -> None:
        assert process.stdout is not None and process.stderr is not None
        self.process = process
        self.lines: list[str] = []
        self._stdout = asyncio.create_task(self._read_lines(process.stdout))
        self._stderr = asyncio.create_task(process.stderr.read())

    async def _read_lines(self, stream: asyncio.StreamReader) -> None:
        async for line in stream:
            self.lines.append(line.decode().rstrip("\n"))

    async def until(self, done: Callable[[list[str]], bool]) -> None:
        """Wait until the output so far satisfies `done`; fail if the command ends first."""
        deadline = time.monotonic() + WAIT_S
        while not done(self.lines):
            assert not self._stdout.done(), f"exited: {self.lines} {await self._stderr!r}"
            assert time.monotonic() < deadline, f"timed out after {self.lines[-3:]}"
            await asyncio.sleep(0.01)

    async def finish(self) -> tuple[int, list[str], str]:
        """Exit status, every output line and the error output, once the command exits."""
        code = await asyncio.wait_for(self.process.wait(), 4 * WAIT_S)
        await self._stdout
        return code, self.lines, (await self._stderr).decode()

    async def kill(self) -> None:
        """End the command if it still runs (a player waiting for good must not outlive the
        test) and collect its readers."""
        if self.process.returncode is None:
            self.process.kill()
        await self.process.wait()
        await asyncio.gather(self._stdout, self._stderr, return_exceptions=True)


StartPlayer = Callable[..., Awaitable[Cli]]


@pytest.fixture
async def players(topology: Topology) -> AsyncIterator[StartPlayer]:
    """Starts `billiards play --quick NAME [OPTIONS]` through nginx; whatever is still running
    at the end is killed, whether the test passed or not."""
    started: list[Cli] = []

    async def start(name: str, *options: str) -> Cli:
        cli = Cli(await run("play", topology.url, "nineball", "--quick", "--name", name, *options))
        started.append(cli)
        return cli

    yield start
    for cli in started:
        await cli.kill()


def outcomes(lines: list[str]) -> dict[int, str]:
    """A player's outcome lines by version (its resync lines, `vN table ...`, left out)."""
    return {int(m[1]): line for line in lines if (m := OUTCOME_LINE.match(line))}


def table_of(lines: list[str]) -> str | None:
    """The table `billiards play` prints once seated (`table <id>: nineball, you are ...`)."""
    seated = next((line for line in lines if line.startswith("table ")), None)
    return None if seated is None else seated.split()[1].rstrip(":")


def match_over(lines: list[str]) -> bool:
    """Whether a player's output ends with the match's end (its last outcome line)."""
    return bool(lines) and "match over" in lines[-1]


async def quick_match(
    start: StartPlayer, *options: str, names: tuple[str, str] = ("Ada", "Bob")
) -> tuple[Cli, Cli, str]:
    """Two `billiards play --quick` processes through nginx, once paired. (A name stays
    claimed for minutes after its player left: another match needs other names.)"""
    ada, bob = await start(names[0], *options), await start(names[1], *options)
    await ada.until(lambda lines: table_of(lines) is not None)
    return ada, bob, str(table_of(ada.lines))


# ----- a whole match: players, a spectator, an EventSource ------------------------------------
async def spectate(topology: Topology, table: str) -> list[tuple[str, bytes]]:
    """Every message of the table's channel (over a WebSocket through nginx, from the oldest
    buffered) until the match is over, with its outcome line as the players print it."""
    client = GameClient(topology.url, topology.http)
    names = names_of(await client.table(table))
    seen: list[tuple[str, bytes]] = []
    async for data in client.messages(f"table-{table}"):
        assert data is not None  # no gap: the channel holds the whole match
        message = json.loads(data)
        if message["kind"] == "outcome":
            outcome = OutcomeMessage.model_validate_json(data)
            seen.append((outcome_line(outcome, names), data))
            if outcome.status is Status.OVER:
                return seen
        else:
            seen.append(("", data))
    raise AssertionError("the table's channel closed before the match was over")


async def first_event(topology: Topology, table: str) -> tuple[bytes, bool]:
    """The first EventSource event of the table's channel through nginx, and whether the
    response was still open when it came (an event held back until the end is not a stream)."""
    url = f"{topology.url}/sub/table-{table}"
    async with topology.http.get(url, headers={"Accept": "text/event-stream"}) as stream:
        assert stream.status == 200 and stream.content_type == "text/event-stream"
        data = b""
        while line := await stream.content.readline():
            if line.startswith(b"data:"):
                data += line.removeprefix(b"data:").strip()
            elif not line.strip() and data:  # the blank line that ends an event
                break
        return data, not stream.content.at_eof()


async def test_a_quick_match_through_nginx_is_played_watched_and_streamed(
    topology: Topology, players: StartPlayer
) -> None:
    ada, bob, table = await quick_match(players)
    watched, (event, open_) = await asyncio.wait_for(
        asyncio.gather(spectate(topology, table), first_event(topology, table)), WAIT_S
    )
    (code_a, lines_a, err_a), (code_b, lines_b, err_b) = await asyncio.gather(
        ada.finish(), bob.finish()
    )
    assert (code_a, code_b) == (0, 0), err_a + err_b
    assert match_over(lines_a) and lines_a[-1] == lines_b[-1]
    # The spectator saw every outcome, and each one as both players did, line for line.
    seen = outcomes([line for line, _ in watched if line])
    assert sorted(seen) == list(range(min(seen), max(seen) + 1)) and seen[max(seen)] == lines_a[-1]
    assert outcomes(lines_a).items() <= seen.items() and outcomes(lines_b).items() <= seen.items()
    assert open_ and json.loads(event) == json.loads(watched[0][1])  # SSE streamed through
    log = topology.nginx.log()
    assert all(entry.status < 500 for entry in log), [e for e in log if e.status >= 500]
    upgrades = [e for e in log if e.path == f"/sub/table-{table}" and e.status == 101]
    assert len(upgrades) >= 3  # both players' feeds and the spectator's, all WebSockets
    assert len({e.upstreams[-1] for e in log if e.upstreams}) > 1  # least_conn spread them


# ----- bodies near the limit ------------------------------------------------------------------
async def test_a_claim_near_the_body_limit_passes_nginx(topology: Topology) -> None:
    """A leaderboard claim padded to the server's own limit reaches a replica whole; one byte
    more is refused by the replica (its JSON 413), not by nginx's client_max_body_size."""
    record, best = next((r, b) for r, b in map(_record, range(1, 20)) if b > 1)
    claim = json.dumps({"game": "nineball", "record": record, "score": best})
    async with topology.http.post(f"{topology.url}/api/players", json={"name": "Cy"}) as answer:
        token = (await answer.json())["token"]
    status, verdict = await post_claim(topology, claim.ljust(MAX_RECORD_BODY), token)
    assert status == 201 and verdict["entry"]["score"] == best
    status, refusal = await post_claim(topology, claim.ljust(MAX_RECORD_BODY + 1), token)
    assert (status, refusal["code"]) == (413, "body_too_large")


async def post_claim(topology: Topology, body: str, token: str) -> tuple[int, dict]:
    """A claim's status and JSON answer; only a replica answers JSON (nginx's own refusals are
    HTML pages), so a body nginx stopped fails here."""
    url = f"{topology.url}/api/leaderboard/claims"
    headers = {"Content-Type": "application/json", "Authorization": f"Bearer {token}"}
    async with topology.http.post(url, data=body, headers=headers) as response:
        assert response.content_type == "application/json", await response.text()
        return response.status, await response.json()


# ----- forwarded headers ----------------------------------------------------------------------
async def test_nginx_forwards_the_client_address_and_host(tmp_path: Path) -> None:
    """The headers a replica receives. The server shows none of them back, so here nginx, from
    the same derived configuration, is in front of an app that answers the headers it got.
    (The server itself reads no forwarded address: the register throttle keys on
    `request.remote`, which behind nginx is nginx's address for every client.)"""

    async def mirror(request: web.Request) -> web.Response:
        return web.json_response(dict(request.headers))

    app = web.Application()
    app.router.add_get("/{path:.*}", mirror)
    async with TestServer(app, host="127.0.0.1") as upstream:
        nginx = Nginx(tmp_path / "nginx", [upstream.port] * REPLICAS)
        try:
            async with aiohttp.ClientSession() as http:
                headers = {"X-Forwarded-For": "203.0.113.7", "Host": "billiards.example:8080"}
                async with http.get(f"{nginx.url}/api/tables", headers=headers) as response:
                    forwarded = await response.json()
        finally:
            nginx.stop()
    assert forwarded["X-Forwarded-For"] == "203.0.113.7, 127.0.0.1"  # the chain, plus the peer
    assert forwarded["Host"].split(":")[0] == "billiards.example"


# ----- a replica dies mid-match ---------------------------------------------------------------
class ClientLeftMatch(AssertionError):
    """A `billiards play` process ended before its match did."""


async def long_lived_connections(ports: list[int], seconds: float = 0.2) -> list[int]:
    """For each local port, the TCP connections established to it that are still there
    `seconds` later (Linux's /proc/net/tcp): the subscribers nginx holds open to a replica,
    not the short requests it passes on."""

    def established(port: int) -> set[tuple[str, str]]:
        rows = [line.split() for line in Path("/proc/net/tcp").read_text().splitlines()[1:]]
        return {
            (row[1], row[2])
            for row in rows
            if row[3] == "01" and int(row[1].rsplit(":", 1)[1], 16) == port
        }

    before = [established(port) for port in ports]
    await asyncio.sleep(seconds)
    return [len(earlier & established(port)) for earlier, port in zip(before, ports, strict=True)]


async def kill_a_feed_mid_match(
    topology: Topology, players: StartPlayer
) -> tuple[Cli, Cli, Replica]:
    """A match under way with the replica holding a player's feed SIGKILLed. A rack can end
    on its break, or be run out before both players' feeds are seen open on a loaded machine,
    before there is anything to kill: so the match is a race to 2 (its first rack's end does
    not end it), played by the weakest bot, whose racks last longest, and if it is over all the
    same, another match (three at most). (Races to 1 ended that early three times in a row in
    CI, once at the second level and once at the weakest.)"""
    for attempt in range(3):
        names = (f"Ada{attempt}", f"Bob{attempt}")
        race = ("--race-to", "2")
        ada, bob, table = await quick_match(players, "--bot", "bot:1", *race, names=names)
        for player in (ada, bob):  # each prints outcomes once its feed is open
            await player.until(lambda lines: len(outcomes(lines)) >= 1 or match_over(lines))
        held = await long_lived_connections([replica.port for replica in topology.replicas])
        victim = topology.replicas[held.index(max(held))]
        async with topology.http.get(f"{topology.url}/api/tables/{table}") as response:
            playing = (await response.json())["status"] == "playing"
        if playing:
            assert max(held) > 0, held  # the victim holds a feed: nothing else stays open
            victim.process.send_signal(signal.SIGKILL)
            return ada, bob, victim
        await asyncio.gather(ada.finish(), bob.finish())
    raise AssertionError("three racks in a row ended on the break")


async def test_a_match_goes_on_when_a_replica_dies(
    topology: Topology, players: StartPlayer
) -> None:
    ada, bob, victim = await kill_a_feed_mid_match(topology, players)
    dead = f"127.0.0.1:{victim.port}"
    # Once nginx has seen the feed end (it logs a WebSocket when it closes), the dead replica
    # has the fewest connections: least_conn picks it, and nginx passes the request on.
    await topology.nginx.logged(lambda e: e.path.startswith("/sub/table-") and dead in e.upstreams)
    # A player's feed reconnecting may have been passed on first, and is logged only when it
    # closes; its failures can make nginx skip the dead replica for fail_timeout (5 s): so
    # requests go on until one passed on from the dead replica is logged.
    deadline, sent = time.monotonic() + WAIT_S, 0
    while sent < 2 * REPLICAS or not [e for e in topology.nginx.log() if dead in e.upstreams[:-1]]:
        assert time.monotonic() < deadline, "nginx passed no request on from the dead replica"
        async with topology.http.get(f"{topology.url}/api/tables") as response:
            assert response.status == 200, await response.text()
        sent += 1
        await asyncio.sleep(0.05 if sent >= 2 * REPLICAS else 0)
    passed_on = [e for e in topology.nginx.log() if dead in e.upstreams[:-1]]
    assert passed_on and all(e.status < 500 and e.upstreams[-1] != dead for e in passed_on)
    # Both players finish the match through the remaining replicas, the feed that died
    # reopened on one of them after the last message it had delivered.
    (code_a, lines_a, err_a), (code_b, lines_b, err_b) = await finish_match(ada, bob)
    assert (code_a, code_b) == (0, 0) and lines_a[-1] == lines_b[-1], err_a + err_b
    resumed = await topology.nginx.logged(
        lambda e: e.path.startswith("/sub/table-") and "last_event_id=" in e.path
    )
    assert resumed.status == 101 and resumed.upstreams[-1] != dead


async def finish_match(*players: Cli) -> list[tuple[int, list[str], str]]:
    """Each player's end, as `Cli.finish`; ClientLeftMatch as soon as one ends before the
    match does (its opponent would then wait for good)."""
    finishing = [asyncio.ensure_future(player.finish()) for player in players]
    pending = set(finishing)
    while pending:
        done, pending = await asyncio.wait(pending, return_when=asyncio.FIRST_COMPLETED)
        for code, lines, err in (task.result() for task in done):
            if not match_over(lines):
                for task in pending:
                    task.cancel()
                raise ClientLeftMatch(f"{lines[0]!r}: exit {code} after {lines[-1]!r} {err}")
    return [task.result() for task in finishing]

"""A real `redis-server` for tests, on a free loopback port in a temporary directory.

Tests that involve Redis talk to the real thing (the project's standard), and some of them must
stop and restart it to prove that nothing acknowledged is lost. So the server runs with the
append-only file on and fsync'ed on every write (`appendfsync always`): a write Redis has
answered is on disk, and a restart on the same port and directory replays it.

Registered for the whole suite by `tests/conftest.py`. A missing binary fails the test with a
clear message; it is never a reason to skip.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

REDIS_BINARY = os.environ.get("REDIS_SERVER", "/usr/bin/redis-server")
START_TIMEOUT_S = 10.0


def free_port() -> int:
    """A TCP port nobody listens on right now on 127.0.0.1 (the OS picks it)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def _answers_ping(port: int) -> bool:
    """True once the server accepts commands (not while it is still loading its AOF)."""
    try:
        with socket.create_connection(("127.0.0.1", port), timeout=0.5) as sock:
            sock.sendall(b"PING\r\n")
            return sock.recv(64).startswith(b"+PONG")
    except OSError:
        return False


class RedisServer:
    """One redis-server process that can be stopped, started and restarted in place."""

    def __init__(self, directory: Path, port: int | None = None) -> None:
        binary = shutil.which(REDIS_BINARY) or shutil.which("redis-server")
        if binary is None:
            raise RuntimeError(
                f"redis-server not found at {REDIS_BINARY} nor on PATH: "
                "install the Debian package 'redis-server' (tests never skip for it)"
            )
        self.binary = binary
        self.directory = directory
        self.port = port or free_port()
        self.process: subprocess.Popen[bytes] | None = None

    @property
    def url(self) -> str:
        return f"redis://127.0.0.1:{self.port}/0"

    @property
    def log_path(self) -> Path:
        return self.directory / "redis.log"

    def start(self) -> None:
        """Start the server and return once it answers PING (after replaying its AOF)."""
        if self.process is not None:
            raise RuntimeError("redis-server is already running")
        args = [
            self.binary,
            "--port", str(self.port),
            "--bind", "127.0.0.1",
            "--dir", str(self.directory),
            "--appendonly", "yes",
            "--appendfsync", "always",
            "--save", "",
            "--daemonize", "no",
            "--logfile", str(self.log_path),
        ]  # fmt: skip
        self.process = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        deadline = time.monotonic() + START_TIMEOUT_S
        while not _answers_ping(self.port):
            if self.process.poll() is not None or time.monotonic() > deadline:
                self._fail_start()
            time.sleep(0.02)

    def _fail_start(self) -> None:
        assert self.process is not None
        self.process.kill()
        _, stderr = self.process.communicate()
        self.process = None
        log = self.log_path.read_text() if self.log_path.exists() else ""
        raise RuntimeError(
            f"redis-server did not start on port {self.port}:\n{stderr.decode()}\n{log[-2000:]}"
        )

    def stop(self, *, kill: bool = False) -> None:
        """Stop the server: a clean shutdown, or with `kill=True` a SIGKILL (a crash)."""
        if self.process is None:
            return
        self.process.send_signal(signal.SIGKILL if kill else signal.SIGTERM)
        try:
            self.process.wait(timeout=START_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.process = None

    def restart(self, *, kill: bool = False) -> None:
        """Stop then start again on the same port and directory (the AOF is replayed)."""
        self.stop(kill=kill)
        self.start()


@pytest.fixture
def redis_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[RedisServer]:
    """A fresh, empty redis-server for one test, stopped afterwards."""
    server = RedisServer(tmp_path_factory.mktemp("redis"))
    server.start()
    try:
        yield server
    finally:
        server.stop()


@pytest.fixture
def redis_url(redis_server: RedisServer) -> str:
    """The URL of a fresh redis-server for one test (`redis://127.0.0.1:PORT/0`)."""
    return redis_server.url

"""The relay as a real server process, for tests that measure it from outside (its RSS).

`python -m tests.relay.process PORT SETTINGS_JSON [REDIS_URL]` serves the relay app with the
test secret, the given `RelaySettings` overrides and defaults otherwise, except that keepalives
are off: the clients of these tests answer no WebSocket ping, and a missed pong would end their
connections early. `RelayProcess` starts that on a free port and stops it.
"""

from __future__ import annotations

import json
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path
from types import TracebackType
from typing import Any

from tests.redis_server import free_port

ROOT = Path(__file__).resolve().parents[2]
START_TIMEOUT_S = 20.0


def rss_bytes(pid: int) -> int:
    """Resident set size of a process, from /proc."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    raise RuntimeError(f"no VmRSS for process {pid}")


class RelayProcess:
    """`with RelayProcess(redis_url) as server:` a relay listening on `server.port`."""

    def __init__(self, redis_url: str | None, **settings: Any) -> None:
        self.port = free_port()
        args = [sys.executable, "-m", "tests.relay.process", str(self.port), json.dumps(settings)]
        self.process = subprocess.Popen([*args, *([redis_url] if redis_url else [])], cwd=ROOT)

    @property
    def rss(self) -> int:
        return rss_bytes(self.process.pid)

    def __enter__(self) -> RelayProcess:
        deadline = time.monotonic() + START_TIMEOUT_S
        while True:
            if self.process.poll() is not None:
                raise RuntimeError(f"relay process exited with {self.process.returncode}")
            with socket.socket() as sock:
                if sock.connect_ex(("127.0.0.1", self.port)) == 0:
                    return self
            if time.monotonic() > deadline:
                self.__exit__(None, None, None)
                raise RuntimeError(f"relay process did not listen on {self.port}")
            time.sleep(0.05)

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.process.send_signal(signal.SIGINT)
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()


def main() -> None:
    from aiohttp import web

    from server.http.app import AppSettings, create_app
    from server.relay.settings import RelaySettings
    from tests.relay.conftest import SECRET

    port, overrides = int(sys.argv[1]), json.loads(sys.argv[2])
    redis_url = sys.argv[3] if len(sys.argv) > 3 else None
    relay = RelaySettings(**{"auth_secret": SECRET, "keepalive": None, **overrides})
    settings = AppSettings(relay=relay, redis_url=redis_url)
    web.run_app(create_app(settings), host="127.0.0.1", port=port, print=None)


if __name__ == "__main__":
    main()

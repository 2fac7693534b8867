"""Browser tests: the real server on a free port, driven by Debian's Chromium through Python
Playwright (launched by path: never a browser download).

WebGL runs headless on SwiftShader, Chromium's software renderer, so the tests need no GPU.
Every page a test opens is watched for console errors and uncaught exceptions; a test that
saw one fails at teardown. Screenshots go to tests/e2e/artefacts/ (gitignored) for a person
to look at.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, ConsoleMessage, Page, sync_playwright

from tests.redis_server import free_port

CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
ARTEFACTS = Path(__file__).parent / "artefacts"
START_TIMEOUT_S = 30.0
#: Software WebGL: ANGLE on SwiftShader, allowed although no GPU is there.
CHROMIUM_ARGS = [
    "--use-gl=angle",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--ignore-gpu-blocklist",
    "--disable-dev-shm-usage",
]


def _answers(url: str) -> bool:
    try:
        with urllib.request.urlopen(url, timeout=1) as response:
            return response.status < 500
    except OSError:
        return False


class Server:
    """`billiards serve` in a subprocess, its data in a temporary directory."""

    def __init__(self, directory: Path) -> None:
        self.directory = directory
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        self.process: subprocess.Popen[bytes] | None = None

    def start(self) -> None:
        command = [sys.executable, "-m", "server.cli", "serve", "--port", str(self.port)]
        env = {**os.environ, "BILLIARDS_RELAY_SECRET": "e2e-secret-0123456789abcdef"}
        self.log = open(self.directory / "server.log", "ab")  # noqa: SIM115 (closed in stop)
        self.process = subprocess.Popen(
            command, cwd=self.directory, env=env, stdout=self.log, stderr=subprocess.STDOUT
        )
        deadline = time.monotonic() + START_TIMEOUT_S
        while not _answers(self.url + "/web/tables"):
            if self.process.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"server did not start; see {self.directory / 'server.log'}")
            time.sleep(0.1)

    def stop(self) -> None:
        if self.process is not None:
            self.process.terminate()
            self.process.wait(timeout=10)
            self.process = None
            self.log.close()


@pytest.fixture(scope="session")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    if not (Path(__file__).resolve().parents[2] / "web" / "dist" / "play.html").is_file():
        raise RuntimeError("the web client is not built: run `bash dev.sh test` (npm ci, build)")
    srv = Server(tmp_path_factory.mktemp("server"))
    srv.start()
    yield srv
    srv.stop()


@pytest.fixture(scope="session")
def browser() -> Iterator[Browser]:
    binary = shutil.which(CHROMIUM) or shutil.which("chromium")
    if binary is None:
        raise RuntimeError(
            f"Chromium not found at {CHROMIUM}: install the Debian package 'chromium' "
            "(`bash dev.sh test` does; browser tests never skip)"
        )
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=binary, args=CHROMIUM_ARGS)
        yield b
        b.close()


class Console:
    """The console errors and uncaught exceptions of every page opened through `open_page`."""

    def __init__(self) -> None:
        self.errors: list[str] = []

    def watch(self, page: Page, who: str) -> Page:
        def on_console(message: ConsoleMessage) -> None:
            if message.type == "error":
                self.errors.append(f"{who}: console: {message.text} at {message.location}")

        page.on("console", on_console)
        page.on("pageerror", lambda e: self.errors.append(f"{who}: uncaught: {e}"))
        return page


@pytest.fixture
def console() -> Iterator[Console]:
    watcher = Console()
    yield watcher
    assert not watcher.errors, "\n".join(watcher.errors)


@pytest.fixture
def open_page(browser: Browser, server: Server, console: Console):
    """open_page(path, who="player", viewport=...) -> a page in its own browser context (its own
    localStorage: a separate person), watched for console errors."""
    contexts = []

    def open_(path: str, who: str = "player", viewport: dict | None = None, context=None) -> Page:
        if context is None:
            context = browser.new_context(viewport=viewport or {"width": 1280, "height": 800})
            contexts.append(context)
        page = console.watch(context.new_page(), who)
        page.goto(server.url + path)
        return page

    yield open_
    for context in contexts:
        context.close()


def artefact(name: str, suffix: str = ".png") -> Path:
    """The path of artefact NAME under tests/e2e/artefacts/ (created)."""
    ARTEFACTS.mkdir(exist_ok=True)
    return ARTEFACTS / f"{name}{suffix}"


def screenshot(page: Page, name: str) -> Path:
    """Save what the page shows as the artefact NAME.png."""
    path = artefact(name)
    page.screenshot(path=str(path))
    return path

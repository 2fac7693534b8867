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
from collections.abc import Iterator, Sequence
from pathlib import Path

import pytest
from playwright.sync_api import Browser, ConsoleMessage, Page, sync_playwright

from rules.pickers import pick
from rules.state import State
from tests.redis_server import free_port

CHROMIUM = os.environ.get("CHROMIUM", "/usr/bin/chromium")
ARTEFACTS = Path(__file__).parent / "artefacts"
START_TIMEOUT_S = 30.0
#: The test server's grace period (`billiards serve --grace`): a gone player's win may be
#: claimed this long after he is shown disconnected, not a minute, so a test can wait for it.
GRACE_S = 5.0
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
        command += ["--grace", str(GRACE_S)]
        command += ["--names-per-address", "1000"]  # every browser of the suite is on loopback
        env = {**os.environ, "BILLIARDS_RELAY_SECRET": "e2e-secret-0123456789abcdef0123456789"}
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


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    """One Chromium per test module. (Playwright's sync API keeps an event loop of its own while
    it runs; stopped at the end of each e2e module, it never meets the suite's asyncio tests.)"""
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
        self.allowed: list[str] = []

    def allow(self, text: str) -> None:
        """Let console errors containing `text` pass: a test that provokes a refusal on purpose
        (the browser logs every non-2xx answer as a failed resource load)."""
        self.allowed.append(text)

    def watch(self, page: Page, who: str) -> Page:
        def on_console(message: ConsoleMessage) -> None:
            if message.type == "error" and not any(a in message.text for a in self.allowed):
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

    def open_(
        path: str,
        who: str = "player",
        viewport: dict | None = None,
        context=None,
        service_workers: str = "block",
    ) -> Page:
        # The service worker is tested on its own (test_app.py); elsewhere it would only stand
        # between the page and the routes some tests put on its requests.
        if context is None:
            viewport = viewport or {"width": 1280, "height": 800}
            context = browser.new_context(viewport=viewport, service_workers=service_workers)
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


_names = iter(range(1, 10**6))


def unique_name(prefix: str) -> str:
    """A display name nobody online has (names are unique among players online)."""
    return f"{prefix}{os.getpid() % 1000}x{next(_names)}"


def name_at_home(page: Page, server: Server, prefix: str) -> None:
    """Open the home page and play as a new name (its name form)."""
    page.goto(server.url + "/")
    page.fill("#name", unique_name(prefix))
    page.click("#name-form button")
    page.wait_for_function("document.getElementById('who').textContent !== ''")


def create_at_home(page: Page, game: str, private: bool = False) -> str:
    """Create a table of `game` with the home page's form; its id, once the page is on it."""
    page.select_option("#create-game", game)
    page.set_checked("#private", private)
    page.click("#create-form button[type=submit]")
    page.wait_for_url("**/table/*")
    return page.url.rsplit("/", 1)[1]


def join_as(page: Page, name: str) -> None:
    """Take the free seat of the table the page shows, as new player `name` (the join button,
    then the name form), until the page shows the player seated."""
    join = page.get_by_role("button", name="Join this table")
    join.click()
    enter_name(page, name)
    join.wait_for(state="detached")


def enter_name(page: Page, name: str) -> None:
    """Answer the page's name form (shown to a visitor without an identity)."""
    page.fill(".overlay input", name)
    page.click(".overlay button[type=submit]")
    page.wait_for_selector(".overlay", state="detached")


def wait_shown(page: Page, count: int = 1, timeout: float = 60_000) -> None:
    """Until the play page has shown `count` table states (views or outcomes, animated)."""
    page.wait_for_function("(n) => (window.billiards?.shown ?? 0) >= n", arg=count, timeout=timeout)


def wait_version(page: Page, version: int, timeout: float = 90_000) -> None:
    """Until the page shows the table at `version` (any animation played to its end)."""
    page.wait_for_function(
        "(v) => (window.billiards?.version ?? -1) >= v", arg=version, timeout=timeout
    )


#: Enough shots for both players of a match to have had a turn (a player who pots goes on:
#: the strokes aim at the lowest ball, and once in CI the breaker kept the table for eight).
MAX_SHOTS = 16


def take_turn(pages: dict[int, Page], view: dict, hold_ms: int = 450) -> None:
    """The seat to act in table view `view` acts in its page (the first choice offered, or a
    keyboard stroke aimed a little left), until that page shows the version after."""
    shooter = pages[view["next"]["seat"]]
    wait_version(shooter, view["version"])
    if view["next"]["kinds"] == ["choice"]:
        shooter.locator("#choices button").first.click()
    else:
        strike_with_keys(shooter, hold_ms=hold_ms, left=2)
    try:
        shooter.wait_for_function(
            "(v) => window.billiards.version > v", arg=view["version"], timeout=90_000
        )
    except Exception as e:
        raise AssertionError(shooter.get_by_role("status").inner_text()) from e


def wait_drawn(page: Page, camera: str | None = None) -> None:
    """Until the table shows every change asked of it (with `camera`: in that view)."""
    page.wait_for_function(
        "(camera) => window.billiards.drawn()"
        " && (camera === null || window.billiards.camera() === camera)",
        arg=camera,
    )


def drawn_balls(page: Page) -> dict[str, list[float]]:
    """Where the page draws each ball (table coordinates)."""
    return page.evaluate("window.billiards.balls()")


def strike_with_keys(page: Page, hold_ms: int = 500, left: int = 0) -> None:
    """Aim with the arrow keys, then hold Space for the power and let go."""
    page.locator("#table").focus()
    for _ in range(left):
        page.keyboard.press("ArrowLeft")
    page.keyboard.down(" ")
    page.wait_for_timeout(hold_ms)
    page.keyboard.up(" ")


def canvas_colours(page: Page) -> dict[str, float]:
    """Fractions of the table canvas's pixels that are mostly blue, mostly green, and blank
    (the page's background): read back from the WebGL canvas."""
    return page.evaluate(
        """() => {
            const gl = document.getElementById('table');
            const c = document.createElement('canvas');
            c.width = 200; c.height = Math.round(200 * gl.height / gl.width);
            const ctx = c.getContext('2d');
            ctx.drawImage(gl, 0, 0, c.width, c.height);
            const d = ctx.getImageData(0, 0, c.width, c.height).data;
            let blue = 0, green = 0, blank = 0;
            for (let i = 0; i < d.length; i += 4) {
                const [r, g, b] = [d[i], d[i + 1], d[i + 2]];
                if (b > r + 40 && b > g + 15) blue++;
                else if (g > r + 30 && g > b + 15) green++;
                if (r < 30 && g < 30 && b < 35) blank++;
            }
            const n = d.length / 4;
            return {blue: blue / n, green: green / n, blank: blank / n};
        }"""
    )


class Api:
    """The game service's HTTP API as one player (the token a page keeps, or a new one),
    through Playwright's request context: the tests put tables where the page is to be shown."""

    def __init__(self, page: Page, server: Server) -> None:
        self.page, self.server = page, server

    def token(self) -> str | None:
        return self.page.evaluate("localStorage.getItem('billiards.token')")

    def call(self, method: str, path: str, body: dict | None = None) -> dict:
        token = self.token()
        headers = {"Authorization": f"Bearer {token}"} if token else {}
        answer = self.page.request.fetch(
            self.server.url + path, method=method, headers=headers, data=body
        )
        assert answer.ok, (path, answer.status, answer.text())
        return answer.json()

    def sign_in(self, name: str) -> dict:
        """Become player `name` and keep the token where the client looks (the server's
        origin's localStorage), as the page's name form does."""
        if not self.page.url.startswith(self.server.url):
            self.page.goto(self.server.url + "/")
        answer = self.call("POST", "/api/players", {"name": name})
        self.page.evaluate(
            """(a) => {
                localStorage.setItem('billiards.token', a.token);
                localStorage.setItem('billiards.player', JSON.stringify(a.player));
            }""",
            answer,
        )
        return answer["player"]

    def table(self, table_id: str) -> dict:
        return self.call("GET", f"/api/tables/{table_id}")

    def practice(self, game: str) -> str:
        """A new practice table of `game`, kept where /practice/{game} looks for it."""
        table_id = self.call("POST", "/api/tables", {"game": game, "mode": "practice"})["id"]
        self.page.evaluate(
            "([game, id]) => localStorage.setItem('billiards.practice.' + game, id)",
            [game, table_id],
        )
        return table_id

    def play(self, table_id: str, action: dict, timeout: float = 60.0) -> dict:
        """Send input `action` for the table as it is; the view once its outcome is in."""
        view = self.table(table_id)
        shot_id = f"e2e{view['version']:06d}x{next(_names)}"
        body = {"version": view["version"], "shot_id": shot_id, "input": action}
        self.call("POST", f"/api/tables/{table_id}/intents", body)
        deadline = time.monotonic() + timeout
        while (now := self.table(table_id))["version"] <= view["version"]:
            assert time.monotonic() < deadline, f"no outcome for {action} in {timeout} s"
            time.sleep(0.1)
        return now

    def play_until(self, table_id: str, done, most: int = 60) -> dict:
        """Play the table with the simple shot picker (rules.pickers) until done(state) holds
        for the referee's state; the view then."""
        for _ in range(most):
            view = self.table(table_id)
            if done(State.model_validate(view["state"])):
                return view
            self.play_picked(table_id)
        raise AssertionError(f"not there after {most} inputs")

    def play_picked(self, table_id: str) -> dict:
        """Play the simple shot picker's input for the table as it is; the view after."""
        state = State.model_validate(self.table(table_id)["state"])
        return self.play(table_id, pick(state).model_dump(mode="json", exclude_defaults=True))


def both_play(apis: Sequence[Api | None], table_id: str, timeout: float = 60.0) -> dict:
    """Play the shot picker's inputs at a match until each seat has played one of its own (a
    match ended before that is neither rated nor recorded); the view then. A seat without an
    Api in `apis` (None: the bot's) is waited for."""
    played: set[int] = set()
    view = apis[0].table(table_id) if apis[0] else apis[1].table(table_id)
    deadline = time.monotonic() + timeout
    while played != {0, 1} and view["status"] == "playing":
        seat = view["next"]["seat"]
        api = apis[seat]
        if api is None:  # the bot's turn: it plays by itself
            assert time.monotonic() < deadline, "the bot did not play"
            time.sleep(0.1)
            before = view["version"]
            view = (apis[0] or apis[1]).table(table_id)
            if view["version"] > before:
                played.add(seat)
            continue
        view = api.play_picked(table_id)
        played.add(seat)
    return view


class Watched:
    """A nine-ball match of two new players, pages A and B with their `apis` (Ada created the
    table, Bob joined it: `view`, the table then), and a third page, C, to watch it."""

    def __init__(
        self, browser: Browser, server: Server, console: Console, prefix: str, **context: object
    ) -> None:
        self.contexts = [browser.new_context(**context) for _ in "ABC"]
        ada, bob, cy = (
            console.watch(c.new_page(), who) for c, who in zip(self.contexts, "ABC", strict=True)
        )
        self.pages = (ada, bob, cy)
        self.apis = [Api(ada, server), Api(bob, server)]
        self.apis[0].sign_in(unique_name(prefix + "a"))
        self.apis[1].sign_in(unique_name(prefix + "b"))
        self.table: str = self.apis[0].call("POST", "/api/tables", {"game": "nineball"})["id"]
        self.view = self.apis[1].call("POST", f"/api/tables/{self.table}/join")

    def close(self) -> None:
        for context in self.contexts:
            context.close()

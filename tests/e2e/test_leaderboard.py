"""The leaderboard: a claimed break is checked by the server, listed, and its replay plays to
the record's final positions; a practice rack's break enters by itself, and its replay link
plays the rack to the positions it ended in."""

from __future__ import annotations

import json
import math
import subprocess
import sys
import time
import urllib.request

from rules.game import Setup
from rules.record import GameRecord, replay
from rules.selfplay import selfplay
from tests.e2e.conftest import drawn_balls, screenshot, unique_name

#: How long the command-line client may take to finish a practice rack (s).
RACK_TIMEOUT_S = 120


def claimable(seed: int) -> tuple[str, int]:
    record, played = selfplay(Setup(game="nineball", seed=seed), max_inputs=60)
    return record.to_json(), max(played.final.best)


def test_a_claimed_break_is_checked_and_listed(open_page, console):
    record, best = next((r, b) for r, b in map(claimable, range(1, 20)) if b > 0)
    page = open_page("/leaderboard/nineball")
    page.wait_for_selector("#board-status:not(:empty)")
    name = unique_name("Cl")
    page.fill("#claim-record", record)
    page.fill("#claim-name", name)
    console.allow("422")  # the wrong claim below is refused on purpose
    page.fill("#claim-score", str(best + 1))
    page.click("#claim-form button[type=submit]")
    page.wait_for_selector("#claim-verdict:has-text('Refused')")
    assert page.locator("#board tbody tr", has_text=name).count() == 0
    page.fill("#claim-score", str(best))
    page.click("#claim-form button[type=submit]")
    page.wait_for_selector("#claim-verdict:has-text('Accepted')")
    row = page.locator("#board tbody tr", has_text=name)
    assert row.count() == 1 and str(best) in row.inner_text()
    screenshot(page, "leaderboard")
    # Its replay plays though it was played on no table: the server replays the record.
    row.get_by_role("link", name="Watch").click()
    page.wait_for_url("**/replay/*")
    page.select_option("#speed", "4")
    shots = sum("strike" in action for action in json.loads(record)["inputs"])
    page.wait_for_function("(n) => window.billiards.shots === n", arg=shots, timeout=60_000)
    page.locator("#shots li a").last.click()  # straight to the last shot
    page.wait_for_function("(n) => window.billiards.shown === n - 1", arg=shots, timeout=60_000)
    final = replay(GameRecord.model_validate_json(record)).final
    drawn = drawn_balls(page)
    assert drawn.keys() == final.balls.keys()
    for ball, p in drawn.items():
        assert math.dist(p, final.balls[ball]) < 1e-6, ball


def get_json(url: str) -> dict:
    with urllib.request.urlopen(url, timeout=10) as answer:
        return json.load(answer)


def practice_rack(server, name: str) -> dict:
    """Practise nine-ball with the command-line client until its first rack with a break ends;
    that rack's leaderboard entry."""
    client = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "server.cli",
            "play",
            server.url,
            "nineball",
            "--practice",
            "--name",
            name,
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.monotonic() + RACK_TIMEOUT_S
        while time.monotonic() < deadline:
            board = get_json(f"{server.url}/api/leaderboard/nineball")
            mine = [b for b in board["breaks"] if b["name"] == name]
            if mine:
                return mine[0]
            time.sleep(0.1)
        raise AssertionError(f"no practice break by {name} within {RACK_TIMEOUT_S} s")
    finally:
        client.terminate()
        client.wait(timeout=10)


def test_a_practice_break_enters_and_its_replay_plays(open_page, server):
    name = unique_name("Cli")
    entry = practice_rack(server, name)
    assert entry["source"] == "practice" and entry["replay"]
    page = open_page("/leaderboard/nineball")
    # The client plays on after that rack, so the name may have more rows: take this one's.
    watch = page.locator(f'a[href$="/replay/{entry["replay"]}"]')
    row = page.locator("#board tbody tr", has_text=name, has=watch)
    row.wait_for()
    row.get_by_role("link", name="Watch").click()
    page.wait_for_url(f"**/replay/{entry['replay']}")
    page.select_option("#speed", "4")
    page.wait_for_function("() => window.billiards.shots > 0", timeout=30_000)
    shots = page.evaluate("window.billiards.shots")
    page.wait_for_function("(n) => window.billiards.shown === n - 1", arg=shots, timeout=180_000)
    # The server's record of the rack, replayed here by the engine, ends where the page does.
    saved = get_json(f"{server.url}/api/replays/{entry['replay']}")
    final = replay(GameRecord.model_validate(saved["record"])).final
    drawn = drawn_balls(page)
    assert drawn.keys() == final.balls.keys()
    for ball, p in drawn.items():
        assert math.dist(p, final.balls[ball]) < 1e-6, ball
    screenshot(page, "replay-of-a-rack")

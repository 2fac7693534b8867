"""A replay link plays the table's shots again and ends on the server's final positions; a
shared link opens at its shot."""

from __future__ import annotations

import math

from tests.e2e.conftest import (
    drawn_balls,
    enter_name,
    screenshot,
    strike_with_keys,
    unique_name,
    wait_shown,
)


def test_replay_reaches_the_final_positions(open_page, server):
    page = open_page("/practice/nineball")
    enter_name(page, unique_name("Rp"))
    wait_shown(page)
    for shots in (1, 2):
        strike_with_keys(page, hold_ms=350 * shots)
        wait_shown(page, 1 + shots)
    table_id = page.evaluate("localStorage.getItem('billiards.practice.nineball')")
    final = page.request.get(f"{server.url}/api/tables/{table_id}").json()

    replay = open_page(f"/replay/{table_id}", who="replay")
    replay.select_option("#speed", "4")
    replay.wait_for_function("() => window.billiards.shots === 2")
    replay.wait_for_function("() => window.billiards.shown === 1", timeout=90_000)
    drawn = drawn_balls(replay)
    assert drawn.keys() == final["state"]["balls"].keys()
    for ball, p in drawn.items():
        assert math.dist(p, final["state"]["balls"][ball]) < 1e-9, ball
    assert replay.locator("#shots li").count() == 2
    assert "Shot 2 of 2" in replay.get_by_role("status").inner_text()
    screenshot(replay, "replay")

    replay.click("#share")
    link = replay.locator("#shared").inner_text()
    assert link.endswith(f"/replay/{table_id}?shot=2")
    shared = open_page(link.removeprefix(server.url), who="shared")
    shared.wait_for_function("() => window.billiards.shown === 1", timeout=90_000)
    assert shared.locator("#shots li").count() == 2

"""A replay link plays the table's shots again and ends on the server's final positions; a
shared link opens at its shot."""

from __future__ import annotations

import math
from urllib.parse import quote

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


def test_an_ended_practice_lists_its_rack_and_its_replay_names_the_player(open_page, server):
    name = unique_name("Rp ")  # a space: the profile link encodes it
    page = open_page("/practice/eightball")
    enter_name(page, name)
    wait_shown(page)
    profile = f"/player/{quote(name)}"
    assert page.locator("#players a.profile").first.get_attribute("href") == profile
    table_id = page.evaluate("localStorage.getItem('billiards.practice.eightball')")

    def last_shot_ended_its_rack() -> bool:
        view = page.request.get(f"{server.url}/api/tables/{table_id}").json()
        return view["last_outcome"] is None or view["last_outcome"]["decision"]["over"]

    # Shots until the rack being played has one (a break may end a rack: the next is empty).
    shown = 1
    for shots in range(1, 7):
        strike_with_keys(page, hold_ms=300 * (1 + shots % 2))
        shown += 1
        wait_shown(page, shown)
        if shots >= 2 and not last_shot_ended_its_rack():
            break
    # Ending the practice (asked first) keeps the rack being played, unfinished as it is.
    page.get_by_role("button", name="End practice").click()
    page.get_by_role("button", name="Yes, end it").click()
    page.wait_for_selector("#result")
    over = page.request.get(f"{server.url}/api/tables/{table_id}").json()
    assert (over["status"], over["ended"]) == ("over", "resigned")
    assert len(over["replays"]) == over["rack"]
    assert "Practice over" in page.get_by_role("status").inner_text()
    page.wait_for_url(f"**/table/{table_id}")  # the ended practice's own address
    page.reload()  # the list is the server's: it survives a reload
    link = page.locator("#result #replays a").last
    link.wait_for()
    assert link.inner_text() == f"rack {over['rack']} (unfinished)"
    screenshot(page, "practice-ended")

    link.click()
    page.wait_for_url(f"**/replay/{over['replays'][-1]}")
    page.select_option("#speed", "4")
    page.wait_for_function("() => window.billiards.shots > 0", timeout=30_000)
    shots = page.evaluate("window.billiards.shots")
    page.wait_for_function("(n) => window.billiards.shown === n - 1", arg=shots, timeout=90_000)
    drawn = drawn_balls(page)
    assert drawn.keys() == over["state"]["balls"].keys()
    for ball, p in drawn.items():
        assert math.dist(p, over["state"]["balls"][ball]) < 1e-9, ball
    # One person played both sides: the replay names that person, never P1 or P2.
    players = page.locator("#players").inner_text()
    assert players.count(name) == 2 and "Player 2" not in players
    shots_words = page.locator("#shots").inner_text() + page.get_by_role("status").inner_text()
    assert "P1" not in shots_words and "P2" not in shots_words and name in shots_words
    assert page.locator("#players a.profile").first.get_attribute("href") == profile
    assert "Not finished: the practice was ended here." in page.locator("#about").inner_text()
    screenshot(page, "practice-replay-unfinished")

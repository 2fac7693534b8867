"""Every page loads without a console error; the table pages draw the table in its colours;
the first load stays within 400 KB gzipped (HTML, JS, CSS and everything else fetched)."""

from __future__ import annotations

import json

import pytest

from tests.e2e.conftest import (
    artefact,
    canvas_colours,
    enter_name,
    screenshot,
    unique_name,
    wait_drawn,
    wait_shown,
)

#: The issue's bound on a first load, gzipped.
FIRST_LOAD_LIMIT = 400 * 1024

#: Bytes that came over the wire for the page and everything it fetched so far.
TRANSFERRED = """() => {
    const entries = [...performance.getEntriesByType('navigation'),
                     ...performance.getEntriesByType('resource')];
    return entries.map((e) => ({name: e.name, bytes: e.transferSize, body: e.encodedBodySize}));
}"""


def first_load(page) -> int:
    entries = page.evaluate(TRANSFERRED)
    return sum(e["bytes"] for e in entries if not e["name"].endswith(("/web/tables",)))


@pytest.mark.parametrize(
    "game, cloth",
    [("nineball", "blue"), ("eightball", "green"), ("snooker", "green"), ("three_cushion", "blue")],
)
def test_practice_table_draws_in_its_colours(open_page, game, cloth):
    page = open_page(f"/practice/{game}")
    enter_name(page, unique_name("Pr"))
    wait_shown(page)
    wait_drawn(page)  # a frame with the balls placed
    colours = canvas_colours(page)
    assert colours[cloth] > 0.2, colours  # the cloth fills much of the view
    assert colours["blank"] < 0.9, colours
    status = page.get_by_role("status").inner_text()
    assert "to shoot" in status and "Score" in status
    screenshot(page, f"practice-{game}-aim")
    page.keyboard.press("v")  # the top view
    wait_drawn(page, "top")
    assert canvas_colours(page)[cloth] > 0.2
    screenshot(page, f"practice-{game}-top")


def test_home_page_and_first_load_size(open_page):
    sizes = {}
    page = open_page("/", who="home")
    page.wait_for_selector("#games .card")
    page.wait_for_load_state("networkidle")
    sizes["/"] = first_load(page)
    screenshot(page, "home")
    page = open_page("/practice/snooker", who="practice")
    enter_name(page, unique_name("Sz"))
    wait_shown(page)
    sizes["/practice/snooker"] = first_load(page)
    page = open_page("/diagrams", who="diagrams")
    page.wait_for_selector("#motion-chart canvas")
    sizes["/diagrams"] = first_load(page)
    artefact("first-load", ".json").write_text(json.dumps(sizes, indent=1))
    print("first load (bytes over the wire, gzipped):", sizes)
    for path, size in sizes.items():
        assert 0 < size <= FIRST_LOAD_LIMIT, (path, size)


def test_leaderboard_page_loads(open_page):
    page = open_page("/leaderboard/snooker")
    page.wait_for_load_state("networkidle")
    screenshot(page, "leaderboard")


def test_mobile_layout(browser, server, console):
    context = browser.new_context(
        viewport={"width": 390, "height": 844},
        is_mobile=True,
        has_touch=True,
        device_scale_factor=2,
    )
    page = console.watch(context.new_page(), "phone")
    page.goto(server.url + "/practice/eightball")
    enter_name(page, unique_name("Ph"))
    wait_shown(page)
    wait_drawn(page)
    # Portrait: the table above the panel, the Hit button on screen without scrolling sideways.
    canvas = page.locator("#table").bounding_box()
    hit = page.locator("#hit").bounding_box()
    assert canvas["width"] <= 390 and hit["y"] > canvas["y"] + canvas["height"] - 1
    assert page.evaluate("document.documentElement.scrollWidth") <= 390
    page.locator("#view-toggle").tap()
    wait_drawn(page, "top")
    assert canvas_colours(page)["green"] > 0.2
    screenshot(page, "practice-phone")
    # The touch controls strike: a tap on the tip disc (low: back spin), then on Hit.
    tip = page.locator("#tip").bounding_box()
    page.touchscreen.tap(tip["x"] + tip["width"] / 2, tip["y"] + tip["height"] * 0.7)
    assert "back" in page.locator("#tip").get_attribute("aria-valuetext")
    page.locator("#hit").tap()
    wait_shown(page, 2)
    assert "potted" in page.get_by_role("status").inner_text()
    context.close()

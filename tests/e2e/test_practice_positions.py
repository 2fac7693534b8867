"""The practice table as a practice tool in the browser: a position set up by dragging balls
off and across the table, played, its shot taken again from the same position, shared as a
link and opened in a second browser context (another person) where it is set up as shared;
a new rack (the shot again, a re-rack, a named position) no longer telling the shot before it;
and a 7 ft nine-ball table created from the lobby, drawn from the server's smaller geometry."""

from __future__ import annotations

import math

from playwright.sync_api import Page

from tests.e2e.conftest import (
    drawn_balls,
    enter_name,
    name_at_home,
    screenshot,
    strike_with_keys,
    unique_name,
    wait_drawn,
    wait_shown,
)

#: Where the test puts the two balls it keeps, as fractions of the table's width and length:
#: the 9 near the top right pocket, the cue ball behind it on the line to that pocket.
NINE_AT, CUE_AT = (0.84, 0.92), (0.6, 0.8)


def table_of(page: Page, server) -> dict:
    table_id = page.evaluate(
        "localStorage.getItem('billiards.practice.' + location.pathname.split('/')[2])"
    )
    return page.request.get(f"{server.url}/api/tables/{table_id}").json()


def drag(page: Page, start: list[float], end: list[float]) -> None:
    """Drag on the canvas from table point `start` to table point `end` (or beyond the rails)."""
    a = page.evaluate("(p) => window.billiards.screenOf(p)", start)
    b = page.evaluate("(p) => window.billiards.screenOf(p)", end)
    page.mouse.move(*a)
    page.mouse.down()
    for k in range(1, 6):
        page.mouse.move(a[0] + (b[0] - a[0]) * k / 5, a[1] + (b[1] - a[1]) * k / 5)
    page.mouse.up()


def editing(page: Page) -> dict[str, list[float]]:
    return page.evaluate("window.billiards.practice().editing")


def close(a: dict[str, list[float]], b: dict[str, list[float]], tol: float) -> bool:
    return a.keys() == b.keys() and all(math.dist(a[k], b[k]) <= tol for k in a)


def test_a_position_set_up_by_dragging_is_played_retaken_and_shared(open_page, server):
    page = open_page("/practice/nineball")
    enter_name(page, unique_name("Set"))
    wait_shown(page)
    page.click("#edit-position")
    wait_drawn(page, "top")
    # Whatever draws the page again meanwhile (a presence message, a refusal) leaves the editor
    # its words and keeps the stroke's controls away.
    page.evaluate("window.billiards.render()")
    assert page.locator("#status").inner_text().startswith("Setting up a position")
    assert page.locator("#hint").inner_text() == ""
    assert page.locator("#controls").is_hidden() and page.locator("#view-toggle").is_hidden()
    table = page.evaluate("window.billiards.table()")
    w, l = table["w"], table["l"]
    # Every object ball but the 9 off the table, over the bottom rail.
    for ball, p in sorted(editing(page).items()):
        if ball not in ("9", "cue"):
            drag(page, p, [p[0], -0.08])
    assert set(editing(page)) == {"9", "cue"}
    drag(page, editing(page)["9"], [NINE_AT[0] * w, NINE_AT[1] * l])
    drag(page, editing(page)["cue"], [CUE_AT[0] * w, CUE_AT[1] * l])
    set_up = editing(page)
    assert math.dist(set_up["9"], [NINE_AT[0] * w, NINE_AT[1] * l]) < 0.02
    # A ball put back from the tray lands on the table, and can be dragged off again.
    page.click(".tray-ball[data-ball='3']")
    assert "3" in editing(page)
    drag(page, editing(page)["3"], [-0.08, l / 2])
    assert editing(page).keys() == {"9", "cue"}
    screenshot(page, "practice-setup-dragging")

    version = page.evaluate("window.billiards.version")
    page.click("#apply-position")
    page.wait_for_function("(v) => window.billiards.version > v", arg=version)
    view = table_of(page, server)
    assert view["position"] is not None and close(view["state"]["balls"], set_up, 1e-4)
    assert close(drawn_balls(page), view["state"]["balls"], 1e-9)
    position = view["state"]["balls"]

    shown = page.evaluate("window.billiards.shown")
    strike_with_keys(page, hold_ms=500)
    wait_shown(page, shown + 1)
    played = table_of(page, server)
    assert played["last_outcome"]["input"]["strike"]["ball"] == "cue"
    if played["last_outcome"]["decision"]["over"]:  # the 9 potted: the set-up comes again
        assert played["rack"] == view["rack"] + 1 and played["state"]["balls"] == position
    else:
        assert played["state"]["balls"] != position
    screenshot(page, "practice-setup-played")

    # The shot again: the position the last shot was played from, as it was.
    version = page.evaluate("window.billiards.version")
    page.click("#retake")
    page.wait_for_function("(v) => window.billiards.version > v", arg=version)
    wait_drawn(page)
    assert close(drawn_balls(page), position, 1e-9)

    page.click("#share-position")
    link = page.locator("#position-link")
    link.wait_for()
    url = link.get_attribute("href")
    assert "/practice/nineball?position=" in url
    screenshot(page, "practice-setup-shared")

    friend = open_page(url.removeprefix(server.url), who="friend")
    enter_name(friend, unique_name("Fr"))
    wait_shown(friend)
    friend.wait_for_url("**/practice/nineball")  # the link's position is set up, then dropped
    theirs = table_of(friend, server)
    assert theirs["id"] != played["id"] and theirs["position"] == position
    assert close(drawn_balls(friend), position, 1e-9)
    screenshot(friend, "practice-setup-opened-elsewhere")


def test_a_named_position_is_set_up_from_the_list(open_page, server):
    page = open_page("/practice/eightball")
    enter_name(page, unique_name("Nm"))
    wait_shown(page)
    version = page.evaluate("window.billiards.version")
    page.select_option("#preset", "combination")
    page.click("#preset-go")
    page.wait_for_function("(v) => window.billiards.version > v", arg=version)
    wait_drawn(page)
    view = table_of(page, server)
    assert view["position"] == view["presets"]["combination"]
    assert close(drawn_balls(page), view["presets"]["combination"], 1e-9)
    page.click("#view-toggle")
    wait_drawn(page, "top")
    screenshot(page, "practice-preset-combination")


def test_a_new_rack_no_longer_tells_the_last_shot(open_page, server):
    page = open_page("/practice/nineball")
    enter_name(page, unique_name("Nw"))
    wait_shown(page)
    status = page.get_by_role("status")
    # A shot, then each way to a new rack: the shot again, a re-rack, a named position. The
    # referee's words of the shot ("... potted ...") go with the rack it was played in.
    for new_rack in ("#retake", "#rerack", "#preset-go"):
        shown = page.evaluate("window.billiards.shown")
        strike_with_keys(page, hold_ms=400)
        wait_shown(page, shown + 1)
        assert "potted" in status.inner_text()
        version = page.evaluate("window.billiards.version")
        page.click(new_rack)
        page.wait_for_function("(v) => window.billiards.version > v", arg=version)
        assert table_of(page, server)["last_outcome"] is None
        assert "potted" not in status.inner_text(), new_rack
        assert "to shoot" in status.inner_text()


def test_a_broken_position_link_says_why(open_page, console):
    console.allow("the server responded with a status of 422")
    page = open_page("/practice/nineball?position=not-a-position")
    enter_name(page, unique_name("Bad"))
    status = page.locator("#status")
    status.filter(has_text="shared position cannot be set up").wait_for()


def ball_to_table_ratio(page: Page) -> float:
    """The drawn ball's diameter over the drawn table's width, in screen pixels."""
    t = page.evaluate("window.billiards.table()")
    screen = lambda p: page.evaluate("(p) => window.billiards.screenOf(p)", p)  # noqa: E731
    left, right = screen([0, t["l"] / 2]), screen([t["w"], t["l"] / 2])
    centre, edge = screen([t["w"] / 2, t["l"] / 2]), screen([t["w"] / 2 + t["R"], t["l"] / 2])
    return 2 * math.dist(centre, edge) / math.dist(left, right)


def test_a_seven_foot_nine_ball_table_is_drawn_smaller(open_page, server):
    page = open_page("/")
    name_at_home(page, server, "Sz")
    page.select_option("#create-game", "nineball")
    page.select_option("#create-options select[name=size]", "7")
    page.click("#create-form button[type=submit]")
    page.wait_for_url("**/table/*")
    wait_shown(page)
    wait_drawn(page)
    view = page.request.get(f"{server.url}/api/tables/{page.url.rsplit('/', 1)[1]}").json()
    assert view["options"]["size"] == 7
    small = page.evaluate("window.billiards.table()")
    assert (small["w"], small["l"]) == (0.9906, 1.9812)
    # Drawn where the server racked them: the cue ball on the 7 ft table's head spot.
    assert close(drawn_balls(page), view["state"]["balls"], 1e-9)
    assert math.dist(drawn_balls(page)["cue"], [small["w"] / 2, small["l"] / 4]) < 1e-9
    small_ratio = ball_to_table_ratio(page)
    screenshot(page, "table-size-7ft")

    # The size select is shown for pool only, in the create form and on each pool game's card.
    page.goto(server.url + "/")
    page.select_option("#create-game", "snooker")
    assert page.locator("#create-options select[name=size]").count() == 0
    assert page.locator(".card[data-game=eightball] select[name=size]").count() == 1
    assert page.locator(".card[data-game=three_cushion] select[name=size]").count() == 0

    nine = open_page("/practice/nineball", who="nine")
    enter_name(nine, unique_name("Nn"))
    wait_shown(nine)
    wait_drawn(nine)
    nine.click("#edit-position")  # the top view, as the open table shows it
    wait_drawn(nine, "top")
    full = nine.evaluate("window.billiards.table()")
    assert (full["w"], full["l"]) == (1.27, 2.54)
    # The same balls on a smaller bed: each ball takes a larger share of the table's width.
    assert small_ratio / ball_to_table_ratio(nine) > 1.2
    screenshot(nine, "table-size-9ft")

"""What the play page tells a player so that nothing is guessed (issue 24): a refusal in the
server's words, the referee's decision once a shot is played, aiming that knows the legal
first contacts (the server's next.shot.targets), ball in hand drawn and placed with the mouse
or the keys, keys that do what their control says, and each game's state beside the scores.
Tables are put where a test needs them through the API; the page is then opened on them."""

from __future__ import annotations

import json
import math

from playwright.sync_api import expect

from rules.inputs import accept
from rules.referee import referee as referee_of
from rules.spots import in_region, is_free
from rules.state import State
from server.game import refereeing
from tests.e2e.conftest import (
    Api,
    drawn_balls,
    enter_name,
    screenshot,
    strike_with_keys,
    unique_name,
    wait_drawn,
    wait_shown,
)
from tests.e2e.test_leaderboard import claimable


def practice(open_page, server, game: str):
    """A new player's practice page of `game`, shown, with the API as that player."""
    page = open_page(f"/practice/{game}")
    enter_name(page, unique_name("Gd"))
    wait_shown(page)
    return page, Api(page, server)


def table_id(page) -> str:
    game = page.url.rsplit("/", 1)[1]
    return page.evaluate("(g) => localStorage.getItem('billiards.practice.' + g)", game)


def drag(page, start, target) -> None:
    """Drag with the mouse from table point `start` to table point `target` (top view)."""
    x0, y0 = page.evaluate("(p) => window.billiards.screenOf(p)", start)
    x1, y1 = page.evaluate("(p) => window.billiards.screenOf(p)", target)
    page.mouse.move(x0, y0)
    page.mouse.down()
    page.mouse.move((x0 + x1) / 2, (y0 + y1) / 2, steps=4)
    page.mouse.move(x1, y1, steps=4)
    page.mouse.up()


def aim(page) -> dict:
    return page.evaluate("window.billiards.aim()")


def top_view(page) -> None:
    page.keyboard.press("v")
    wait_drawn(page, "top")


def test_a_refused_shot_is_shown_in_words_until_the_next_action(open_page, server, console):
    console.allow("422")  # the browser logs the refused request as a failed load
    page, api = practice(open_page, server, "nineball")
    top_view(page)
    # The cue ball dropped in the mouth of a corner pocket: behind the head string as drawn,
    # but the referee refuses a ball where it would fall.
    drag(page, drawn_balls(page)["cue"], [0.0, 0.0])
    page.click("#hit")
    refusal = page.locator("#refusal")
    refusal.wait_for(state="visible")
    words = refusal.inner_text()
    assert words.startswith("Refused (illegal_input): ") and len(words) > 40
    assert words in page.get_by_role("status").inner_text()
    # The cue ball stays where the player put it, to be moved from there.
    placed = page.evaluate("window.billiards.placement()")
    assert placed is not None and math.dist(drawn_balls(page)["cue"], placed) < 1e-9
    screenshot(page, "guidance-refusal")
    # The next action (a legal place, then the shot) takes the refusal away.
    drag(page, placed, [0.6, 0.5])
    page.click("#hit")
    wait_shown(page, 2)
    assert refusal.is_hidden()
    assert "Refused" not in page.get_by_role("status").inner_text()
    assert api.table(table_id(page))["version"] == 1


def test_the_status_says_the_referees_decision_once_a_shot_is_played(open_page, server):
    page, api = practice(open_page, server, "eightball")
    # The answer to the shot held back until its outcome has come and been shown, as when the
    # channel is quicker than the HTTP answer: the referee's words must stay.
    held = []
    page.route("**/intents", lambda route: held.append((route, route.fetch())))
    strike_with_keys(page, hold_ms=60)  # a soft stroke: a short animation
    wait_shown(page, 2)
    route, response = held.pop()
    route.fulfill(response=response)
    page.wait_for_function("() => !window.billiards.sending")
    page.wait_for_timeout(300)  # (a page without the flag: time to take the answer)
    decision = api.table(table_id(page))["last_outcome"]["decision"]
    status = page.get_by_role("status").inner_text()
    assert "Shot sent" not in status
    assert ("potted nothing" in status) == (not decision["pocketed"]), status
    assert all(foul["reason"] in status for foul in decision["fouls"]), status
    screenshot(page, "guidance-referee-words")


def test_aiming_starts_at_a_legal_first_contact_and_marks_a_foul(open_page, server):
    # Snooker's opening: a red, not the blue or the pink in front of the pack.
    page, api = practice(open_page, server, "snooker")
    first = aim(page)["contact"]
    assert first["ball"].startswith("red") and first["legal"] is True
    contact = page.locator("#contact")
    assert "legal first contact" in contact.inner_text()
    screenshot(page, "guidance-aim-snooker")
    # Aimed at the blue instead (a click in the top view aims there): marked a foul.
    top_view(page)
    blue = drawn_balls(page)["blue"]
    x, y = page.evaluate("(p) => window.billiards.screenOf(p)", blue)
    page.mouse.click(x, y)
    assert aim(page)["contact"] == {"ball": "blue", "legal": False}
    assert "is a foul" in contact.inner_text() and "a red" in contact.inner_text()
    screenshot(page, "guidance-aim-foul")
    # Three-cushion's break must hit the red: the first aim does.
    page, api = practice(open_page, server, "three_cushion")
    targets = api.table(table_id(page))["next"]["shot"]["targets"]
    assert aim(page)["contact"] == {"ball": targets[0], "legal": True}


def foul_beside(state: State, ball: str) -> dict | None:
    """With the cue ball in hand anywhere: an input that places it just beside `ball` and rolls
    it a centimetre away from it (touching nothing: a foul), from where the straight line to
    the lowest ball is clear and longer than to `ball`; None if there is no such place."""
    table = referee_of(state.game).TABLE
    lowest = min((b for b in state.balls if b.isdigit()), key=int)
    others = {b: p for b, p in state.balls.items() if b != "cue"}
    at = others[ball]
    for step in range(16):
        angle = 2 * math.pi * step / 16
        p = (at[0] + 0.07 * math.cos(angle), at[1] + 0.07 * math.sin(angle))
        if not (in_region(p, "anywhere", table) and is_free(p, others, table.R)):
            continue
        if math.dist(p, others[lowest]) < 0.25 or blocked(p, others, lowest, 2.2 * table.R):
            continue
        strike = {"ball": "cue", "speed": refereeing.TIMEOUT_SPEED, "heading": math.degrees(angle)}
        action = accept({"strike": strike, "place": [round(p[0], 4), round(p[1], 4)]})
        try:
            refereeing.check(state, action)
        except refereeing.RuleError:
            continue
        return action.model_dump(mode="json", exclude_defaults=True)
    return None


def blocked(p, balls: dict, target: str, width: float) -> bool:
    """Whether a ball other than `target` lies within `width` of the segment from p to it."""
    q = balls[target]
    length = math.dist(p, q)
    for ball, c in balls.items():
        t = ((c[0] - p[0]) * (q[0] - p[0]) + (c[1] - p[1]) * (q[1] - p[1])) / length**2
        closest = (p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1]))
        if ball != target and 0 < t < 1 and math.dist(c, closest) < width:
            return True
    return False


def test_after_a_foul_in_nineball_the_aim_is_at_the_lowest_ball(open_page, server):
    page, api = practice(open_page, server, "nineball")
    table = table_id(page)
    view = api.play_picked(table)  # the break
    while view["next"]["shot"]["place"] != "anywhere":  # a foul: ball in hand anywhere
        view = api.play(
            table,
            refereeing.timeout_input(State.model_validate(view["state"])).model_dump(mode="json"),
        )
    # The cue ball put beside a ball that is not the lowest, and a foul from there: the next
    # player has the ball in hand where it stopped, nearest to that ball.
    state = State.model_validate(view["state"])
    lowest = min((b for b in state.balls if b.isdigit()), key=int)
    foul = next(
        filter(None, (foul_beside(state, b) for b in state.balls if b not in ("cue", lowest)))
    )
    view = api.play(table, foul)
    balls = view["state"]["balls"]
    assert (
        view["next"]["shot"]["targets"] == [lowest] and view["next"]["shot"]["place"] == "anywhere"
    )
    nearest = min((b for b in balls if b != "cue"), key=lambda b: math.dist(balls[b], balls["cue"]))
    assert nearest != lowest
    wait_shown(page, view["version"] + 1)
    page.wait_for_function("(v) => window.billiards.version === v", arg=view["version"])
    assert aim(page)["contact"] == {"ball": lowest, "legal": True}
    assert (
        f"Aiming at the {lowest}: a legal first contact." in page.locator("#contact").inner_text()
    )
    screenshot(page, "guidance-aim-nineball-after-foul")


def test_ball_in_hand_is_drawn_kept_off_the_balls_and_moved_with_keys(open_page, server):
    page, api = practice(open_page, server, "snooker")
    assert page.evaluate("window.billiards.region()") == "D"
    assert "Drag the cue ball" in page.locator("#hint").inner_text()
    top_view(page)
    # Dropped on the brown (on the D's straight edge), the cue ball is set beside it instead.
    brown = drawn_balls(page)["brown"]
    drag(page, drawn_balls(page)["cue"], brown)
    placed = page.evaluate("window.billiards.placement()")
    table = page.evaluate("fetch('/web/tables').then((r) => r.json()).then((t) => t.snooker)")
    assert math.dist(placed, brown) >= 2 * table["R"] - 1e-9
    centre = [table["w"] / 2, table["baulk_y"]]
    assert placed[1] <= centre[1] and math.dist(placed, centre) <= table["d_radius"]
    screenshot(page, "guidance-ball-in-hand")
    # Alt + the arrow keys move it: down the table in the top view, away from the baulk line
    # and into the D.
    page.locator("#table").focus()
    before = page.evaluate("window.billiards.placement()")
    for _ in range(4):
        page.keyboard.press("Alt+ArrowDown")
    after = page.evaluate("window.billiards.placement()")
    assert math.dist(before, after) > 0.015
    strike_with_keys(page, hold_ms=300)
    wait_shown(page, 2)
    played = api.table(table_id(page))["last_outcome"]["input"]
    assert math.dist(played["place"], after) < 1e-3  # as the server quantised it


def test_the_game_keys_work_from_the_sliders_and_the_spin_disc_spins(open_page, server):
    page, api = practice(open_page, server, "nineball")
    page.locator("#power").click()
    power, heading = aim(page)["power"], aim(page)["heading"]
    page.keyboard.press("ArrowLeft")
    assert aim(page)["power"] == power and math.isclose(aim(page)["heading"], heading + 0.5)
    # On the spin disc the arrows are spin, as its label says.
    page.locator("#tip").focus()
    page.keyboard.press("ArrowRight")
    page.keyboard.press("ArrowUp")
    now = aim(page)
    assert math.isclose(now["heading"], heading + 0.5) and now["a"] > 0 and now["b"] > 0
    # Space from the slider strikes.
    page.locator("#elevation").focus()
    page.keyboard.down(" ")
    page.wait_for_timeout(300)
    page.keyboard.up(" ")
    wait_shown(page, 2)
    assert api.table(table_id(page))["version"] == 1


def test_each_games_state_is_beside_the_scores(open_page, server):
    page, api = practice(open_page, server, "snooker")
    players = page.locator("#players")
    assert "Ball on: a red. Points remaining: 147." in players.inner_text()
    screenshot(page, "guidance-snooker-state")
    page, api = practice(open_page, server, "eightball")
    assert players_text(page).count("open table") == 2
    view = api.play_until(table_id(page), lambda s: any(s.groups))
    page.reload()
    wait_shown(page)
    groups = view["state"]["groups"]
    for seat, group in enumerate(groups):
        left = sum(str(n) in view["state"]["balls"] for n in GROUP_BALLS[group])
        assert f"{group}, {left} left" in players_text(page), (seat, players_text(page))
    screenshot(page, "guidance-eightball-groups")


GROUP_BALLS = {"solids": range(1, 8), "stripes": range(9, 16)}


def players_text(page) -> str:
    return page.locator("#players").inner_text()


def test_the_home_page_speaks_to_players(open_page, console):
    console.allow("400")  # the refused name's request
    page = open_page("/")
    page.fill("#name", "<Ada>")
    page.click("#name-form button")
    error = page.locator("#name-error")
    error.wait_for(state="visible")
    page.wait_for_function("document.getElementById('name-error').textContent !== ''")
    assert error.inner_text().startswith("Use 1 to 24 letters")
    assert not any(c in error.inner_text() for c in "^[]\\$")
    # The bot's level is chosen in words, and the table is made at that level.
    card = page.locator("#games .card", has_text="Nine-ball")
    level = card.locator("select.bot-level")
    assert level.locator("option").all_inner_texts()[0].startswith("Beginner bot (level 1)")
    level.select_option("bot:1")
    page.fill("#name", unique_name("Hm"))
    page.click("#name-form button")
    page.wait_for_function("document.getElementById('who').textContent !== ''")
    card.get_by_role("button", name="Play the bot").click()
    page.wait_for_url("**/table/*")
    wait_shown(page)
    assert "Beginner bot (level 1)" in page.locator("#players").inner_text()
    screenshot(page, "guidance-bot-table")


def test_a_refusal_on_the_home_page_is_shown_beside_its_control(open_page, server, console):
    console.allow("409")  # the refused request, logged by the browser
    page = open_page("/")
    api = Api(page, server)
    api.sign_in(unique_name("Tm"))
    for _ in range(3):  # the most open tables one player may have
        api.call("POST", "/api/tables", {"game": "snooker"})
    page.reload()
    page.wait_for_function("document.getElementById('who').textContent !== ''")
    page.click("#create-form button[type=submit]")
    refusal = page.get_by_role("alert").filter(has_text="you have 3 open tables")
    refusal.wait_for(state="attached")
    expect(refusal).to_be_in_viewport()  # where the player looks, not at the page's foot
    card = page.locator(".card", has=page.locator("#create-form"))
    assert card.get_by_role("alert").inner_text() == refusal.inner_text()  # by its control
    assert page.url == server.url + "/"  # no table was made
    screenshot(page, "guidance-home-refusal")


PHONE = {"width": 390, "height": 844}


def test_a_phone_shows_the_leaderboard_and_the_open_tables(open_page, server):
    page = open_page("/", viewport=PHONE)
    api = Api(page, server)
    name = (unique_name("Pl") + "Longname" * 3)[:24]  # the longest name allowed
    api.sign_in(name)
    # (Seeds of its own: a record is claimed once, and test_leaderboard claims from seed 1 on.)
    record, best = next((r, b) for r, b in map(claimable, range(101, 140)) if b > 0)
    claim = {"game": "nineball", "record": json.loads(record), "name": name, "score": best}
    api.call("POST", "/api/leaderboard/claims", claim)
    api.call("POST", "/api/tables", {"game": "snooker"})  # an open table for the lobby
    page.goto(server.url + "/leaderboard/nineball")
    page.wait_for_selector("#board tbody tr")
    assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"]
    screenshot(page, "guidance-phone-leaderboard")
    page.goto(server.url + "/")
    page.wait_for_selector("#tables a.button")
    lobby = page.locator("#lobby").bounding_box()
    assert lobby["y"] < PHONE["height"] / 2  # in sight without scrolling
    screenshot(page, "guidance-phone-lobby")

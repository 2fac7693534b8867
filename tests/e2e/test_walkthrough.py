"""The issue's closing walk-through, as a newcomer meets the game: a practice rack (the break,
a shot, ending it, its replay), an online match between two browsers to its end and its
rematch, and a game against the bot. Every step is saved as tests/e2e/artefacts/walk-*.png
for a person to look at; the test asserts only what each step must show to be understood."""

from __future__ import annotations

import time

from playwright.sync_api import TimeoutError as PlaywrightTimeout

from tests.e2e.conftest import (
    Api,
    create_at_home,
    enter_name,
    join_as,
    screenshot,
    strike_with_keys,
    take_turn,
    unique_name,
    wait_drawn,
    wait_shown,
    wait_version,
)

#: How long a page may take to animate every shot it was sent (a whole rack, software WebGL).
CATCH_UP_MS = 600_000
#: How long (s) a table against the bot may show no change: a shot simulated and animated, or
#: the bot's search and its pause, take seconds; longer is a stall, and the test says where.
STALL_S = 180


class Walk:
    """Numbered screenshots, in the order taken."""

    def __init__(self) -> None:
        self.step = 0

    def shot(self, page, what: str, settle: bool = True) -> None:
        """Save what `page` shows now (`settle`: once a play page has drawn every change)."""
        self.step += 1
        if settle and page.evaluate("typeof window.billiards?.drawn === 'function'"):
            wait_drawn(page)
        screenshot(page, f"walk-{self.step:02d}-{what}")


def replay_to_its_end(page) -> None:
    page.select_option("#speed", "4")
    page.wait_for_function("() => window.billiards.shots > 0", timeout=60_000)
    shots = page.evaluate("window.billiards.shots")
    page.wait_for_function("(n) => window.billiards.shown === n - 1", arg=shots, timeout=180_000)


def practice(walk: Walk, page, server) -> None:
    page.goto(server.url + "/practice/nineball")
    enter_name(page, unique_name("Newcomer"))
    wait_shown(page)
    assert "Drag the cue ball" in page.locator("#hint").inner_text()
    assert "a legal first contact" in page.locator("#contact").inner_text()
    walk.shot(page, "practice-opened")
    strike_with_keys(page, hold_ms=1600)
    wait_shown(page, 2, timeout=120_000)
    assert "Shot sent" not in page.get_by_role("status").inner_text()
    walk.shot(page, "practice-after-break")
    strike_with_keys(page, hold_ms=500)
    wait_shown(page, 3, timeout=120_000)
    walk.shot(page, "practice-second-shot")
    page.get_by_role("button", name="End practice").click()
    walk.shot(page, "practice-end-asked")
    page.get_by_role("button", name="Yes, end it").click()
    page.wait_for_selector("#result #replays a")
    walk.shot(page, "practice-ended")
    page.locator("#result #replays a").last.click()
    page.wait_for_url("**/replay/*")
    replay_to_its_end(page)
    walk.shot(page, "practice-replay")


def match(walk: Walk, ada, bob, server) -> tuple[list, str]:
    """Ada (named in practice) creates a nine-ball table, Bob joins by its link; two turns with
    the keys, then the picker plays the rack out for both through the API. (pages, table)."""
    ada.goto(server.url + "/")
    walk.shot(ada, "home")
    table = create_at_home(ada, "nineball")
    wait_version(ada, 0)
    walk.shot(ada, "match-waiting")
    bob.goto(ada.url)
    walk.shot(bob, "match-visitor")
    join_as(bob, unique_name("Opponent"))
    apis = [Api(ada, server), Api(bob, server)]
    view = apis[0].table(table)
    pages = [ada, bob]
    for page in pages:
        wait_version(page, view["version"])
    walk.shot(pages[view["next"]["seat"]], "match-first-to-shoot")
    walk.shot(pages[1 - view["next"]["seat"]], "match-waiting-for-the-break")
    for _ in range(2):
        take_turn(dict(enumerate(pages)), view, hold_ms=900)
        view = apis[0].table(table)
        if view["status"] != "playing":
            break
    for page in pages:
        wait_version(page, view["version"])
    walk.shot(ada, "match-after-two-turns")
    while view["status"] == "playing":
        view = apis[view["next"]["seat"]].play_picked(table)
    for page in pages:
        page.wait_for_function(
            "(v) => window.billiards.version >= v", arg=view["version"], timeout=CATCH_UP_MS
        )
        page.wait_for_selector("#result")
    winner, loser = pages[view["winner"]], pages[1 - view["winner"]]
    assert "wins the match: winning 1 rack to 0" in winner.locator("#result h2").inner_text()
    assert winner.locator("#result #replays a").count() == 1
    for page in pages:
        page.wait_for_selector("#result .rating:has-text('Your rating')")
    walk.shot(winner, "match-won")
    walk.shot(loser, "match-lost")
    return [winner, loser], table


def rematch(walk: Walk, pages: list, table: str) -> None:
    winner, loser = pages
    loser.get_by_role("button", name="Offer a rematch").click()
    winner.wait_for_selector("#result .offer")
    walk.shot(winner, "rematch-offered")
    walk.shot(loser, "rematch-waiting")
    winner.get_by_role("button", name="Accept the rematch").click()
    for page in pages:
        page.wait_for_url(lambda url: table not in url)
        wait_version(page, 0)
    walk.shot(loser, "rematch-table")


def bot(walk: Walk, page, server) -> None:
    """A table against the beginner bot, played until the bot lines up a shot. A rack can end
    before the bot ever shoots (the player's own stroke pots the 8 early): then a new table."""
    for _ in range(3):
        if bot_shoots(walk, page, server):
            return
    raise AssertionError("three racks against the bot ended before it shot")


def bot_shoots(walk: Walk, page, server) -> bool:
    """Open a table against the bot and shoot until the bot has shot; False if the rack
    ended first."""
    page.goto(server.url + "/")
    card = page.locator("#games .card", has_text="Eight-ball")
    card.locator("select.bot-level").select_option("bot:1")
    card.get_by_role("button", name="Play the bot").click()
    page.wait_for_url("**/table/*")
    wait_shown(page)
    walk.shot(page, "bot-table")
    api, table = Api(page, server), page.url.rsplit("/", 1)[1]
    # The player shoots until the bot has a shot to play (a break that pots plays on).
    deadline = time.monotonic() + STALL_S
    while page.evaluate("window.billiards.botAims()") < 1:
        view = api.table(table)
        if time.monotonic() > deadline:
            raise AssertionError(f"the bot's rack stalled at {view['version']}: {view['next']}")
        shown = page.evaluate("window.billiards.version") == view["version"]
        if view["next"] is None:  # the rack is over: its last shot may be the bot's, still shown
            if shown and page.evaluate("window.billiards.botAims()") < 1:
                return False
            page.wait_for_timeout(100)
        elif view["next"]["seat"] == 0 and shown:
            if view["next"]["kinds"] == ["choice"]:
                page.locator("#choices button").first.click()
            else:
                strike_with_keys(page, hold_ms=1200)
            wait_explained(
                page,
                api,
                table,
                "(v) => window.billiards.version > v || window.billiards.botAims() >= 1",
                view["version"],
            )
            deadline = time.monotonic() + STALL_S
        else:
            page.wait_for_timeout(100)
    walk.shot(page, "bot-lining-up", settle=False)  # (during the bot's pause before its stroke)
    version = page.evaluate("window.billiards.version")
    wait_explained(page, api, table, "(v) => window.billiards.version > v", version)
    walk.shot(page, "bot-after-its-shot")
    return True


def wait_explained(page, api: Api, table: str, condition: str, version: int) -> None:
    """Wait (at most STALL_S) for `condition` of the page's version; if it never holds, fail
    with what the page showed, what the server held and the end of its log, so that a stall
    says where it was."""
    try:
        page.wait_for_function(condition, arg=version, timeout=STALL_S * 1000)
    except PlaywrightTimeout:
        shown = page.evaluate(
            """() => ({status: document.getElementById('status').textContent,
                refusal: document.getElementById('refusal').textContent,
                hint: document.getElementById('hint').textContent,
                version: window.billiards.version, sending: window.billiards.sending,
                drawn: window.billiards.drawn(), botAims: window.billiards.botAims()})"""
        )
        held = api.table(table)
        log = (api.server.directory / "server.log").read_text(errors="replace")[-4000:]
        raise AssertionError(
            f"the page stalled after version {version}: it shows {shown}; the server holds "
            f"version {held['version']}, next {held['next']}, status {held['status']}; "
            f"the server's log ends:\n{log}"
        ) from None


def test_a_newcomer_walks_through_the_game(browser, server, console):
    contexts = [browser.new_context(viewport={"width": 1280, "height": 800}) for _ in range(2)]
    ada, bob = (console.watch(c.new_page(), who) for c, who in zip(contexts, "AB", strict=True))
    walk = Walk()
    try:
        practice(walk, ada, server)
        pages, table = match(walk, ada, bob, server)
        rematch(walk, pages, table)
        bot(walk, bob, server)
    finally:
        for c in contexts:
            c.close()

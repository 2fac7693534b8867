"""An online match in three browser contexts: Ada creates a table from the home page, Bob
opens its link and joins, Cy watches. Each player shoots with the keyboard; all three see
every outcome and agree on the balls; Bob reloads mid-match and resumes where the table is."""

from __future__ import annotations

import math
from urllib.parse import quote

from tests.e2e.conftest import (
    MAX_SHOTS,
    create_at_home,
    drawn_balls,
    join_as,
    name_at_home,
    screenshot,
    strike_with_keys,
    take_turn,
    unique_name,
    wait_version,
)


def view_of(page, server, table_id: str) -> dict:
    return page.request.get(f"{server.url}/api/tables/{table_id}").json()


def assert_shows(page, view: dict) -> None:
    in_hand = view["next"] and view["next"]["cue_ball"] not in view["state"]["balls"]
    # The player to shoot is offered a place for a cue ball in hand; the others see none.
    assert_shows_balls(page, view["state"]["balls"], view["next"]["cue_ball"] if in_hand else None)


def assert_shows_balls(page, balls: dict, offered: str | None = None) -> None:
    """The page draws exactly `balls` (a state's), each where it stands (and perhaps the ball
    `offered`, in hand)."""
    drawn = drawn_balls(page)
    drawn.pop(offered, None)
    assert drawn.keys() == balls.keys()
    for ball, p in drawn.items():
        assert math.dist(p, balls[ball]) < 1e-9, ball


def test_two_players_and_a_spectator(browser, server, console):
    contexts = [browser.new_context(viewport={"width": 1100, "height": 700}) for _ in range(3)]
    ada, bob, cy = (
        console.watch(c.new_page(), who) for c, who in zip(contexts, "ABC", strict=True)
    )
    try:
        name_at_home(ada, server, "Ada")
        table_id = create_at_home(ada, "nineball")
        wait_version(ada, 0)
        assert "Waiting for an opponent" in ada.get_by_role("status").inner_text()

        bob.goto(ada.url)
        join_as(bob, unique_name("Bob"))
        started = view_of(bob, server, table_id)
        assert started["status"] == "playing"
        names = [seat["name"] for seat in started["seats"]]
        cy.goto(ada.url)
        pages = {0: ada, 1: bob}
        for page in (ada, bob, cy):
            wait_version(page, started["version"])
        assert cy.get_by_role("button", name="Join this table").count() == 0

        shooters = set()
        view = started
        for _ in range(MAX_SHOTS):
            shooters.add(view["next"]["seat"])
            take_turn(pages, view, hold_ms=250 + 150 * len(shooters))
            view = view_of(cy, server, table_id)
            for page in (ada, bob, cy):
                wait_version(page, view["version"])
                assert_shows(page, view)
            words = {p.get_by_role("status").inner_text() for p in (ada, bob, cy)}
            assert len(words) == 1, words  # players and spectator read the same
            if shooters == {0, 1} or view["status"] != "playing":
                break
        assert shooters == {0, 1}
        screenshot(cy, "match-spectator")
        screenshot(ada, "match-player")

        # Bob reloads: the page resumes at the table's version, showing the same table.
        bob.reload()
        wait_version(bob, view["version"])
        assert_shows(bob, view_of(bob, server, table_id))
        assert bob.get_by_role("button", name="Join this table").count() == 0
        screenshot(bob, "match-after-reload")

        # Ada resigns (asked first); the result panel says how the match ended. Bob offers a
        # rematch, Ada is told and accepts, and both are taken to the new table.
        ada.get_by_role("button", name="Resign").click()
        ada.get_by_role("button", name="Keep playing").click()
        assert view_of(ada, server, table_id)["status"] == "playing"
        ada.get_by_role("button", name="Resign").click()
        ada.get_by_role("button", name="Yes, resign").click()
        for page in (ada, bob, cy):
            page.wait_for_selector("#result:has-text('resigned')")
            assert "Match over" in page.get_by_role("status").inner_text()
            assert page.locator("#hint").inner_text() == ""  # nothing left to place or aim
        result = cy.locator("#result h2").inner_text()
        assert result.startswith(f"{names[1]} wins the match") and f"{names[0]} resigned" in result
        # The rack cut short has its replay, listed in the result panel, after a reload too.
        over = view_of(cy, server, table_id)
        assert len(over["replays"]) == over["rack"]
        cy.reload()
        wait_version(cy, over["version"])
        for page in (ada, bob, cy):
            links = page.locator("#result #replays a")
            assert links.count() == len(over["replays"])
            assert links.last.inner_text() == f"rack {over['rack']} (unfinished)"
            assert links.last.get_attribute("href") == f"/replay/{over['replays'][-1]}"
        # The players' names lead to their profiles.
        profiles = cy.locator("#players a.profile")
        assert [profiles.nth(i).get_attribute("href") for i in range(2)] == [
            f"/player/{quote(name)}" for name in names
        ]
        screenshot(cy, "match-result")
        bob.get_by_role("button", name="Offer a rematch").click()
        ada.wait_for_selector(f"#result:has-text('{names[1]} offers a rematch')")
        screenshot(ada, "match-rematch-offered")
        ada.get_by_role("button", name="Accept the rematch").click()
        for page in (ada, bob):
            page.wait_for_url(lambda url: table_id not in url)
            wait_version(page, 0)
        assert ada.url == bob.url and ada.url.rsplit("/", 1)[1] != table_id

        # Cy, still at the finished table, watches the resigned rack: it ends where the match
        # did, its players named and linked.
        cy.locator("#result #replays a").last.click()
        cy.wait_for_url("**/replay/*")
        cy.select_option("#speed", "4")
        cy.wait_for_function("() => window.billiards.shots > 0", timeout=30_000)
        shots = cy.evaluate("window.billiards.shots")
        cy.wait_for_function("(n) => window.billiards.shown === n - 1", arg=shots, timeout=90_000)
        assert_shows_balls(cy, over["state"]["balls"])
        assert "Not finished" in cy.locator("#about").inner_text()
        assert f"{names[0]} resigned" in cy.locator("#about").inner_text()
        replay_names = cy.locator("#players a.profile")
        assert [replay_names.nth(i).inner_text() for i in range(2)] == names
        screenshot(cy, "match-replay-of-the-resigned-rack")

        # Bob leaves: Ada is told he is gone once his heartbeats stop (10 s).
        bob.close()
        ada.wait_for_selector("#banner:has-text('disconnected')", timeout=40_000)
        screenshot(ada, "match-opponent-gone")
    finally:
        for c in contexts:
            c.close()


def test_quick_match_pairs_two_players(browser, server, console):
    contexts = [browser.new_context() for _ in range(2)]
    try:
        pages = [console.watch(c.new_page(), who) for c, who in zip(contexts, "DE", strict=True)]
        for page in pages:
            name_at_home(page, server, "Qm")
        # The first waits (told of its pairing on its player channel), the second is paired.
        first, second = pages
        first.locator("#games .card", has_text="Snooker").get_by_role(
            "button", name="Quick match"
        ).click()
        first.wait_for_selector("text=Waiting for an opponent")
        second.locator("#games .card", has_text="Snooker").get_by_role(
            "button", name="Quick match"
        ).click()
        for page in pages:
            page.wait_for_url("**/table/*")
            wait_version(page, 0)
        assert first.url == second.url
        table = view_of(first, server, first.url.rsplit("/", 1)[1])
        assert table["game"] == "snooker" and table["status"] == "playing"
        assert all(table["seats"])
    finally:
        for c in contexts:
            c.close()


def test_a_game_against_the_bot(open_page, server):
    page = open_page("/")
    name_at_home(page, server, "Vb")
    page.locator("#games .card", has_text="Eight-ball").get_by_role(
        "button", name="Play the bot"
    ).click()
    page.wait_for_url("**/table/*")
    table_id = page.url.rsplit("/", 1)[1]
    wait_version(page, 0)
    for _ in range(MAX_SHOTS):
        view = view_of(page, server, table_id)
        if view["last_outcome"] and view["last_outcome"]["seat"] == 1:
            break  # the bot has played, through the same match path
        if view["next"] and view["next"]["seat"] == 0:
            wait_version(page, view["version"])
            strike_with_keys(page, hold_ms=500, left=1)
            page.wait_for_function(
                "(v) => window.billiards.version > v", arg=view["version"], timeout=90_000
            )
        else:
            page.wait_for_timeout(200)  # the bot is thinking
    # The bot may play on: compare once it is our turn again (or the rack is over) and the page
    # has caught up.
    for _ in range(600):  # two minutes at most
        bot = view_of(page, server, table_id)
        if bot["next"] is None or bot["next"]["seat"] == 0:
            break
        page.wait_for_timeout(200)
    wait_version(page, bot["version"])
    assert bot["seats"][1]["id"].startswith("bot:")
    assert_shows(page, bot)
    screenshot(page, "bot-table")

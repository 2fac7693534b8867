"""A match's life around the shots, in two browser contexts: a private table reached only by
its link, the shot clock counting down and ruled by the server when it runs out, and a win
claimed once a gone opponent's grace period is over (the test server's is GRACE_S)."""

from __future__ import annotations

import re

from tests.e2e.conftest import (
    GRACE_S,
    MAX_SHOTS,
    Api,
    create_at_home,
    join_as,
    name_at_home,
    screenshot,
    take_turn,
    unique_name,
    wait_version,
)

#: The shot clock of the clock's test (s): long enough for the pages to load within it.
CLOCK_S = 20


def seated(browser, server, console, game: str = "nineball", **options) -> tuple:
    """Ada's table with Bob seated (both by the API), each then opening it in his own browser
    context: (pages, apis, table id)."""
    contexts = [browser.new_context(viewport={"width": 1100, "height": 700}) for _ in range(2)]
    pages = [console.watch(c.new_page(), who) for c, who in zip(contexts, "AB", strict=True)]
    apis = [Api(page, server) for page in pages]
    apis[0].sign_in(unique_name("Ada"))
    apis[1].sign_in(unique_name("Bob"))
    table = apis[0].call("POST", "/api/tables", {"game": game, **options})["id"]
    view = apis[1].call("POST", f"/api/tables/{table}/join")
    for page in pages:
        page.goto(f"{server.url}/table/{table}")
    for page in pages:
        wait_version(page, view["version"])
    return pages, apis, table


def clock_seconds(page) -> int:
    text = page.locator("#clock").inner_text()
    found = re.fullmatch(r"Shot clock (\d+) s", text)
    assert found, text
    return int(found[1])


def test_a_private_table_is_played_through_its_link(browser, server, console):
    contexts = [browser.new_context() for _ in range(2)]
    ada, bob = (console.watch(c.new_page(), who) for c, who in zip(contexts, "AB", strict=True))
    try:
        name_at_home(ada, server, "Pa")
        # Three-cushion: no rack can end before Bob's turn, no foul offers him a choice instead.
        table = create_at_home(ada, "three_cushion", private=True)
        link = ada.locator("#invite a").inner_text()
        assert link == ada.url
        api = Api(ada, server)
        assert api.table(table)["options"]["private"] is True
        listed = [t["id"] for t in api.call("GET", "/api/tables")["tables"]]
        assert table not in listed  # in no lobby: only the link leads there
        screenshot(ada, "private-table-invite")

        bob.goto(link)
        join_as(bob, unique_name("Pb"))
        pages = {0: ada, 1: bob}
        for _ in range(MAX_SHOTS):
            view = api.table(table)
            if view["last_outcome"] and view["last_outcome"]["seat"] == 1:
                break
            take_turn(pages, view)
        view = api.table(table)
        assert view["last_outcome"]["seat"] == 1  # Bob, who came by the link, played
        assert not view["last_outcome"]["shot_id"].startswith(("clock:", "bot:"))
        wait_version(ada, view["version"])
        assert ada.locator("#invite").count() == 0  # the invitation is gone once it is taken
        # No shot clock: the match's turn limit runs instead, and the page says which it is.
        assert re.fullmatch(r"Turn limit \d+ s", ada.locator("#clock").inner_text())
    finally:
        for c in contexts:
            c.close()


def test_the_shot_clock_counts_down_and_the_server_rules_its_end(browser, server, console):
    pages, apis, table = seated(browser, server, console, shot_clock=CLOCK_S)
    ada, bob = pages
    try:
        start = apis[0].table(table)
        assert start["next"]["seat"] == 0 and start["next"]["deadline"] is not None
        first = clock_seconds(ada)
        assert 0 < first <= CLOCK_S and abs(clock_seconds(bob) - first) <= 1
        ada.wait_for_timeout(2500)
        later = clock_seconds(ada)
        assert later < first  # counting down, on the page
        screenshot(ada, "table-shot-clock")
        ada.wait_for_selector("#clock.urgent", timeout=(CLOCK_S + 30) * 1000)  # the last seconds
        # Ada does not shoot: when the clock runs out the server plays for her, and both
        # pages show its ruling (a shot that hits nothing: a foul, Bob has ball in hand).
        for page in pages:
            page.wait_for_function(
                "() => document.getElementById('status').textContent.includes('clock ran out')",
                timeout=(CLOCK_S + 60) * 1000,
            )
        view = apis[0].table(table)
        outcome = view["last_outcome"]
        assert outcome["shot_id"] == f"clock:{start['version']:08d}" and outcome["seat"] == 0
        assert outcome["decision"]["fouls"] and view["next"]["seat"] == 1
        for page in pages:
            wait_version(page, view["version"])
            assert "Foul" in page.get_by_role("status").inner_text()
        assert clock_seconds(bob) > later  # Bob's clock started afresh
        screenshot(bob, "table-clock-ran-out")
    finally:
        for page in pages:
            page.context.close()


def test_the_win_is_claimed_after_the_grace_period(browser, server, console):
    pages, apis, table = seated(browser, server, console)
    ada, bob = pages
    try:
        claim = ada.get_by_role("button", name="Claim the win")
        assert claim.count() == 0
        bob.context.close()  # Bob is gone: his heartbeats stop
        ada.wait_for_selector("#banner:has-text('may be claimed in')", timeout=40_000)
        assert claim.count() == 0  # not within the grace period
        screenshot(ada, "table-opponent-gone")
        claim.wait_for(timeout=(GRACE_S + 30) * 1000)
        claim.click()
        ada.wait_for_function(
            "() => document.getElementById('status').textContent.includes('Match over')"
        )
        view = apis[0].table(table)
        assert (view["status"], view["winner"]) == ("over", 0)
        assert f"{view['seats'][0]['name']} wins" in ada.get_by_role("status").inner_text()
        ada.locator("#banner").wait_for(state="hidden")  # nothing is left to claim
        screenshot(ada, "table-win-claimed")
    finally:
        ada.context.close()

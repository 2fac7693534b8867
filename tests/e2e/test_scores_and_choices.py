"""What the play page says a match stands at and what a choice was. Each game's score is what
its players win: racks in pool (the referee's points stay 0 there), a game's points and the
games won in three-cushion. A choice (nine-ball's answer to a push-out) is told on both
players' pages, by who chose what, and listed among the table's shots in its replay. The
inputs before are played through the API (the simple shot picker); the pages open after."""

from __future__ import annotations

from playwright.sync_api import Page

from rules.state import State
from server.game import refereeing
from tests.e2e.conftest import Api, Server, unique_name, wait_version

#: Inputs after which a table played by the picker is taken to be stuck.
MOST_INPUTS = 200


def match(browser, server: Server, console, game: str, **options) -> tuple:
    """Ada's table of `game` with Bob seated (by the API), each in his own browser context
    (not on the table yet): (pages, apis, names, table id, the version the match starts at)."""
    contexts = [browser.new_context(viewport={"width": 1100, "height": 700}) for _ in range(2)]
    pages = [console.watch(c.new_page(), who) for c, who in zip(contexts, "AB", strict=True)]
    apis = [Api(page, server) for page in pages]
    names = [apis[0].sign_in(unique_name("A"))["name"], apis[1].sign_in(unique_name("B"))["name"]]
    table = apis[0].call("POST", "/api/tables", {"game": game, **options})["id"]
    start = apis[1].call("POST", f"/api/tables/{table}/join")
    return pages, apis, names, table, start["version"]


def play_until(apis: list[Api], table: str, done, action=None) -> dict:
    """Play for whichever seat is to act (`action(view)`'s input, or the picker's when that
    gives None) until done(view) holds; the view then."""
    for _ in range(MOST_INPUTS):
        view = apis[0].table(table)
        if done(view):
            return view
        api = apis[view["next"]["seat"]]
        chosen = action(view) if action else None
        if chosen is None:
            api.play_picked(table)
        else:
            api.play(table, chosen)
    raise AssertionError(f"not there after {MOST_INPUTS} inputs")


def open_table(page: Page, server: Server, table: str, version: int) -> str:
    """The page on the table at `version`; its status line."""
    page.goto(f"{server.url}/table/{table}")
    wait_version(page, version)
    return page.get_by_role("status").inner_text()


def scores(page: Page) -> list[str]:
    return page.locator("#players .score").all_inner_texts()


def test_pool_counts_racks_won_and_three_cushion_points_and_games(browser, server, console):
    pages, apis, names, table, _ = match(browser, server, console, "nineball", race_to=2)
    try:
        view = play_until(apis, table, lambda v: v["rack"] == 2 or v["status"] == "over")
        won = view["racks_won"]
        assert sorted(won) == [0, 1]
        winner = names[won.index(1)]
        status = open_table(pages[0], server, table, view["version"])
        assert scores(pages[0]) == [str(n) for n in won]  # not the referee's points, always 0
        assert f"{winner} wins the rack." in status
        assert f"Racks won: {names[0]} {won[0]}, {names[1]} {won[1]}." in status
        assert "Score (" not in status
    finally:
        for page in pages:
            page.context.close()

    pages, apis, names, table, _ = match(
        browser, server, console, "three_cushion", race_to=2, target=1
    )
    try:
        view = play_until(apis, table, lambda v: v["rack"] == 2 or v["status"] == "over")
        won = view["racks_won"]
        winner = names[won.index(1)]
        status = open_table(pages[0], server, table, view["version"])
        assert scores(pages[0]) == [str(p) for p in view["state"]["scores"]]  # the new game's
        games = f"Games won: {names[0]} {won[0]}, {names[1]} {won[1]}."
        assert games in status and games in pages[0].locator("#players").inner_text()
        assert f"{winner} wins the game." in status and "rack" not in status.lower()
    finally:
        for page in pages:
            page.context.close()


def push_out(view: dict) -> dict | None:
    """When the shot may be a push-out: one (a dead-slow stroke away from every ball, which no
    rule can call a foul on a push-out); else None."""
    if not (view["next"]["shot"] or {}).get("push_out"):
        return None
    stroke = refereeing.timeout_input(State.model_validate(view["state"]))
    return {**stroke.model_dump(mode="json", exclude_defaults=True), "push_out": True}


def test_a_choice_is_told_on_both_pages_and_listed_in_the_replay(browser, server, console):
    pages, apis, names, table, start = match(browser, server, console, "nineball")
    try:
        view = play_until(apis, table, lambda v: v["next"]["kinds"] == ["choice"], push_out)
        chooser = view["next"]["seat"]
        assert view["next"]["options"] == ["play_on", "play_again"]
        pushed = open_table(pages[1 - chooser], server, table, view["version"])
        open_table(pages[chooser], server, table, view["version"])
        pages[chooser].get_by_role("button", name="Make them play again").click()
        told = f"{names[chooser]} chose to make {names[1 - chooser]} play again."
        for page in pages:
            wait_version(page, view["version"] + 1)
            status = page.get_by_role("status").inner_text()
            assert told in status and status != pushed  # not the push-out's words again
        after = apis[0].table(table)
        assert after["last_outcome"]["input"] == {"option": "play_again"}

        # The replay of the table lists the choice after the shots, and tells it in turn.
        replay = pages[0]
        replay.goto(f"{server.url}/replay/{table}")
        replay.select_option("#speed", "4")
        inputs = after["version"] - start  # every input played moved the version on by one
        replay.wait_for_function("(n) => window.billiards.shots === n", arg=inputs)
        assert replay.locator("#shots li").last.inner_text() == told
        replay.wait_for_function(
            "(n) => window.billiards.shown === n - 1", arg=inputs, timeout=90_000
        )
        shots = inputs - 1  # the choice is not a numbered shot
        said = f"After shot {shots} of {shots}: {told}"
        assert said in replay.get_by_role("status").inner_text()
    finally:
        for page in pages:
            page.context.close()

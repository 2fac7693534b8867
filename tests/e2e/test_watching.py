"""Watching the other player: in a match the shooter's aim reaches the opponent and the
spectators (throttled, drawn, never played), and the bot lines up before it strikes."""

from __future__ import annotations

from tests.e2e.conftest import Api, Watched, screenshot, unique_name, wait_shown, wait_version


def test_the_opponent_and_a_spectator_watch_the_shooter_line_up(browser, server, console):
    match = Watched(browser, server, console, "W")
    (ada, bob, cy), apis, table, view = match.pages, match.apis, match.table, match.view
    try:
        for page in (ada, bob, cy):
            page.goto(f"{server.url}/table/{table}")
            wait_version(page, view["version"])
        shooter = ada if view["next"]["seat"] == 0 else bob
        watchers = [bob if shooter is ada else ada, cy]
        sent = []
        shooter.on("request", lambda r: sent.append(r) if r.url.endswith("/aim") else None)
        shooter.locator("#table").focus()
        presses = 30
        for _ in range(presses):
            shooter.keyboard.press("ArrowLeft")
        heading = shooter.evaluate("window.billiards.aim().heading")
        for page in watchers:
            page.wait_for_function(
                "(h) => Math.abs((window.billiards.theirAim()?.heading ?? -1e9) - h) < 1e-3",
                arg=heading,
            )
        # Throttled: far fewer aims than key presses, the last one the aim as it was left.
        assert 1 <= len(sent) < presses / 3
        screenshot(watchers[1], "watching-spectator-sees-aim")
        assert apis[0].table(table)["version"] == view["version"]  # nothing was played
    finally:
        match.close()


def test_the_bot_lines_up_before_it_strikes(open_page, server):
    page = open_page("/")
    api = Api(page, server)
    api.sign_in(unique_name("Bt"))
    table = api.call(
        "POST", "/api/tables", {"game": "three_cushion", "mode": "bot", "bot": "bot:1"}
    )
    page.goto(f"{server.url}/table/{table['id']}")
    wait_shown(page)
    if table["next"]["seat"] == 0:  # the player breaks: a soft stroke, then the bot's turn
        page.locator("#table").focus()
        page.keyboard.down(" ")
        page.wait_for_timeout(200)
        page.keyboard.up(" ")
    # Counted when a bot's shot (shot id bot-<version>) was shown lined up before it played.
    page.wait_for_function("() => window.billiards.botAims() >= 1", timeout=120_000)
    screenshot(page, "watching-bot")

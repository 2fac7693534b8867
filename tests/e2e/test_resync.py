"""A page that missed a change of its table catches up from the next message that carries the
table's version (docs/protocol.md, "Other table messages"): a seated player's page from its
heartbeat's answer, a spectator's from a chat message. The missed change is an outcome that
never reaches the page, as when the relay restarts without its buffer and says nothing of
what it lost: the page's table channel is routed through a filter that drops those messages."""

from __future__ import annotations

import json
import math

from playwright.sync_api import Page, WebSocketRoute

from tests.e2e.conftest import Watched, drawn_balls, wait_version

#: Long enough for a heartbeat (every 3 s) or a chat message to reach the page and for the
#: table to be fetched again, on a machine busy with other tests.
CATCH_UP_MS = 30_000


def losing(page: Page, kinds: tuple[str, ...]) -> list[str]:
    """Route the table channel the page will open through a filter that drops its messages of
    `kinds`; the kinds dropped so far, in order. (Before the page opens the table.)"""
    dropped: list[str] = []

    def route(ws: WebSocketRoute) -> None:
        relay = ws.connect_to_server()

        def from_relay(frame: str | bytes) -> None:
            # A frame is the relay's headers (message id, content type), a blank line, the JSON.
            text = frame if isinstance(frame, str) else frame.decode()
            kind = json.loads(text.split("\n\n", 1)[1]).get("kind")
            if kind in kinds:
                dropped.append(kind)
            else:
                ws.send(frame)

        relay.on_message(from_relay)

    page.route_web_socket("**/sub/table-*", route)
    return dropped


def assert_draws(page: Page, view: dict) -> None:
    """The page draws the balls of table view `view` where they stand (and, to the player with
    the cue ball in hand off the table, that ball where the page offers to place it)."""
    drawn = drawn_balls(page)
    if view["next"]["cue_ball"] not in view["state"]["balls"]:
        drawn.pop(view["next"]["cue_ball"], None)
    assert drawn.keys() == view["state"]["balls"].keys()
    for ball, p in drawn.items():
        assert math.dist(p, view["state"]["balls"][ball]) < 1e-9, ball


def test_a_page_that_missed_a_shot_catches_up_from_the_next_message(browser, server, console):
    match = Watched(browser, server, console, "R", viewport={"width": 1100, "height": 700})
    (ada, bob, cy), apis, table, start = match.pages, match.apis, match.table, match.view
    try:
        # Bob's page hears of the shot only through its heartbeats' answers; Cy, who watches
        # (and sends no heartbeat), only through a chat message.
        bob_lost = losing(bob, ("outcome", "presence", "aim", "chat"))
        cy_lost = losing(cy, ("outcome", "presence", "aim"))
        for page in (ada, bob, cy):
            page.goto(f"{server.url}/table/{table}")
            wait_version(page, start["version"])

        after = apis[0].play_picked(table)  # Ada breaks (through the API)
        assert after["version"] == start["version"] + 1
        wait_version(bob, after["version"], timeout=CATCH_UP_MS)
        assert "outcome" in bob_lost  # it did miss the shot, and shows the table after it
        assert_draws(bob, after)

        assert cy.evaluate("window.billiards.version") == start["version"]
        assert "outcome" in cy_lost
        apis[1].call("POST", f"/api/tables/{table}/messages", {"message": "good_shot"})
        wait_version(cy, after["version"], timeout=CATCH_UP_MS)
        assert_draws(cy, after)
    finally:
        match.close()

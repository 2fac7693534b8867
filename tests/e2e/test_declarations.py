"""What a shot declares beside its stroke, chosen in the page: eight-ball's called pocket for
the 8 (the shot is not sent without one) and snooker's nominated colour after a red. The table
is first played by the API with the simple shot picker to where the declaration is needed,
then the page is opened on it and the declaration made in its widget; the server's outcome
says it took the declaration."""

from __future__ import annotations

from rules.eightball import on_eight
from tests.e2e.conftest import (
    Api,
    screenshot,
    strike_with_keys,
    unique_name,
    wait_drawn,
    wait_shown,
)


def shoot_from_page(page, api: Api, table_id: str) -> dict:
    """Strike with the keyboard; the view once the page has shown the outcome."""
    before = api.table(table_id)["version"]
    strike_with_keys(page, hold_ms=300)
    page.wait_for_function(
        "(v) => (window.billiards.version ?? -1) > v", arg=before, timeout=90_000
    )
    return api.table(table_id)


def test_the_eight_is_called_in_the_page(open_page, server):
    page = open_page("/")
    api = Api(page, server)
    api.sign_in(unique_name("Ca"))
    table = api.practice("eightball")
    view = api.play_until(table, lambda s: on_eight(s, s.balls))
    page.goto(server.url + "/practice/eightball")
    wait_shown(page)
    call = page.locator("#extras select[name=call]")
    assert call.is_visible() and call.input_value() == ""
    # Without a call the page does not send the shot (the referee would refuse it) and says so.
    strike_with_keys(page, hold_ms=300)
    page.wait_for_function(
        "() => document.getElementById('status').textContent.includes('choose one')"
    )
    assert api.table(table)["version"] == view["version"]
    assert page.evaluate("document.activeElement.name") == "call"
    call.select_option("top_right")
    page.locator("#view-toggle").click()  # from above, the called pocket ringed
    wait_drawn(page, "top")
    screenshot(page, "practice-eightball-call")
    after = shoot_from_page(page, api, table)
    outcome = after["last_outcome"]
    assert outcome["input"]["call"] == "top_right" and outcome["decision"] is not None
    assert "potted" in page.get_by_role("status").inner_text()


def test_a_colour_is_nominated_after_a_red(open_page, server):
    page = open_page("/")
    api = Api(page, server)
    api.sign_in(unique_name("Nm"))
    table = api.practice("snooker")
    view = api.play_until(table, lambda s: s.on == "colour")
    assert any(b.startswith("red") for b in view["last_outcome"]["decision"]["pocketed"])
    page.goto(server.url + "/practice/snooker")
    wait_shown(page)
    nominate = page.locator("#extras select[name=nominate]")
    offered = nominate.locator("option").all_inner_texts()
    # The page offers exactly the server's list (next.shot.nominate): the colours on the table.
    assert offered == ["(the first ball hit)", *view["next"]["shot"]["nominate"]]
    assert set(offered[1:]) == {"yellow", "green", "brown", "blue", "pink", "black"}
    nominate.select_option("pink")
    screenshot(page, "practice-snooker-nominate")
    after = shoot_from_page(page, api, table)
    outcome = after["last_outcome"]
    assert outcome["input"]["nominate"] == "pink" and outcome["decision"] is not None
    # After the colour the reds are on again (or the visit is over): no nomination offered.
    assert after["state"]["on"] == "red"
    page.wait_for_function("() => !document.querySelector('#extras select[name=nominate]')")

"""The table's sounds: none before the first user gesture (browsers forbid it), then one per
sounding event of each outcome as the animation reaches it (web/src/play/sound.js), and none
once muted, a choice the page keeps across a reload. Counted through the page's debug hook
`window.billiards.sound()`, against the events of the server's outcome."""

from __future__ import annotations

from collections import Counter

from tests.e2e.conftest import Api, enter_name, strike_with_keys, unique_name, wait_shown

#: The event types that make a sound (sound.js SOUNDING); motion state changes are silent.
SOUNDING = {"strike", "ball_ball", "ball_cushion", "ball_jaw", "ball_pocket"}


def sounding_events(page, server) -> Counter:
    """The sounding events of the page's practice table's last outcome, by type. A view
    carries its last outcome without the motion, so the shot is sent again: a resend is
    answered with its first outcome, whole, and plays nothing."""
    api = Api(page, server)
    table = page.evaluate("localStorage.getItem('billiards.practice.nineball')")
    last = api.table(table)["last_outcome"]
    again = {"version": last["version"] - 1, "shot_id": last["shot_id"], "input": last["input"]}
    answer = api.call("POST", f"/api/tables/{table}/intents", again)
    assert answer["status"] == "duplicate" and answer["outcome"]["version"] == last["version"]
    events = answer["outcome"]["trajectory"]["events"]
    return Counter(e["type"] for e in events if e["type"] in SOUNDING)


def sound(page) -> dict:
    return page.evaluate("window.billiards.sound()")


def test_events_sound_after_a_gesture_and_not_when_muted(open_page, server):
    page = open_page("/practice/nineball")
    page.wait_for_selector(".overlay input")
    assert sound(page)["state"] == "none"  # no audio before the visitor has done anything
    enter_name(page, unique_name("Sd"))
    wait_shown(page)
    assert sound(page)["state"] == "running"
    strike_with_keys(page, hold_ms=700, left=3)
    wait_shown(page, 2)
    events = sounding_events(page, server)
    heard = sound(page)
    assert events["strike"] == 1 and events["ball_ball"] >= 1
    assert heard["scheduled"]["strike"] == 1
    for kind, n in heard["scheduled"].items():
        assert 0 < n <= events[kind], kind
    # Every sounding event was either scheduled or dropped in a crowd of simultaneous ones.
    assert sum(heard["scheduled"].values()) + heard["dropped"] == sum(events.values())
    assert heard["muted"] == 0

    toggle = page.locator("#sound")
    assert toggle.get_attribute("aria-pressed") == "true"
    toggle.click()
    assert toggle.get_attribute("aria-pressed") == "false" and toggle.inner_text() == "Sound off"
    page.reload()
    wait_shown(page)
    assert page.locator("#sound").inner_text() == "Sound off"  # remembered
    strike_with_keys(page, hold_ms=500, left=1)
    wait_shown(page, 2)
    muted = sound(page)
    assert muted["scheduled"] == {} and muted["dropped"] == 0
    assert muted["muted"] == sum(sounding_events(page, server).values())

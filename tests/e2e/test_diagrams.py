"""The /diagrams page draws the server's curves and redraws them when a slider moves."""

from __future__ import annotations

from tests.e2e.conftest import artefact


def test_diagrams_draw_and_follow_the_sliders(open_page):
    page = open_page("/diagrams")
    for chart in ("throw-chart", "cushion-chart", "motion-chart"):
        page.wait_for_selector(f"#{chart} canvas")
    page.wait_for_timeout(300)  # the first answers drawn
    before = page.locator("#throw-chart canvas").first.evaluate("(c) => c.toDataURL()")
    # Raise the friction: the throw curve must move, and so must its drawing.
    slider = page.locator('#throw-sliders input[name="throw_b"]')
    slider.evaluate("(el) => { el.value = el.max; el.dispatchEvent(new Event('input')); }")
    page.wait_for_function(
        "(before) => document.querySelector('#throw-chart canvas').toDataURL() !== before",
        arg=before,
    )
    page.screenshot(path=str(artefact("diagrams")), full_page=True)

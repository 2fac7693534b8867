"""The /diagrams page draws the server's curves and redraws them when a slider moves; its
families of shots, the Mathavan figures and the real shots view render without a console
error, and a real shot refits on the server."""

from __future__ import annotations

from tests.e2e.conftest import artefact

REBOUND_FAMILIES = ["stun", "running", "check", "side", "slow_topspin", "hard_topspin"]
THROW_FAMILIES = ["stun", "roll", "varying_roll", "varying_side"]


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


def _fit_says(page, pattern: str, timeout: float = 30_000) -> None:
    """Wait until the real shot's text matches the regular expression `pattern`."""
    page.wait_for_function(
        "(p) => new RegExp(p).test(document.getElementById('real-fit').textContent)",
        arg=pattern,
        timeout=timeout,
    )


def _families(page, box: str) -> list[str]:
    return page.locator(f"#{box} figure").evaluate_all("(fs) => fs.map((f) => f.dataset.family)")


def test_the_families_the_mathavan_figures_and_a_real_shot_render(open_page):
    page = open_page("/diagrams", viewport={"width": 1200, "height": 900})
    page.wait_for_selector("#rebounds-families figure canvas", timeout=60_000)
    page.wait_for_selector("#throws-families figure canvas", timeout=60_000)
    assert _families(page, "rebounds-families") == REBOUND_FAMILIES
    assert _families(page, "throws-families") == THROW_FAMILIES
    legends = page.locator("#throws-families .legend").all_inner_texts()
    assert all("throw" in text for text in legends)
    for chart in ("mathavan-speed-chart", "mathavan-angle-chart", "rebound_side-chart"):
        page.wait_for_selector(f"#{chart} canvas")
    fit = page.locator("#real-fit")
    _fit_says(page, "RMSE")
    assert "1 simulation," in fit.inner_text() and page.locator("#real-shot option").count() == 91
    page.screenshot(path=str(artefact("diagrams-families")), full_page=True)
    # Another shot, then a refit of it on the server within its bound.
    page.select_option("#real-shot", index=3)
    _fit_says(page, "Shot #6 ")
    page.click("#real-refit")
    _fit_says(page, r"\((converged|simulations|time)\)", timeout=60_000)
    assert page.locator("#diagram-error").inner_text() == ""
    page.locator("#real-shots").screenshot(path=str(artefact("diagrams-real-shots")))

"""The fixed-step reference integrator (physics/fixed_step.py) against the event engine."""

from __future__ import annotations

import math

import pytest

from physics import simulate_scene
from physics.accuracy_data import cut_with_throw, position_error, straight_draw
from physics.fixed_step import simulate_fixed


@pytest.mark.parametrize("shot", [straight_draw, cut_with_throw], ids=["draw", "cut"])
def test_fixed_step_converges_to_the_event_engine(shot):
    """Both share every model, so the fixed-step error comes only from finding collisions a
    step late and ending slides within a step: it falls as dt shrinks (by 3x or more from
    1e-3 to 2e-4 s) and is under 5 mm at 2e-4 s on these single-collision shots."""
    scene = shot()
    ref = simulate_scene(scene)
    coarse = position_error(ref, simulate_fixed(scene, 1e-3))
    fine = position_error(ref, simulate_fixed(scene, 2e-4))
    assert fine["rms_mm"] < coarse["rms_mm"] / 3
    assert fine["max_mm"] < 5.0
    assert fine["pocket_mismatch"] == 0


def test_result_has_the_engine_summary_shape_and_is_deterministic():
    scene = cut_with_throw()
    a = simulate_fixed(scene, 1e-3)
    assert a == simulate_fixed(scene, 1e-3)
    ref = simulate_scene(scene)
    assert set(a["final"]) == set(ref["final"])
    for name, f in a["final"].items():
        assert set(f) == {"pos", "state", "pocket"}
        assert f["state"] == ref["final"][name]["state"]
    assert a["models"]["cushion"] == ref["models"]["cushion"]
    assert a["duration"] == pytest.approx(ref["duration"], rel=0.05)


@pytest.mark.parametrize("dt", [0.0, -1e-3, 0.5, math.nan, math.inf])
def test_bad_step_sizes_are_refused(dt):
    with pytest.raises(ValueError, match="dt must be"):
        simulate_fixed(cut_with_throw(), dt)


def test_pockets_catch_balls_as_in_the_engine():
    """A ball sent straight into a corner pocket drops into the same pocket."""
    scene = {
        "table": "nineball",
        "balls": {"cue": [0.3, 0.3]},
        "initial": {"cue": {"v": [-1.0, -1.0]}},
    }
    assert simulate_fixed(scene, 1e-3)["final"]["cue"]["pocket"] == "bottom_left"
    assert simulate_scene(scene)["final"]["cue"]["pocket"] == "bottom_left"

"""Ball motion between collisions against the closed forms of Han 2005 (with docs/physics.md's
corrections 1-3)."""

from __future__ import annotations

import math

import pytest

from physics import simulate
from physics.params import POOL

P = POOL
R, G = P.R, P.g


def open_table(v, w, models=None, at=(5.0, 1.0), others=None):
    """A single ball (or a few) on a 10 m by 150 m carom table: no cushion in reach."""
    scene = {
        "table": {"preset": "nineball", "w": 10.0, "l": 150.0, "pockets": False},
        "balls": {"cue": list(at), **(others or {})},
        "initial": {"cue": {"v": list(v), "w": list(w)}},
    }
    if models:
        scene["models"] = models
    return simulate(scene)


def event_time(shot, kind, ball="cue"):
    return next(e.t for e in shot.events if e.type == kind and ball in e.balls)


@pytest.mark.parametrize("v0", [0.5, 2.0, 6.0])
def test_struck_ball_slides_then_rolls_to_rest(v0):
    """Han 2005, eqs. for a ball struck at its centre: it slides until t = 2 v0 / (7 u_s g),
    leaving at 5/7 v0 after 12 v0^2 / (49 u_s g) of travel, then rolls a further
    (5/7 v0)^2 / (2 u_r g) to rest. Tolerance: 1e-9 relative (the engine is closed form)."""
    shot = open_table((0.0, v0), (0.0, 0.0, 0.0))
    t_slide = 2 * v0 / (7 * P.u_s * G)
    assert event_time(shot, "sliding_rolling") == pytest.approx(t_slide, rel=1e-9)
    rolling = next(s for s in shot.trajectories["cue"] if s.state == "rolling")
    assert rolling.v[1] == pytest.approx(5 / 7 * v0, rel=1e-9)
    assert rolling.r[1] - 1.0 == pytest.approx(12 * v0**2 / (49 * P.u_s * G), rel=1e-9)
    t_roll = (5 / 7 * v0) / (P.u_r * G)
    assert event_time(shot, "rolling_stationary") == pytest.approx(t_slide + t_roll, rel=1e-9)
    travel = 12 * v0**2 / (49 * P.u_s * G) + (5 / 7 * v0) ** 2 / (2 * P.u_r * G)
    assert shot.final["cue"].pos[1] - 1.0 == pytest.approx(travel, rel=1e-9)
    assert shot.final["cue"].pos[0] == pytest.approx(5.0, abs=1e-12)


def test_side_spin_alone_decays_at_the_spin_rate():
    """Correction 3 (docs/physics.md): a ball spinning in place loses w_z at 5/2 u_sp g / R; it
    stops after |w_z| R / (2.5 u_sp g). Tolerance 1e-9 relative."""
    shot = open_table((0.0, 0.0), (0.0, 0.0, 30.0))
    assert event_time(shot, "spinning_stationary") == pytest.approx(
        30.0 * R / (2.5 * P.u_sp * G), rel=1e-9
    )


@pytest.mark.parametrize("kind, roll_factor", [("stun", 0.0), ("follow", 1.0), ("draw", -1.0)])
def test_stun_follow_draw_after_a_full_hit(kind, roll_factor):
    """Full hit with frictionless balls (so the cue ball keeps its spin): the cue ball keeps
    v1 = (1 - e_b)/2 v0 and slides until it rolls at 5/7 v1 + 2/7 (R w) where R w is its
    spin's rolling speed at impact: stun stops dead (but for e_b < 1), follow runs on at about
    2/7 v0, draw comes back at about 2/7 v0 (Han 2005, sec. 3; the "2/7 rule").
    Tolerance 1e-6 relative (the cue ball slides 1 micrometre before contact)."""
    v0 = 2.0
    gap = 1e-6
    shot = open_table(
        (0.0, v0),
        (-roll_factor * v0 / R, 0.0, 0.0),
        models={"ball_ball": "frictionless"},
        others={"1": [5.0, 1.0 + 2 * R + gap]},
    )
    t_hit = event_time(shot, "ball_ball")
    assert t_hit < 1e-5
    # The cue ball's speed at impact, after the micrometre of slide.
    first = shot.trajectories["cue"][1]
    v_hit = first.v[1] + first.a[1] * t_hit
    w_hit = first.w[0] + first.dw[0] * t_hit
    v1 = (1 - P.e_b) / 2 * v_hit
    after = [s for s in shot.trajectories["cue"] if s.t > t_hit and s.state == "rolling"]
    final_speed = after[0].v[1]
    assert final_speed == pytest.approx(5 / 7 * v1 + 2 / 7 * (-w_hit * R), rel=1e-6)
    if kind == "stun":
        assert abs(final_speed) < 0.02 * v0
    if kind == "follow":
        assert final_speed > 0.25 * v0
    if kind == "draw":
        assert final_speed < -0.25 * v0


@pytest.mark.parametrize("side", [0.3, -0.3])
def test_masse_swerve_is_a_parabola_towards_the_side_hit(side):
    """Han 2005 with correction 1 (docs/physics.md): while it slides the slip keeps its
    direction, so the ball moves on a parabola: the lateral offset is 1/2 a_x t^2 with
    a = -u_s g (slip direction). An elevated cue with right english (a > 0) swerves the ball
    right, left english left. Tolerance 1e-9."""
    shot = simulate(
        {
            "table": {"preset": "nineball", "w": 10.0, "l": 10.0, "pockets": False},
            "balls": {"cue": [5.0, 1.0]},
            "strike": {"ball": "cue", "speed": 3.0, "heading": 90.0, "elevation": 60.0, "a": side},
        }
    )
    slide = shot.trajectories["cue"][1]
    assert slide.state == "sliding"
    ux, uy = slide.v[0] - R * slide.w[1], slide.v[1] + R * slide.w[0]
    u = math.hypot(ux, uy)
    assert slide.a[0] == pytest.approx(-P.u_s * G * ux / u, rel=1e-9)
    t_end = event_time(shot, "sliding_rolling")
    for frac in (0.25, 0.5, 1.0):
        t = frac * t_end
        x, _ = shot.position("cue", t)
        assert x - 5.0 == pytest.approx(slide.v[0] * t + 0.5 * slide.a[0] * t * t, abs=1e-12)
    lateral = shot.position("cue", t_end)[0] - 5.0
    assert math.copysign(1.0, lateral) == math.copysign(1.0, side)
    assert abs(lateral) > 0.01

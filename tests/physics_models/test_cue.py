"""The cue strike (physics/cue.py): speed, spin directions, limits."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from physics.cue import MAX_ELEVATION, MAX_SPEED, MISCUE_LIMIT, strike
from physics.params import POOL

R = POOL.R


def momentum_speed(cue_speed, offset2=0.0):
    """Leckie & Greenspan / Marlow: ball speed 2 V / (1 + m/M + 5/2 (a^2 + b^2)) for a level
    cue, offsets in units of R."""
    return 2.0 * cue_speed / (1.0 + POOL.m / POOL.m_cue + 2.5 * offset2)


def test_centre_hit_gives_no_spin_and_the_momentum_speed():
    v, w = strike(3.0, 90.0, 0.0, 0.0, 0.0, POOL)
    assert v[0] == pytest.approx(0.0, abs=1e-12)
    assert v[1] == pytest.approx(momentum_speed(3.0), rel=1e-12)
    assert max(map(abs, w)) == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("heading", [0.0, 37.0, 180.0, 271.5])
def test_heading_sets_the_direction(heading):
    v, _ = strike(2.0, heading, 0.0, 0.0, 0.0, POOL)
    assert math.degrees(math.atan2(v[1], v[0])) % 360 == pytest.approx(heading % 360, abs=1e-9)


def test_top_hit_gives_follow_and_bottom_hit_gives_draw():
    """Shooting along +y: natural roll has w_x = -v/R. A hit above centre spins the ball that
    way (follow), below the other way (draw); b = 2/5 is the natural-roll height."""
    v, w = strike(2.0, 90.0, 0.0, 0.0, 0.4, POOL)
    assert w[0] < 0
    assert -w[0] * R == pytest.approx(v[1], rel=1e-9)  # rolls from the start
    v, w = strike(2.0, 90.0, 0.0, 0.0, -0.3, POOL)
    assert w[0] > 0
    assert w[1] == pytest.approx(0.0, abs=1e-9)
    assert w[2] == pytest.approx(0.0, abs=1e-9)


def test_side_hits_spin_about_the_vertical():
    """Right of centre (a > 0) turns the ball counter-clockwise seen from above (w_z > 0),
    left of centre clockwise; side spin alone adds no top or back spin."""
    _, right = strike(2.0, 90.0, 0.0, 0.3, 0.0, POOL)
    _, left = strike(2.0, 90.0, 0.0, -0.3, 0.0, POOL)
    assert right[2] > 0 > left[2]
    assert right[2] == pytest.approx(-left[2])
    assert right[0] == pytest.approx(0.0, abs=1e-9)


def test_offset_hits_are_slower_and_spin_as_the_formula_says():
    """Ball speed falls with offset as 1 / (1 + m/M + 5/2 (a^2 + b^2)), and the spin is
    5/2 v (offset) / R per unit of offset (angular impulse F r / I)."""
    v, w = strike(4.0, 0.0, 0.0, 0.3, 0.4, POOL)
    speed = math.hypot(*v)
    assert speed == pytest.approx(momentum_speed(4.0, 0.25), rel=1e-12)
    assert w[2] == pytest.approx(2.5 * speed * 0.3 / R, rel=1e-9)
    assert math.hypot(w[0], w[1]) == pytest.approx(2.5 * speed * 0.4 / R, rel=1e-9)


def test_elevated_centre_hit_draws_and_keeps_less_speed():
    """An elevated cue drives down through the back of the ball: the horizontal speed is cut
    to cos(elevation) of the impulse and the ball takes back spin."""
    flat_v, _ = strike(3.0, 90.0, 0.0, 0.0, 0.0, POOL)
    v, w = strike(3.0, 90.0, 30.0, 0.0, 0.0, POOL)
    assert v[1] < flat_v[1] * math.cos(math.radians(30.0)) + 1e-12
    assert w[0] > 0  # draw


@settings(max_examples=200, deadline=None)
@given(
    speed=st.floats(0.01, MAX_SPEED),
    heading=st.floats(-720.0, 720.0),
    elevation=st.floats(0.0, MAX_ELEVATION),
    angle=st.floats(0.0, 2 * math.pi),
    radius=st.floats(0.0, MISCUE_LIMIT),
)
def test_the_ball_never_gets_more_energy_than_the_cue_had(speed, heading, elevation, angle, radius):
    a, b = radius * math.cos(angle), radius * math.sin(angle)
    v, w = strike(speed, heading, elevation, a, b, POOL)
    ball = 0.5 * POOL.m * (v[0] ** 2 + v[1] ** 2) + 0.2 * POOL.m * R * R * sum(x * x for x in w)
    assert ball <= 0.5 * POOL.m_cue * speed**2 * (1 + 1e-12)


@pytest.mark.parametrize(
    "args, message",
    [
        ((float("nan"), 90.0, 0.0, 0.0, 0.0), "speed must be a finite"),
        ((2.0, float("inf"), 0.0, 0.0, 0.0), "heading must be a finite"),
        ((2.0, 90.0, 0.0, float("nan"), 0.0), "a must be a finite"),
        ((0.0, 90.0, 0.0, 0.0, 0.0), "speed must be in"),
        ((-1.0, 90.0, 0.0, 0.0, 0.0), "speed must be in"),
        ((MAX_SPEED + 0.5, 90.0, 0.0, 0.0, 0.0), "speed must be in"),
        ((2.0, 90.0, -1.0, 0.0, 0.0), "elevation must be in"),
        ((2.0, 90.0, MAX_ELEVATION + 0.5, 0.0, 0.0), "elevation must be in"),
        ((2.0, 90.0, 0.0, 0.4, 0.31), "miscue"),
        ((2.0, 90.0, 0.0, 0.0, -MISCUE_LIMIT - 0.01), "miscue"),
    ],
)
def test_bad_strikes_raise_clear_errors(args, message):
    with pytest.raises(ValueError, match=message):
        strike(*args, POOL)


def test_limits_are_accepted():
    strike(MAX_SPEED, 0.0, MAX_ELEVATION, 0.0, MISCUE_LIMIT, POOL)
    strike(1e-6, 0.0, 0.0, -MISCUE_LIMIT, 0.0, POOL)

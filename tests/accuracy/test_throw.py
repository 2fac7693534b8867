"""Ball-ball throw against Alciatore's throw analysis (his technical proof on collision-induced
throw and its published throw-versus-cut curves), and the 90 degree rule."""

from __future__ import annotations

import itertools
import math
from dataclasses import replace

import pytest

from physics.accuracy_data import throw_angle
from physics.ball_ball import BALL_BALL_MODELS
from physics.params import POOL

CUTS = range(0, 91, 5)
SLOW, FAST = 0.45, 3.0  # about 1 mph and 7 mph, the speeds of Alciatore's curves


def curve(speed, spin):
    return {c: throw_angle(c, speed, spin) for c in CUTS}


def test_slow_stun_throw_peaks_near_a_half_ball_hit_at_a_few_degrees():
    """Alciatore's stun curve at slow speed rises from zero, peaks at 4-6 degrees between a
    quarter-ball and a half-ball-and-a-bit hit (cut 20-45 degrees), then eases off.
    Tolerance: peak 3.5-6 degrees at a cut of 20-45 degrees; zero throw at a full hit."""
    throws = curve(SLOW, "stun")
    peak_cut = max(throws, key=throws.get)
    assert throws[0] == pytest.approx(0.0, abs=1e-12)
    assert 3.5 <= throws[peak_cut] <= 6.0
    assert 20 <= peak_cut <= 45
    assert throws[90] < throws[peak_cut]


def test_faster_shots_throw_less():
    """Friction falls with sliding speed (mu = a + b exp(-c v)), so a fast stun shot throws
    about half as much as a slow one: fast peak 1.5-3.5 degrees and below the slow curve at
    every cut from 20 degrees on. At small cuts the slip between the balls stops during the
    impact (the m |v_t| / 7 limit), so there the throw is the same at any speed (to 1e-9)."""
    slow, fast = curve(SLOW, "stun"), curve(FAST, "stun")
    assert 1.5 <= max(fast.values()) <= 3.5
    assert all(fast[c] < slow[c] for c in CUTS if c >= 20)
    assert fast[5] == pytest.approx(slow[5], abs=1e-9)


def test_rolling_cue_ball_throws_less_than_a_stun_one():
    """Alciatore: follow (or draw) reduces throw, most at small cuts, because the ball's roll
    cancels part of the slip between the balls. Rolling throw grows steadily with cut and
    stays below the stun throw at the same speed for cuts up to 60 degrees."""
    stun, roll = curve(SLOW, "stun"), curve(SLOW, "roll")
    assert all(roll[c] < stun[c] for c in CUTS if 0 < c <= 60)
    values = [roll[c] for c in CUTS]
    assert all(b >= a for a, b in itertools.pairwise(values))


def test_throw_never_exceeds_the_friction_angle():
    """The throw angle is atan(J_t / J_n) <= atan(mu_max) with mu_max = a + b at zero slip."""
    limit = math.degrees(math.atan(POOL.throw_a + POOL.throw_b))
    for speed in (0.2, SLOW, FAST, 8.0):
        for spin in ("stun", "roll"):
            assert max(curve(speed, spin).values()) <= limit + 1e-9


@pytest.mark.parametrize("cut", [5.0, 30.0, 60.0, 85.0])
def test_frictionless_stun_obeys_the_90_degree_rule(cut):
    """With frictionless, perfectly elastic balls (e_b = 1) a stun cue ball and the object
    ball leave at exactly 90 degrees to each other, and the object ball along the line of
    centres (no throw). Tolerance 1e-9 degrees."""
    p = replace(POOL, e_b=1.0)
    a = math.radians(cut)
    n = (math.sin(a), math.cos(a))
    va, _, vb, _ = BALL_BALL_MODELS["frictionless"](
        (0.0, 2.0), (0, 0, 0), (0.0, 0.0), (0, 0, 0), n, p
    )
    angle = math.degrees(
        math.acos((va[0] * vb[0] + va[1] * vb[1]) / math.hypot(*va) / math.hypot(*vb))
    )
    assert angle == pytest.approx(90.0, abs=1e-9)
    assert throw_angle(cut, 2.0, "stun", p, model="frictionless") == pytest.approx(0.0, abs=1e-9)

"""Energy and momentum bookkeeping of every collision model: what each dissipates, checked against
its restitution and friction (docs/physics.md, corrections 4-7, for the models' definitions)."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from physics.ball_ball import BALL_BALL_MODELS
from physics.cue import strike
from physics.cushion import CUSHION_MODELS
from physics.params import POOL

P = POOL
R, M = P.R, P.m
I = 0.4 * M * R * R


def energy(v, w):
    return 0.5 * M * (v[0] ** 2 + v[1] ** 2) + 0.5 * I * sum(x * x for x in w)


speeds = st.floats(0.05, 8.0)
spins = st.floats(-1.5, 1.5)
angles = st.floats(0.0, 2 * math.pi)


@settings(max_examples=200, deadline=None)
@given(
    speed=speeds, hit=st.floats(-0.99, 0.99), wx=spins, wy=spins, wz=spins, e=st.floats(0.5, 1.0)
)
def test_frictionless_balls_conserve_momentum_and_lose_exactly_the_restitution_share(
    speed, hit, wx, wy, wz, e
):
    """Frictionless ball-ball: momentum conserved to 1e-12, spins untouched, and the energy
    lost is exactly (1 - e^2)/4 m v_n^2 (relative 1e-9), the normal share of a half-mass
    impact."""
    p = replace(P, e_b=e)
    n = (hit, math.sqrt(1 - hit * hit))
    va, wa = (0.0, speed), (wx * speed / R, wy * speed / R, wz * speed / R)
    va1, wa1, vb1, wb1 = BALL_BALL_MODELS["frictionless"](va, wa, (0.0, 0.0), (0, 0, 0), n, p)
    assert va1[0] + vb1[0] == pytest.approx(va[0], abs=1e-12)
    assert va1[1] + vb1[1] == pytest.approx(va[1], abs=1e-12)
    assert wa1 == wa
    vn = va[0] * n[0] + va[1] * n[1]
    before = energy(va, wa)
    lost = before - energy(va1, wa1) - energy(vb1, wb1)
    # The loss is a difference of energies: its rounding error scales with the energy itself.
    assert lost == pytest.approx((1 - e * e) / 4 * M * vn * vn, rel=1e-9, abs=1e-14 * before)


@settings(max_examples=200, deadline=None)
@given(speed=speeds, hit=st.floats(-0.99, 0.99), wx=spins, wy=spins, wz=spins)
def test_alciatore_conserves_table_momentum_and_loses_at_least_the_normal_share(
    speed, hit, wx, wy, wz
):
    """Alciatore's friction impulse is equal and opposite on the two balls, so momentum in
    the table plane is conserved (1e-12); friction only adds loss, so the energy lost is at
    least the frictionless (1 - e^2)/4 m v_n^2 and at most that plus mu J_n times the slip
    speed (the most Coulomb friction can dissipate)."""
    n = (hit, math.sqrt(1 - hit * hit))
    va, wa = (0.0, speed), (wx * speed / R, wy * speed / R, wz * speed / R)
    va1, wa1, vb1, wb1 = BALL_BALL_MODELS["alciatore"](va, wa, (0.0, 0.0), (0, 0, 0), n, P)
    assert va1[0] + vb1[0] == pytest.approx(va[0], abs=1e-12)
    assert va1[1] + vb1[1] == pytest.approx(va[1], abs=1e-12)
    vn = va[0] * n[0] + va[1] * n[1]
    before = energy(va, wa)
    lost = before - energy(va1, wa1) - energy(vb1, wb1)
    normal = (1 - P.e_b**2) / 4 * M * vn * vn
    assert lost >= normal * (1 - 1e-9) - 1e-14 * before
    slip_bound = (P.throw_a + P.throw_b) * M * (1 + P.e_b) / 2 * vn * (speed * 2.6)
    assert lost <= normal + slip_bound


@pytest.mark.parametrize("model", ["han", "mathavan"])
@pytest.mark.parametrize("e_c", [0.6, 0.85, 1.0])
def test_cushion_without_friction_keeps_e_squared_of_the_normal_energy(model, e_c):
    """Without friction a cushion keeps e_c^2 of the normal kinetic energy and all the rest
    (relative 1e-9), at any angle."""
    p = replace(P, e_c=e_c, f_c=0.0, u_s=0.0)
    for angle in (0.0, 30.0, 70.0):
        a = math.radians(angle)
        v = (2.0 * math.sin(a), -2.0 * math.cos(a))
        v1, _w1 = CUSHION_MODELS[model](v, (5.0, -7.0, 11.0), (0.0, 1.0), p, 0.27)
        assert v1[1] ** 2 == pytest.approx(e_c**2 * v[1] ** 2, rel=1e-9)
        assert v1[0] == pytest.approx(v[0], rel=1e-12)


@pytest.mark.parametrize("model", ["han", "mathavan"])
def test_cushion_friction_dissipates_beyond_restitution(model):
    """With friction the loss is at least the restitution share (1 - e^2) of the normal energy
    and no more than the total energy: for rolling balls at 0-80 degrees."""
    for angle in range(0, 81, 10):
        a = math.radians(angle)
        v = (2.0 * math.sin(a), -2.0 * math.cos(a))
        w = (-v[1] / R, v[0] / R, 0.0)
        v1, w1 = CUSHION_MODELS[model](v, w, (0.0, 1.0), P, 0.27)
        lost = energy(v, w) - energy(v1, w1)
        assert lost >= (1 - P.e_c**2) * 0.5 * M * v[1] ** 2 * 0.999
        assert lost <= energy(v, w)


@settings(max_examples=100, deadline=None)
@given(speed=st.floats(0.1, 12.0), a=st.floats(-0.35, 0.35), b=st.floats(-0.35, 0.35))
def test_cue_strike_momentum_and_energy(speed, a, b):
    """Level cue: the ball's momentum is the impulse 2 m V / (1 + m/M + 5/2 (a^2 + b^2)) and
    its energy share is what an elastic impact of the cue (mass m_cue) gives (relative 1e-9):
    the cue keeps the rest."""
    v, w = strike(speed, 90.0, 0.0, a, b, P)
    impulse = 2 * M * speed / (1 + M / P.m_cue + 2.5 * (a * a + b * b))
    assert M * math.hypot(*v) == pytest.approx(impulse, rel=1e-9)
    cue_after = speed - impulse / P.m_cue
    assert energy(v, w) + 0.5 * P.m_cue * cue_after**2 == pytest.approx(
        0.5 * P.m_cue * speed**2, rel=1e-9
    )

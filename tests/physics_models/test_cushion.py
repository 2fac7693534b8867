"""The cushion models (physics/cushion.py): energy, symmetry, spin, convergence, agreement."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from physics.cushion import CUSHION_MODELS, han, mathavan
from physics.params import POOL

#: The nine-ball preset's nose height: 63.5% of the ball's diameter.
SIN_THETA = 0.635 * 2 - 1
R = POOL.R


def energy(v, w, p=POOL):
    """Kinetic plus rotational energy of a solid ball (J)."""
    return 0.5 * p.m * (v[0] ** 2 + v[1] ** 2) + 0.2 * p.m * R * R * sum(x * x for x in w)


def speed(v):
    return math.hypot(v[0], v[1])


def mirror(v, w):
    """Reflect in the plane x = 0 (which contains the normal (0, 1)): v_x and the axial
    vector's y and z components change sign."""
    return (-v[0], v[1]), (w[0], -w[1], -w[2])


NORMAL = (0.0, 1.0)  # the bottom cushion, y = 0: the ball approaches with v_y < 0


def incoming(speed_, angle_deg):
    """Velocity towards the bottom cushion at angle_deg from its normal (+ = moving +x)."""
    a = math.radians(angle_deg)
    return (speed_ * math.sin(a), -speed_ * math.cos(a))


def rolling(v):
    """Natural roll on the cloth: the contact point at -R z is at rest, so w = z x v / R."""
    return (-v[1] / R, v[0] / R, 0.0)


models = st.sampled_from(sorted(CUSHION_MODELS))
spins = st.floats(-1.5, 1.5)


@settings(max_examples=150, deadline=None)
@given(
    model=models,
    v_in=st.floats(0.05, 8.0),
    angle=st.floats(-85.0, 85.0),
    wx=spins,
    wy=spins,
    wz=spins,
    sin_theta=st.floats(0.1, 0.45),
    e_c=st.floats(0.5, 1.0),
    f_c=st.floats(0.0, 0.6),
    u_s=st.floats(0.0, 0.4),
)
def test_energy_never_increases(model, v_in, angle, wx, wy, wz, sin_theta, e_c, f_c, u_s):
    """Kinetic plus rotational energy after an impact never exceeds that before, over a grid
    of speeds, angles, spins (up to 1.5 v/R on each axis), nose heights and coefficients."""
    p = replace(POOL, e_c=e_c, f_c=f_c, u_s=u_s)
    v = incoming(v_in, angle)
    w = (wx * v_in / R, wy * v_in / R, wz * v_in / R)
    v1, w1 = CUSHION_MODELS[model](v, w, NORMAL, p, sin_theta)
    assert energy(v1, w1, p) <= energy(v, w, p) * (1 + 1e-9)
    assert v1[1] > 0.0  # it leaves the cushion


@pytest.mark.parametrize("model", sorted(CUSHION_MODELS))
def test_frictionless_head_on_rebound_keeps_e(model):
    """Without friction a head-on hit keeps exactly e_c of the speed and gains no spin."""
    p = replace(POOL, f_c=0.0, u_s=0.0)
    v1, w1 = CUSHION_MODELS[model]((0.0, -2.0), (0.0, 0.0, 0.0), NORMAL, p, SIN_THETA)
    assert v1[0] == pytest.approx(0.0, abs=1e-12)
    assert v1[1] == pytest.approx(2.0 * p.e_c, rel=1e-9)
    assert max(map(abs, w1)) == pytest.approx(0.0, abs=1e-9)


def test_han_head_on_stun_rebounds_near_e():
    """Han, with friction: a stun ball hit head-on comes back at e_c times its speed to within
    3% (the friction at the nose, which sticks, adds only a little backspin and speed loss)."""
    v1, _ = han((0.0, -2.0), (0.0, 0.0, 0.0), NORMAL, POOL, SIN_THETA)
    assert v1[0] == pytest.approx(0.0, abs=1e-12)
    assert v1[1] / 2.0 == pytest.approx(POOL.e_c, rel=0.03)


@pytest.mark.parametrize("model", sorted(CUSHION_MODELS))
@pytest.mark.parametrize("angle", [0.0, 20.0, 45.0, 70.0])
@pytest.mark.parametrize("spin", ["stun", "roll", "side"])
def test_mirror_inputs_give_mirror_outputs(model, angle, spin):
    """Reflecting the incoming state across the cushion normal reflects the outcome."""
    v = incoming(2.5, angle)
    w = {"stun": (0.0, 0.0, 0.0), "roll": rolling(v), "side": (10.0, -30.0, 40.0)}[spin]
    v1, w1 = CUSHION_MODELS[model](v, w, NORMAL, POOL, SIN_THETA)
    mv, mw = mirror(v, w)
    v2, w2 = CUSHION_MODELS[model](mv, mw, NORMAL, POOL, SIN_THETA)
    ev, ew = mirror(v1, w1)
    assert v2 == pytest.approx(ev, abs=1e-9)
    assert w2 == pytest.approx(ew, abs=1e-6)


@pytest.mark.parametrize("model", sorted(CUSHION_MODELS))
def test_side_spin_throws_the_rebound_its_way(model):
    """Running english: a head-on ball spinning counter-clockwise seen from above (w_z > 0,
    what a tip right of centre gives) has its nose contact moving left, so the cushion's
    friction pushes it right; the opposite spin sends it left, and no spin straight back."""
    v = (0.0, -2.0)
    out = {}
    for wz in (-60.0, 0.0, 60.0):
        w = (*rolling(v)[:2], wz)
        out[wz] = CUSHION_MODELS[model](v, w, NORMAL, POOL, SIN_THETA)[0]
    # Looking at the bottom cushion from the table (towards -y), right is -x.
    assert out[60.0][0] < -0.05
    assert out[-60.0][0] > 0.05
    assert out[0.0][0] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("model", sorted(CUSHION_MODELS))
def test_rebound_angle_widens_with_friction_on_a_stun_ball(model):
    """An angled stun ball leaves at a steeper angle to the cushion than a frictionless one:
    friction at the nose slows its motion along the cushion more than it slows the normal."""
    v = incoming(2.0, 45.0)
    smooth = CUSHION_MODELS[model](v, (0.0, 0.0, 0.0), NORMAL, replace(POOL, f_c=0.0), SIN_THETA)
    rough = CUSHION_MODELS[model](v, (0.0, 0.0, 0.0), NORMAL, POOL, SIN_THETA)
    assert abs(rough[0][0]) < abs(smooth[0][0])


def test_han_and_mathavan_agree_without_friction():
    """With no friction anywhere the two models are the same impact: the normal speed comes
    back times e_c, the rest is untouched, at every angle and spin."""
    p = replace(POOL, f_c=0.0, u_s=0.0)
    for angle in (-60.0, -10.0, 0.0, 30.0, 80.0):
        v = incoming(3.0, angle)
        for w in ((0.0, 0.0, 0.0), rolling(v), (40.0, -10.0, 90.0)):
            a = han(v, w, NORMAL, p, SIN_THETA)
            b = mathavan(v, w, NORMAL, p, SIN_THETA)
            assert a[0] == pytest.approx(b[0], abs=1e-9)
            assert a[1] == pytest.approx(b[1], abs=1e-7)


def test_han_close_to_mathavan_with_cushion_friction_only():
    """With cushion friction but none at the cloth, Han's single impulse stays within 10% of
    the speed of Mathavan's integration for rolling balls at common angles."""
    p = replace(POOL, u_s=0.0)
    for angle in (0.0, 20.0, 40.0, 60.0):
        v = incoming(2.0, angle)
        a = han(v, rolling(v), NORMAL, p, SIN_THETA)[0]
        b = mathavan(v, rolling(v), NORMAL, p, SIN_THETA)[0]
        assert math.dist(a, b) < 0.1 * 2.0


def reference(v, w):
    return mathavan(v, w, NORMAL, replace(POOL, mathavan_steps=4000), SIN_THETA)


@pytest.mark.parametrize(
    "v, w",
    [
        (incoming(3.0, 0.0), (0.0, 0.0, 80.0)),
        (incoming(1.0, 60.0), (-20.0, 35.0, -50.0)),
        (incoming(2.0, 10.0), (30.0, 20.0, 60.0)),
    ],
    ids=["stun-side-spin", "mixed-spin-60deg", "mixed-spin-10deg"],
)
def test_mathavan_converges_as_steps_grow(v, w):
    """The rebound velocity converges to a 4000-step reference as the step count grows.

    Runge-Kutta 4 with located stops falls far faster than explicit Euler (1/steps, docs/physics.md
    correction 7) until it meets a floor of about 1e-5 m/s set by where small slips are taken as
    stuck.
    The default step count is within 1e-4 of the incoming speed of the reference (0.3 mm of
    position per second of travel after a 3 m/s bounce).
    """
    ref = reference(v, w)[0]
    errors = {}
    for steps in (1, 16, 256):
        out = mathavan(v, w, NORMAL, replace(POOL, mathavan_steps=steps), SIN_THETA)[0]
        errors[steps] = math.dist(out, ref)
    assert errors[16] < errors[1] / 5
    assert errors[256] < 2e-5
    default = mathavan(v, w, NORMAL, POOL, SIN_THETA)[0]
    assert math.dist(default, ref) < 1e-4 * math.hypot(*v)


@pytest.mark.parametrize("model", sorted(CUSHION_MODELS))
def test_a_ball_leaving_the_cushion_is_untouched(model):
    v, w = (0.3, 1.0), (1.0, 2.0, 3.0)
    assert CUSHION_MODELS[model](v, w, NORMAL, POOL, SIN_THETA) == (v, w)


@pytest.mark.parametrize("model", sorted(CUSHION_MODELS))
def test_same_input_same_bits(model):
    v = incoming(2.7, 33.0)
    w = (12.0, -40.0, 25.0)
    first = CUSHION_MODELS[model](v, w, NORMAL, POOL, SIN_THETA)
    assert all(CUSHION_MODELS[model](v, w, NORMAL, POOL, SIN_THETA) == first for _ in range(3))


@pytest.mark.parametrize("model", sorted(CUSHION_MODELS))
def test_any_cushion_orientation_is_the_same_impact(model):
    """Rotating the whole impact (cushion normal, velocity, spin about z) rotates the result."""
    v, w = incoming(2.0, 25.0), (15.0, -30.0, 20.0)
    base_v, base_w = CUSHION_MODELS[model](v, w, NORMAL, POOL, SIN_THETA)
    a = math.radians(117.0)
    ca, sa = math.cos(a), math.sin(a)

    def rot(x):
        return (ca * x[0] - sa * x[1], sa * x[0] + ca * x[1])

    rv, rw = CUSHION_MODELS[model](rot(v), (*rot(w[:2]), w[2]), rot(NORMAL), POOL, SIN_THETA)
    assert rv == pytest.approx(rot(base_v), abs=1e-9)
    assert rw == pytest.approx((*rot(base_w[:2]), base_w[2]), abs=1e-6)


@settings(max_examples=300, deadline=None)
@given(
    model=models,
    v_in=st.floats(1e-6, 12.0),
    angle=st.floats(-89.9, 89.9),
    w=st.tuples(*[st.sampled_from([0.0, 1.0]).flatmap(lambda k: st.floats(-500 * k, 500 * k))] * 3),
    sin_theta=st.sampled_from([0.0, 0.27, 0.7]),
    e_c=st.sampled_from([0.0, 0.5, 1.0]),
    f_c=st.sampled_from([0.0, 0.2, 1.0]),
    u_s=st.sampled_from([0.0, 0.2, 0.6]),
)
def test_extreme_inputs_give_finite_dissipative_results(
    model, v_in, angle, w, sin_theta, e_c, f_c, u_s
):
    """Far outside play (spins of 500 rad/s on crawling balls, friction 1, a nose at 85% of
    the ball's height) the models still return finite states without gaining energy; where
    friction would wedge the ball into the cushion, Mathavan hands over to Han's closed form
    rather than integrate forever."""
    p = replace(POOL, e_c=e_c, f_c=f_c, u_s=u_s)
    v = incoming(v_in, angle)
    v1, w1 = CUSHION_MODELS[model](v, w, NORMAL, p, sin_theta)
    assert all(math.isfinite(x) for x in (*v1, *w1))
    assert energy(v1, w1, p) <= energy(v, w, p) * (1 + 1e-9) + 1e-18


@pytest.mark.parametrize("model", sorted(CUSHION_MODELS))
@pytest.mark.parametrize("roll", [0.0, 0.5, 0.9, 1.0, -0.5])
@pytest.mark.parametrize("angle", [0.0, 25.0])
def test_a_tiny_change_in_the_input_makes_a_tiny_change_in_the_result(model, roll, angle):
    """Continuity: moving the incoming velocity by 1e-9 of its size moves the rebound by less
    than 1e-6 of it. Head-on balls with partial roll are the hard case: there a slip lands
    exactly on zero within a step and a rounding-level sideways slip must not be taken for a
    direction (the engine's 1e-9 m sensitivity checks rely on this)."""
    v = incoming(2.5, angle)
    w = (-roll * v[1] / R, roll * v[0] / R, 0.0)
    base = CUSHION_MODELS[model](v, w, NORMAL, POOL, SIN_THETA)[0]
    for dx in (1e-9, -1e-9):
        moved = CUSHION_MODELS[model]((v[0] + dx * 2.5, v[1]), w, NORMAL, POOL, SIN_THETA)[0]
        assert math.dist(moved, base) < 1e-6 * 2.5

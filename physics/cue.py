"""The cue strike: an instantaneous point impact of the cue tip on the ball.

The cue (mass m_cue, speed V along its axis) hits the ball at a point of its surface; the
impact is elastic, quick and without tip slip, so the impulse F acts along the cue's axis d at
the contact point r (from the ball's centre). Momentum and energy then give the result of
Leckie & Greenspan and of Marlow ("The Physics of Pocket Billiards"), the model pooltool calls
`instantaneous_point`:

    F = 2 m V / (1 + m / m_cue + 5/2 |r x d|^2 / R^2),   v = F d / m,   w = F (r x d) / I

with I = 2/5 m R^2 the ball's moment of inertia. The tip position (a, b) is where the tip
touches the ball as the player sees it from behind, level with the ball: a to the right, b up,
both as fractions of R. Elevating the cue tilts d downwards, so a centre hit of an elevated cue
also draws; the downward part of v is taken by the cloth (the ball stays on the table).
"""

from __future__ import annotations

import math

from physics.params import Params

#: Fastest cue speed accepted (m/s): well above a professional break (about 10 m/s).
MAX_SPEED = 12.0

#: Largest tip offset from the ball's centre, as a fraction of R, that does not miscue.
#: Alciatore's measurements of the miscue limit (his technical proofs on maximum spin; the
#: figure is also what pooltool and most games use) put it near half the radius: there the tip
#: meets the surface 30 degrees (asin 0.5) from the normal, and tan(30 degrees) = 0.58 is about
#: the friction a chalked tip can hold.
MISCUE_LIMIT = 0.5

#: Largest cue elevation accepted (degrees above horizontal).
MAX_ELEVATION = 89.0


def strike(
    speed: float, heading: float, elevation: float, a: float, b: float, p: Params
) -> tuple[tuple[float, float], tuple[float, float, float]]:
    """The ball's velocity (table plane) and angular velocity just after the cue hits it.

    speed: cue speed (m/s), in (0, MAX_SPEED]. heading: direction of the shot in degrees from
    +x. elevation: cue elevation in degrees, in [0, MAX_ELEVATION]. a, b: tip offset right of
    and above the centre as fractions of R, with sqrt(a^2 + b^2) <= MISCUE_LIMIT.
    Raises ValueError for anything else, naming the bad value.
    """
    for name, value in (
        ("speed", speed),
        ("heading", heading),
        ("elevation", elevation),
        ("a", a),
        ("b", b),
    ):
        if not math.isfinite(value):
            raise ValueError(f"strike {name} must be a finite number, got {value!r}")
    if not 0.0 < speed <= MAX_SPEED:
        raise ValueError(f"strike speed must be in (0, {MAX_SPEED}] m/s, got {speed}")
    if not 0.0 <= elevation <= MAX_ELEVATION:
        raise ValueError(
            f"strike elevation must be in [0, {MAX_ELEVATION}] degrees, got {elevation}"
        )
    offset = math.hypot(a, b)
    if offset > MISCUE_LIMIT:
        raise ValueError(
            f"miscue: tip offset sqrt(a^2 + b^2) = {offset:.3f} R exceeds {MISCUE_LIMIT} R"
        )
    R = p.R
    phi = math.radians(heading)
    theta = math.radians(elevation)
    # Horizontal heading h, the player's right r = h x z, and up z.
    hx, hy = math.cos(phi), math.sin(phi)
    rx, ry = hy, -hx
    # Cue axis d (downwards when elevated) and the contact point from the centre.
    ct, st = math.cos(theta), math.sin(theta)
    d = (hx * ct, hy * ct, -st)
    back = math.sqrt(max(0.0, 1.0 - a * a - b * b))  # depth of the contact behind the centre
    q = (R * (a * rx - back * hx), R * (a * ry - back * hy), R * b)
    # Lever arm of the impulse: q x d.
    lever = (
        q[1] * d[2] - q[2] * d[1],
        q[2] * d[0] - q[0] * d[2],
        q[0] * d[1] - q[1] * d[0],
    )
    lever2 = (lever[0] ** 2 + lever[1] ** 2 + lever[2] ** 2) / (R * R)
    impulse = 2.0 * p.m * speed / (1.0 + p.m / p.m_cue + 2.5 * lever2)  # F, in N s
    v_scale = impulse / p.m
    w_scale = impulse / (0.4 * p.m * R * R)
    return (
        (v_scale * d[0], v_scale * d[1]),
        (w_scale * lever[0], w_scale * lever[1], w_scale * lever[2]),
    )

"""Ball-ball collision models: an instantaneous impulse at the contact point.

`alciatore` adds the friction between the balls that makes an object ball "throw" off the
line of centres (Alciatore's technical proofs, with docs/physics.md's corrections 4 and 5):
the normal impulse is m (1 + e) / 2 v_n; the friction impulse opposes the full contact-point slip
(vertical part included, which is what draw and follow put there) with magnitude
min(mu |J_n|, m |v_t| / 7), mu = a + b exp(-c |v_t|), the 1/7 being where the slip of two equal
solid spheres would stop. Both balls receive the same angular impulse. `frictionless` keeps
only the normal impulse: a stun shot then obeys the 90 degree rule exactly.

Every model takes (va, wa, vb, wb, n, p): velocities (2-tuples, table plane), angular
velocities (3-tuples), n the unit vector from ball a's centre to ball b's, and Params; and
returns the four updated vectors.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from physics.params import Params

V2 = tuple[float, float]
V3 = tuple[float, float, float]
BallBallModel = Callable[[V2, V3, V2, V3, V2, Params], tuple[V2, V3, V2, V3]]


def frictionless(va: V2, wa: V3, vb: V2, wb: V3, n: V2, p: Params) -> tuple[V2, V3, V2, V3]:
    nx, ny = n
    vn = (va[0] - vb[0]) * nx + (va[1] - vb[1]) * ny
    if vn <= 0.0:
        return va, wa, vb, wb
    dv = 0.5 * (1.0 + p.e_b) * vn
    return (
        (va[0] - dv * nx, va[1] - dv * ny),
        wa,
        (vb[0] + dv * nx, vb[1] + dv * ny),
        wb,
    )


def alciatore(va: V2, wa: V3, vb: V2, wb: V3, n: V2, p: Params) -> tuple[V2, V3, V2, V3]:
    nx, ny = n
    vn = (va[0] - vb[0]) * nx + (va[1] - vb[1]) * ny
    if vn <= 0.0:
        return va, wa, vb, wb
    R, m = p.R, p.m
    # Contact-point velocities: ball a's contact is at +R n, ball b's at -R n; w x (R n).
    ca = (va[0] - wa[2] * R * ny, va[1] + wa[2] * R * nx, R * (wa[0] * ny - wa[1] * nx))
    cb = (vb[0] + wb[2] * R * ny, vb[1] - wb[2] * R * nx, -R * (wb[0] * ny - wb[1] * nx))
    rx, ry, rz = ca[0] - cb[0], ca[1] - cb[1], ca[2] - cb[2]
    rn = rx * nx + ry * ny
    tx, ty, tz = rx - rn * nx, ry - rn * ny, rz
    slip = math.sqrt(tx * tx + ty * ty + tz * tz)
    jn = 0.5 * m * (1.0 + p.e_b) * vn
    if slip > 0.0:
        mu = p.throw_a + p.throw_b * math.exp(-p.throw_c * slip)
        jt = min(mu * jn, m * slip / 7.0) / slip
        jx, jy, jz = -jt * tx, -jt * ty, -jt * tz  # friction impulse on ball a
    else:
        jx = jy = jz = 0.0
    # Linear: a gets -jn n + J_t (its vertical part is taken by the cloth), b the opposite.
    ax, ay = (-jn * nx + jx) / m, (-jn * ny + jy) / m
    # Angular: (R n x J_t) / I, the same for both balls.
    k = R / (0.4 * m * R * R)
    dw = (k * ny * jz, -k * nx * jz, k * (nx * jy - ny * jx))
    return (
        (va[0] + ax, va[1] + ay),
        (wa[0] + dw[0], wa[1] + dw[1], wa[2] + dw[2]),
        (vb[0] - ax, vb[1] - ay),
        (wb[0] + dw[0], wb[1] + dw[1], wb[2] + dw[2]),
    )


BALL_BALL_MODELS: dict[str, BallBallModel] = {
    "alciatore": alciatore,
    "frictionless": frictionless,
}

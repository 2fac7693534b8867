"""Ball-cushion impact: Han 2005 (closed form) and Mathavan 2010 (impulse integration).

Both models take the ball's state just before the impact and return it just after, in the
table frame. The ball stays on the cloth: the table takes the vertical part of the cushion's
push (and in Mathavan's model also rubs the ball through its own friction u_s), so the vertical
velocity is zero before and after.

Internally both work in the cushion frame of Mathavan 2010: y points from the ball towards the
cushion (y = -normal, so an approaching ball has v_y > 0), x runs along the cushion
(x = (-n_y, n_x), so x, y, z are right-handed), z is up. The nose touches the ball at I, above
the centre by R sin(theta); the cloth touches it at C, below the centre. Spins are carried as
surface speeds W = R w so that every quantity is a velocity, and impulses are per unit mass.

Slips (the velocity of each contact point of the ball relative to what it touches):
    at I, along the cushion:          x_I = v_x + s W_y - c W_z
    at I, in the vertical plane:      y_I = -s v_y + W_x        (s, c = sin, cos theta)
    at C:                              x_C = v_x - W_y,  y_C = v_y + W_x
Per unit normal impulse p at I, with friction forces f_I (cushion, |f_I| <= f_c) and f_C (cloth,
|f_C| <= u_s N where N = s - c f_Iy is the cloth's normal force), the state changes at

    dv_x = f_Ix + f_Cx            dW_x = 5/2 (f_Iy + f_Cy)        dW_z = -5/2 c f_Ix
    dv_y = -c - s f_Iy + f_Cy     dW_y = 5/2 (s f_Ix - f_Cx)

which are Mathavan's impulse equations with docs/physics.md's correction 6 (phi' from the
cloth slip, atan2 everywhere). From them each slip moves linearly with the forces; the
Mathavan solver uses that to decide when a contact sticks (the force needed to hold its slip at
zero fits inside its friction cone) and which way a slip starting from zero will grow, so the
directions never chatter.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from physics.params import Params

Vec2 = tuple[float, float]
Vec3 = tuple[float, float, float]
#: (v, w, normal, params, sin_theta[, work]) -> (v, w). `work`, when given, is a one-element
#: list to which the model adds the integration steps it took (the engine's budget meters them).
CushionModel = Callable[..., tuple[Vec2, Vec3]]

#: A slip below this fraction of the ball's speed scale counts as zero (a stuck contact). The
#: velocity error this allows is of the same relative size, micrometres over a table length.
_ZERO_SLIP = 1e-12

#: A slip below this fraction of the speed scale is set to zero outright (sticks or turns):
#: getting there by steps would take many, for a velocity change of this relative size.
_SNAP_SLIP = 1e-4

#: A step that would carry a slip to zero stops this fraction of the way: the last
#: Runge-Kutta stage then still sees the slip's direction, not the rounding noise of a zero.
_LAND = 0.999

#: A step times the rate at which friction can change a slip, over the slip, stays below this
#: (Coulomb friction is stiff where a slip is small; Runge-Kutta 4 is stable up to 2.8).
_STIFF = 1.0

#: The most a step may turn the direction of a sliding slip (radians).
_TURN = 0.2

#: Steps (beyond 10 per p.mathavan_steps, several times what an impact needs) after which an
#: impact that has not ended is handed to the closed form (han).
_MAX_STEPS = 1_000


def _leaving(v: Vec2, normal: Vec2) -> bool:
    """True for a ball not moving into the cushion: no impact."""
    return v[0] * normal[0] + v[1] * normal[1] >= 0.0


def _to_cushion(v: Vec2, w: Vec3, normal: Vec2, R: float) -> tuple[float, ...]:
    """(v_x, v_y, W_x, W_y, W_z) in the cushion frame; W = R w."""
    nx, ny = normal
    return (
        -ny * v[0] + nx * v[1],
        -(nx * v[0] + ny * v[1]),
        R * (-ny * w[0] + nx * w[1]),
        -R * (nx * w[0] + ny * w[1]),
        R * w[2],
    )


def _to_table(
    vx: float, vy: float, Wx: float, Wy: float, Wz: float, normal: Vec2, R: float
) -> tuple[Vec2, Vec3]:
    nx, ny = normal
    return (
        (-ny * vx - nx * vy, nx * vx - ny * vy),
        ((-ny * Wx - nx * Wy) / R, (nx * Wx - ny * Wy) / R, Wz / R),
    )


def han(
    v: Vec2, w: Vec3, normal: Vec2, p: Params, sin_theta: float, work: list[int] | None = None
) -> tuple[Vec2, Vec3]:
    """Han 2005: one impulse at the nose contact I, in closed form.

    The normal impulse reverses the normal velocity with restitution e_c; the ball is held on
    the cloth, so its normal speed after is exactly e_c times the speed before (Han's free
    ball would keep only 1 - (1 + e_c) cos^2 theta of it; the table takes the vertical part
    here, as in Mathavan 2010, so that the two models agree without friction). The friction
    impulse at I then either stops the slip of I (sticking, when the impulse needed is within
    f_c times the normal impulse) or slides at its Coulomb limit against the slip. The slip it
    acts on is the one left after the normal impulse: with that choice every impact provably
    loses energy (the work of the friction impulse is never positive). The cloth's friction
    during the impact is neglected, as in Han's paper. A ball not moving into the cushion is
    returned unchanged.
    """
    if _leaving(v, normal):
        return v, w
    R, s, c = p.R, sin_theta, math.sqrt(1.0 - sin_theta * sin_theta)
    vx, vy, Wx, Wy, Wz = _to_cushion(v, w, normal, R)
    e = p.e_c
    # Normal impulse per unit mass, along the contact normal: its horizontal part is (1 + e) v_y.
    p_n = (1.0 + e) * vy / c
    vy = -e * vy
    # Slip of I after the normal impulse; its vertical part was raised by s c p_n.
    x_i = vx + s * Wy - c * Wz
    y_i = -s * vy + Wx
    # Impulse that stops the slip (the inverse contact mobility is diag(2/7, 1/(5/2 + s^2))).
    fx = -x_i / 3.5
    fy = -y_i / (2.5 + s * s)
    limit = p.f_c * p_n
    stick = math.hypot(fx, fy)
    if stick > limit:
        slip = math.hypot(x_i, y_i)
        fx = -limit * x_i / slip
        fy = -limit * y_i / slip
    # Friction may press the ball back into the cushion (huge top spin on a slow ball); it is
    # cut to leave the ball at most running along the cushion, as a longer contact would.
    if -s * fy > -vy:
        fx, fy = fx * vy / (s * fy), vy / s
    vx += fx
    vy -= s * fy
    Wx += 2.5 * fy
    Wy += 2.5 * s * fx
    Wz -= 2.5 * c * fx
    return _to_table(vx, vy, Wx, Wy, Wz, normal, R)


class _Impact:
    """The equations of one impact (see `mathavan`): its angle, friction and slip scales."""

    __slots__ = (
        "c",
        "det_both",
        "eps",
        "eps2",
        "grip_c",
        "grip_i",
        "mu_s",
        "mu_w",
        "s",
        "snap2",
    )

    def __init__(self, s: float, c: float, p: Params, scale: float) -> None:
        self.s, self.c = s, c
        self.eps = _ZERO_SLIP * scale
        snap = _SNAP_SLIP * scale
        self.eps2, self.snap2 = self.eps * self.eps, snap * snap
        # How fast each contact's friction can change its slip (the cloth's normal force is ~ s).
        self.grip_i, self.grip_c = 2.5 * p.f_c, 3.5 * p.u_s * s
        self.mu_w, self.mu_s = p.f_c, p.u_s
        # Both contacts stuck: f_Ix = f_Cx = 0 and a 2x2 system for f_Iy, f_Cy, of determinant:
        self.det_both = 3.5 * (2.5 + s * s) - (2.5 - s) ** 2

    def forces(self, x_i: float, y_i: float, x_c: float, y_c: float) -> tuple[float, ...]:
        """The friction forces (f_Ix, f_Iy, f_Cx, f_Cy) per unit normal impulse, given the slips.

        A sliding contact (slip above eps) pulls against its slip at its Coulomb limit. A
        contact whose slip is zero sticks when the force that holds the slip at zero fits in its
        cone (the force is solved for exactly, so a stuck slip stays at zero); otherwise its slip
        grows along its drive (its slip rate without its own friction) and the friction opposes
        that.
        """
        s, c, eps, mu_w, mu_s = self.s, self.c, self.eps, self.mu_w, self.mu_s
        slip_i = math.hypot(x_i, y_i)
        slip_c = math.hypot(x_c, y_c)
        if slip_i > eps:
            fix = -mu_w * x_i / slip_i
            fiy = -mu_w * y_i / slip_i
            fcx, fcy = self._cloth(fix, fiy, x_c, y_c, slip_c)
            return fix, fiy, fcx, fcy
        if slip_c > eps:
            ux, uy = x_c / slip_c, y_c / slip_c
        else:
            # Both contacts at zero slip: both stuck if both forces fit their cones.
            fiy = -c * (3.5 * s + 2.5 - s) / self.det_both
            fcy = c * (2.5 + s * s + (2.5 - s) * s) / self.det_both
            if abs(fiy) <= mu_w and abs(fcy) <= mu_s * (s - c * fiy):
                return 0.0, fiy, 0.0, fcy
            ux, uy = 0.0, -1.0  # the cloth slips the way the normal impulse drives it
        # I stuck, C sliding along (ux, uy): f_C = -u_s N u with N = s - c f_Iy, and holding
        # the slip of I at zero gives f_Iy (and f_Ix) in closed form.
        k = mu_s * (2.5 - s)
        fiy = (-s * c + k * s * uy) / (2.5 + s * s + k * c * uy)
        n_c = max(0.0, s - c * fiy)
        fcx = -mu_s * n_c * ux
        fcy = -mu_s * n_c * uy
        fix = -(1.0 - 2.5 * s) * fcx / 3.5
        if math.hypot(fix, fiy) <= mu_w:
            return fix, fiy, fcx, fcy
        # I cannot stick: it slips along its drive (taken with the cloth force at N = s).
        ax = -(1.0 - 2.5 * s) * mu_s * s * ux
        ay = s * c - (2.5 - s) * mu_s * s * uy
        drive = math.hypot(ax, ay) or 1.0
        fix = -mu_w * ax / drive
        fiy = -mu_w * ay / drive
        fcx, fcy = self._cloth(fix, fiy, x_c, y_c, slip_c)
        return fix, fiy, fcx, fcy

    def _cloth(
        self, fix: float, fiy: float, x_c: float, y_c: float, slip_c: float
    ) -> tuple[float, float]:
        """The cloth's friction force, given the cushion's (see `forces`)."""
        s, c, mu_s = self.s, self.c, self.mu_s
        n_c = max(0.0, s - c * fiy)
        if slip_c > self.eps:
            return -mu_s * n_c * x_c / slip_c, -mu_s * n_c * y_c / slip_c
        ax = (1.0 - 2.5 * s) * fix
        ay = -c + (2.5 - s) * fiy
        drive = math.hypot(ax, ay)
        if drive <= 3.5 * mu_s * n_c:
            return -ax / 3.5, -ay / 3.5
        return -mu_s * n_c * ax / drive, -mu_s * n_c * ay / drive

    def rate(self, vx: float, vy: float, Wx: float, Wy: float, Wz: float) -> tuple[float, ...]:
        """d(v_x, v_y, W_x, W_y, W_z, E)/dp: the state's rate per unit normal impulse."""
        s, c, eps, mu_w, mu_s = self.s, self.c, self.eps, self.mu_w, self.mu_s
        x_i = vx + s * Wy - c * Wz
        y_i = -s * vy + Wx
        x_c = vx - Wy
        y_c = vy + Wx
        slip_i = math.hypot(x_i, y_i)
        slip_c = math.hypot(x_c, y_c)
        if slip_i > eps and slip_c > eps:  # both sliding: the common case, inline
            k = mu_w / slip_i
            fix = -k * x_i
            fiy = -k * y_i
            k = mu_s * max(0.0, s - c * fiy) / slip_c
            fcx = -k * x_c
            fcy = -k * y_c
        else:
            fix, fiy, fcx, fcy = self.forces(x_i, y_i, x_c, y_c)
        return (
            fix + fcx,
            -c - s * fiy + fcy,
            2.5 * (fiy + fcy),
            2.5 * (s * fix - fcx),
            -2.5 * c * fix,
            c * vy,
        )

    def rk4(self, y: tuple[float, ...], k1: tuple[float, ...], h: float) -> tuple[float, ...]:
        y0, y1, y2, y3, y4, y5 = y
        a0, a1, a2, a3, a4, a5 = k1
        h2 = 0.5 * h
        b0, b1, b2, b3, b4, b5 = self.rate(
            y0 + h2 * a0, y1 + h2 * a1, y2 + h2 * a2, y3 + h2 * a3, y4 + h2 * a4
        )
        c0, c1, c2, c3, c4, c5 = self.rate(
            y0 + h2 * b0, y1 + h2 * b1, y2 + h2 * b2, y3 + h2 * b3, y4 + h2 * b4
        )
        d0, d1, d2, d3, d4, d5 = self.rate(
            y0 + h * c0, y1 + h * c1, y2 + h * c2, y3 + h * c3, y4 + h * c4
        )
        h6 = h / 6.0
        return (
            y0 + h6 * (a0 + 2.0 * (b0 + c0) + d0),
            y1 + h6 * (a1 + 2.0 * (b1 + c1) + d1),
            y2 + h6 * (a2 + 2.0 * (b2 + c2) + d2),
            y3 + h6 * (a3 + 2.0 * (b3 + c3) + d3),
            y4 + h6 * (a4 + 2.0 * (b4 + c4) + d4),
            y5 + h6 * (a5 + 2.0 * (b5 + c5) + d5),
        )

    def slips(self, y: tuple[float, ...]) -> tuple[float, float, float, float]:
        s, c = self.s, self.c
        return y[0] + s * y[3] - c * y[4], -s * y[1] + y[2], y[0] - y[3], y[1] + y[2]

    def step_limit(self, y: tuple[float, ...], d: tuple[float, ...]) -> tuple[float, int]:
        """The largest step the slips allow, and a contact (0: I, 1: C) to set to zero first.

        A step stops just short of where a slip closing on zero at its present rate would
        reach it (_LAND), turns a sliding slip's direction by at most _TURN radians, and keeps
        the step times the rate at which friction changes a slip, over the slip, below _STIFF
        (Coulomb friction is stiff where a slip is small). A slip closing on zero that is
        already too small to matter is set to zero rather than followed round its last turns.
        """
        s, c = self.s, self.c
        y0, y1, y2, y3, y4 = y[0], y[1], y[2], y[3], y[4]
        d0, d1, d2, d3, d4 = d[0], d[1], d[2], d[3], d[4]
        best = math.inf
        best = self._limit(
            best, y0 + s * y3 - c * y4, y2 - s * y1, d0 + s * d3 - c * d4, d2 - s * d1, self.grip_i
        )
        if best < 0.0:
            return 0.0, 0
        best = self._limit(best, y0 - y3, y1 + y2, d0 - d3, d1 + d2, self.grip_c)
        if best < 0.0:
            return 0.0, 1
        return best, -1

    def _limit(self, best: float, sx: float, sy: float, dx: float, dy: float, grip: float) -> float:
        """`step_limit` for one contact, whose slip (sx, sy) changes at (dx, dy) per unit
        impulse and whose friction can change it at `grip`: `best` lowered to what it allows,
        or -1 where the slip is to be set to zero instead. (A method called once per contact,
        not a loop over a tuple of the two: the compiled kernel then keeps them in C doubles.)
        """
        size = sx * sx + sy * sy
        if size <= self.eps2:
            return best
        closing = -(sx * dx + sy * dy)
        if closing > 0.0:
            if size < self.snap2 and grip > 0.0:
                return -1.0
            if _LAND * size < best * closing:
                best = _LAND * size / closing
        turning = abs(sx * dy - sy * dx)
        if _TURN * size < best * turning:
            best = _TURN * size / turning
        if grip > 0.0 and _STIFF * math.sqrt(size) < best * grip:
            best = _STIFF * math.sqrt(size) / grip
        return best

    def zero_slip(self, y: tuple[float, ...], contact: int) -> tuple[float, ...]:
        """Cancel the slip of a contact that has (all but) reached zero, with the impulse that
        holds it there: a correction of the size of the slip left."""
        s, c = self.s, self.c
        x_i, y_i, x_c, y_c = self.slips(y)
        if contact == 0:
            fix, fiy, fcx, fcy = -x_i / 3.5, -y_i / (2.5 + s * s), 0.0, 0.0
        else:
            fix, fiy, fcx, fcy = 0.0, 0.0, -x_c / 3.5, -y_c / 3.5
        return (
            y[0] + fix + fcx,
            y[1] - s * fiy + fcy,
            y[2] + 2.5 * (fiy + fcy),
            y[3] + 2.5 * (s * fix - fcx),
            y[4] - 2.5 * c * fix,
            y[5],
        )


def mathavan(
    v: Vec2, w: Vec3, normal: Vec2, p: Params, sin_theta: float, work: list[int] | None = None
) -> tuple[Vec2, Vec3]:
    """Mathavan 2010: integrate the impact over the normal impulse at I (see the module doc).

    The impact ends when the work of the normal force has given back e_c^2 of what compression took
    (docs/physics.md, correction 7: with E the energy absorbed so far, E rises while v_y > 0 and
    restitution ends when E <= (1 - e_c^2) E_max; E_max is the value at v_y = 0). Compression and
    restitution are one smooth integration, so only E_max and the end need locating: both are found
    on the cubic Hermite interpolant of the step they fall in, as accurate as the step itself.
    The integrator is the classical 4th-order Runge-Kutta (explicit Euler, where the model started,
    is 1st order) with p.mathavan_steps steps over the frictionless compression impulse, each step
    shortened where the slips demand it: to land where a slip closing on zero reaches it, to turn a
    slip's direction by at most _TURN, and to keep Coulomb friction's stiffness near a small slip
    within Runge-Kutta's stable range. A slip closing on zero within _SNAP_SLIP of
    the speed scale is set exactly to zero (a correction impulse of that size), so that the
    contact sticks or turns without chatter. A ball not moving into the cushion is returned
    unchanged; one that friction wedges into it (the normal velocity stops falling during
    compression, possible only with friction far beyond real cushions) gets Han's result.
    Cost: about 10-15 steps of 5 force evaluations for a rolling ball at the default 4 steps;
    rebound velocity within about 1e-4 of the incoming speed of a converged result. Heavy spin
    on a steep nose can take a thousand steps (a few ms); the steps taken are added to
    `work[0]` when `work` is given, which is how the engine's budget sees them.
    """
    if _leaving(v, normal):
        return v, w
    R, s, c = p.R, sin_theta, math.sqrt(1.0 - sin_theta * sin_theta)
    vx, vy, Wx, Wy, Wz = _to_cushion(v, w, normal, R)
    impact = _Impact(s, c, p, abs(vx) + vy + abs(Wx) + abs(Wy) + abs(Wz))
    h = vy / (c * max(1, p.mathavan_steps))
    y = (vx, vy, Wx, Wy, Wz, 0.0)
    d = impact.rate(y[0], y[1], y[2], y[3], y[4])
    target = -math.inf
    taken = 0
    for taken in range(1, _MAX_STEPS + 10 * p.mathavan_steps + 1):
        if target == -math.inf and d[1] >= 0.0:
            break  # friction wedges the ball: the compression cannot end
        step, contact = impact.step_limit(y, d)
        if contact >= 0:
            y = impact.zero_slip(y, contact)
            d = impact.rate(y[0], y[1], y[2], y[3], y[4])
            continue
        step = min(h, step)
        y1 = impact.rk4(y, d, step)
        d1 = impact.rate(y1[0], y1[1], y1[2], y1[3], y1[4])
        lo = 0.0
        if target == -math.inf and y1[1] <= 0.0:
            m0, m1 = d[5] * step, d1[5] * step
            lo = _hermite_peak(y[5], y1[5], m0, m1)
            target = (1.0 - p.e_c * p.e_c) * _hermite(y[5], y1[5], m0, m1, lo)
        if y1[5] <= target:
            m0, m1 = d[5] * step, d1[5] * step
            u = _hermite_root(y[5] - target, y1[5] - target, m0, m1, lo)
            end = impact.rk4(y, d, u * step)
            if work is not None:
                work[0] += taken
            return _to_table(end[0], end[1], end[2], end[3], end[4], normal, R)
        y, d = y1, d1
    # Only for friction far beyond any cloth or rubber (cushion friction near 1 with a steep
    # nose): the impulse integration cannot finish, and the closed form stands in for it.
    if work is not None:
        work[0] += taken
    return han(v, w, normal, p, sin_theta)


def _hermite(f0: float, f1: float, m0: float, m1: float, u: float) -> float:
    """Cubic Hermite interpolant on [0, 1] with end values f and end slopes m (per unit u)."""
    u2 = u * u
    u3 = u2 * u
    return (
        (2.0 * u3 - 3.0 * u2 + 1.0) * f0
        + (u3 - 2.0 * u2 + u) * m0
        + (3.0 * u2 - 2.0 * u3) * f1
        + (u3 - u2) * m1
    )


def _hermite_peak(f0: float, f1: float, m0: float, m1: float) -> float:
    """Where in [0, 1] the interpolant is largest (its slopes are m0 >= 0 >= m1)."""
    a = 6.0 * (f0 - f1) + 3.0 * (m0 + m1)
    b = 6.0 * (f1 - f0) - 4.0 * m0 - 2.0 * m1
    # The ends and where the slope is zero (NaN in place of a root that is not: never in [0, 1]).
    r1 = r2 = math.nan
    disc = b * b - 4.0 * a * m0
    if disc >= 0.0:
        # The stable pair of roots of a u^2 + b u + m0 (a is often all but zero).
        q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
        if q != 0.0:
            r1 = m0 / q
        if a != 0.0:
            r2 = q / a
    best, peak = 0.0, _hermite(f0, f1, m0, m1, 0.0)
    for u in (1.0, r1, r2):  # after 0, in order: the first largest, as max() finds it
        if 0.0 <= u <= 1.0:
            value = _hermite(f0, f1, m0, m1, u)
            if value > peak:
                best, peak = u, value
    return best


def _hermite_root(f0: float, f1: float, m0: float, m1: float, lo: float) -> float:
    """The u in [lo, 1] where a falling interpolant crosses zero (value >= 0 at lo, <= 0 at 1):
    Newton steps kept inside a shrinking bracket."""
    hi = 1.0
    tol = 1e-15 * (abs(f0) + abs(f1))
    u = 0.5 * (lo + hi)
    for _ in range(60):
        g = _hermite(f0, f1, m0, m1, u)
        if abs(g) <= tol:
            break
        if g > 0.0:
            lo = u
        else:
            hi = u
        if hi - lo < 1e-15:
            break
        u2 = u * u
        slope = (6.0 * u2 - 6.0 * u) * (f0 - f1) + (3.0 * u2 - 4.0 * u + 1.0) * m0
        slope += (3.0 * u2 - 2.0 * u) * m1
        newton = u - g / slope if slope < 0.0 else -1.0
        u = newton if lo < newton < hi else 0.5 * (lo + hi)
    return u


#: The cushion models by the names the scene format uses.
CUSHION_MODELS: dict[str, CushionModel] = {"han": han, "mathavan": mathavan}

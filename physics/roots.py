"""The earliest time a polynomial distance function reaches zero.

Collision times are the first root of f(t) = |d(t)|^2 - D^2 (a quartic for two balls on
quadratic paths or a ball and a circle) or of a quadratic (a ball and a straight line). Rather
than trust a closed-form quartic, which loses roots to cancellation exactly in the hard cases
(grazing contacts, near-double roots), the interval is split at the roots of f' (found the same
way, one degree down) into pieces where f is monotone; the first piece on which f falls from
positive to non-positive holds the earliest root, which a safeguarded Newton iteration then
pins down to machine precision. No root is missed and none is reported for a pair that only
moves apart. Pure Python floats: for degree <= 4 this beats numpy's per-call overhead.

Every polynomial is a `Poly`, five coefficients whatever its degree, so that the compiled
kernel holds it in C doubles (physics/roots.pxd) rather than in a tuple of Python floats; a
time that never comes is `math.inf`, a C double too, where None would be a Python object.
"""

from __future__ import annotations

import math

from physics import pymath

_NEWTON_ITERS = 60

#: c0 + c1 t + c2 t^2 + c3 t^3 + c4 t^4 as (c0, c1, c2, c3, c4); a lower degree has zeros
#: at the top. Horner's rule below starts from zero, so those zeros change no bit of a value:
#: 0 t + 0 is 0 for any finite t, and the first coefficient that is not zero is then added to
#: a zero, as it would have been without them.
Poly = tuple[float, float, float, float, float]


def _horner(c: Poly, t: float) -> float:
    """Evaluate c at t."""
    c0, c1, c2, c3, c4 = c
    return ((((0.0 * t + c4) * t + c3) * t + c2) * t + c1) * t + c0


def _derivative(c: Poly) -> Poly:
    return (c[1], 2.0 * c[2], 3.0 * c[3], 4.0 * c[4], 0.0)


def _degree(c: Poly) -> int:
    """The index of the last coefficient that is not zero (0 for a constant, even zero)."""
    if c[4] != 0.0:
        return 4
    if c[3] != 0.0:
        return 3
    if c[2] != 0.0:
        return 2
    if c[1] != 0.0:
        return 1
    return 0


def _quadratic_roots(c0: float, c1: float, c2: float) -> tuple[float, float]:
    """Real roots of c0 + c1 t + c2 t^2, sorted, computed without cancellation; inf in place
    of each root there is not (no caller looks beyond a finite time)."""
    if c2 == 0.0:
        if c1 == 0.0:
            return math.inf, math.inf
        return -c0 / c1, math.inf
    disc = c1 * c1 - 4.0 * c2 * c0
    if disc < 0.0:
        return math.inf, math.inf
    q = -0.5 * (c1 + math.copysign(math.sqrt(disc), c1))
    if q == 0.0:
        return 0.0, math.inf
    r1, r2 = q / c2, c0 / q
    return (r1, r2) if r1 <= r2 else (r2, r1)


def _refine(c: Poly, dc: Poly, lo: float, hi: float) -> float:
    """The root of a polynomial monotone on [lo, hi] with f(lo) > 0 >= f(hi).

    Newton steps that stay inside the bracket, bisection otherwise, so the loop ends even
    where Newton would cycle. Once a Newton step no longer moves the estimate, the estimate is
    nudged up by a few ulps to where f <= 0, so a contact is never resolved before it begins.
    """
    t = hi
    for _ in range(_NEWTON_ITERS):
        f = _horner(c, t)
        if f > 0.0:
            lo = t
        else:
            hi = t
        if hi - lo <= 4e-16 * max(1.0, hi):
            return hi
        d = _horner(dc, t)
        step = t - f / d if d != 0.0 else lo - 1.0
        if not lo <= step <= hi:
            t = 0.5 * (lo + hi)
        elif abs(step - t) <= 4e-16 * max(1.0, t):
            break
        else:
            t = step
    for _ in range(8):
        if _horner(c, t) <= 0.0:
            break
        t = math.nextafter(t, math.inf)
    return min(t, hi)


def _knots(dc: Poly, lo: float, hi: float) -> list[float]:
    """lo, the roots of the derivative `dc` of a polynomial inside (0, hi) and past lo in
    order, and hi: the ends of the pieces of [lo, hi] on which the polynomial is monotone.
    (The callers have the derivative already, for their Newton steps.)"""
    knots = [lo]
    degree = _degree(dc)
    if degree == 1:
        turn = -dc[0] / dc[1]
        if 0.0 < turn < hi and turn > lo:
            knots.append(turn)
    elif degree == 2:
        r1, r2 = _quadratic_roots(dc[0], dc[1], dc[2])
        for turn in (r1, r2):
            if 0.0 < turn < hi and turn > lo:
                knots.append(turn)
    elif degree > 2:
        for turn in all_roots(dc, hi):
            if 0.0 < turn < hi and turn > lo:
                knots.append(turn)
    knots.append(hi)
    return knots


def all_roots(c: Poly, hi: float) -> list[float]:
    """Every root of the polynomial `c` in (0, hi), sorted (by recursion on the degree)."""
    dc = _derivative(c)
    knots = _knots(dc, 0.0, hi)
    roots = []
    f_prev = _horner(c, 0.0)
    for k in range(len(knots) - 1):  # each piece between knots, in order
        a, b = knots[k], knots[k + 1]
        f_b = _horner(c, b)
        if (f_prev > 0.0) != (f_b > 0.0):
            roots.append(_refine(c, dc, a, b) if f_prev > 0.0 else _refine_neg(c, dc, a, b))
        f_prev = f_b
    return roots


def _negated(c: Poly) -> Poly:
    c0, c1, c2, c3, c4 = c
    return (-c0, -c1, -c2, -c3, -c4)


def _refine_neg(c: Poly, dc: Poly, lo: float, hi: float) -> float:
    """As `_refine`, for a polynomial rising through zero on [lo, hi]."""
    return _refine(_negated(c), _negated(dc), lo, hi)


def path_misses(
    px: float, py: float, vx: float, vy: float, ax: float, ay: float, h: float, clearance: float
) -> bool:
    """True when p(t) = p + v t + a t^2 / 2 stays farther than `clearance` from the origin
    for all t in [0, h]: a cheap, conservative test that culls most pairs and circles before
    any polynomial is formed. The parabola never strays from its chord by more than
    |a| h^2 / 8, so the distance from the origin to the chord, less that, bounds it below.
    """
    cx, cy = (vx + 0.5 * ax * h) * h, (vy + 0.5 * ay * h) * h
    chord2 = cx * cx + cy * cy
    s = 0.0
    if chord2 > 0.0:
        s = min(1.0, max(0.0, -(px * cx + py * cy) / chord2))
    return pymath.clears(px + s * cx, py + s * cy, ax, ay, h, clearance)


def first_entry_quadratic(c0: float, c1: float, c2: float, hi: float, skip: float = 0.0) -> float:
    """`first_entry` for a quadratic c0 + c1 t + c2 t^2, in closed form."""
    if skip > hi:
        return math.inf
    if c0 + (c1 + c2 * skip) * skip <= 0.0:
        return skip
    r1, r2 = _quadratic_roots(c0, c1, c2)
    if skip <= r1 <= hi:
        return r1
    if skip <= r2 <= hi:
        return r2
    return math.inf


def first_entry(c: Poly, hi: float, skip: float = 0.0) -> float:
    """The earliest t in [skip, hi] with c(t) <= 0, or inf if f stays positive.

    The caller has already dealt with a contact at the present (touching and approaching).
    `skip` > 0 is for a pair that touches now and is not approaching: it ignores the contact
    at the present and asks whether the two come together again later.
    """
    if skip > hi:
        return math.inf
    if _horner(c, skip) <= 0.0:
        return skip
    dc = _derivative(c)
    knots = _knots(dc, skip, hi)
    for k in range(len(knots) - 1):  # each piece between knots, in order
        a, b = knots[k], knots[k + 1]
        if _horner(c, b) <= 0.0:
            return _refine(c, dc, a, b)
    return math.inf


def first_return(c: Poly, hi: float, depth: float) -> float:
    """For two things in contact now (c(0) ~ 0) and not approaching: the next contact (inf
    if none comes).

    Either they come apart (c rises above zero) and meet again where c falls back to zero,
    or they stay pressed together and a contact is due once c sinks `depth` below where it
    is now (or below zero, if it is above). Float noise at the touching point is neither.
    """
    c0, c1, c2, c3, c4 = c
    floor = min(c0, 0.0) - depth
    dc = _derivative(c)
    knots = _knots(dc, 0.0, hi)
    apart = False
    for k in range(len(knots) - 1):  # each piece between knots, in order
        a, b = knots[k], knots[k + 1]
        f_b = _horner(c, b)
        if apart:
            if f_b <= 0.0:
                return _refine(c, dc, a, b)
        elif f_b > 0.0:
            apart = True
        elif f_b <= floor:
            return _refine((c0 - floor, c1, c2, c3, c4), dc, a, b)
    return math.inf

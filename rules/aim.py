"""Straight-line geometry of aiming: clear paths, ghost balls, and whether a player is snookered.

A cue ball of radius R travelling in a straight line from a to b sweeps a band 2R wide; another
ball blocks the path when its centre comes within 2R of the segment ab. These tests ignore
cushions and spin: they describe the straight shots a player can see, which is what snooker's
definition of "snookered" and the shot pickers both need.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping

from rules.spots import Point


def segment_distance(p: Point, a: Point, b: Point) -> float:
    """Distance from p to the segment ab."""
    ax, ay = a
    dx, dy = b[0] - ax, b[1] - ay
    den = dx * dx + dy * dy
    t = 0.0 if den == 0 else max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / den))
    return math.hypot(p[0] - ax - t * dx, p[1] - ay - t * dy)


def path_clear(
    a: Point, b: Point, balls: Mapping[str, Point], R: float, ignore: Iterable[str] = ()
) -> bool:
    """No ball but those in `ignore` lies within 2R of the segment ab (touching is clear).

    The bot's look-ahead asks this millions of times a game, so a ball outside the segment's
    box grown by 2R, which cannot be that near, is passed over before any distance is taken."""
    skip = set(ignore)
    reach = 2 * R * (1 - 1e-9)
    x0, x1 = min(a[0], b[0]) - reach, max(a[0], b[0]) + reach
    y0, y1 = min(a[1], b[1]) - reach, max(a[1], b[1]) + reach
    for k, q in balls.items():
        near = x0 <= q[0] <= x1 and y0 <= q[1] <= y1
        if near and k not in skip and segment_distance(q, a, b) < reach:
            return False
    return True


def ghost(target: Point, toward: Point, R: float) -> Point:
    """Where the cue ball's centre must be at contact to send `target` straight at `toward`."""
    dx, dy = toward[0] - target[0], toward[1] - target[1]
    d = math.hypot(dx, dy)
    return (target[0] - 2 * R * dx / d, target[1] - 2 * R * dy / d)


def edge_contacts(cue: Point, target: Point, R: float) -> tuple[Point, Point]:
    """Cue-ball centres at contact when the cue ball just grazes either extreme edge of target.

    The cue ball travels along a tangent from its centre to the circle of radius 2R about the
    target; the contact point is where that tangent touches the circle.
    """
    dx, dy = target[0] - cue[0], target[1] - cue[1]
    d = math.hypot(dx, dy)
    r = 2 * R * (1 - 1e-6)
    if d <= r:
        return cue, cue
    along = math.sqrt(d * d - r * r)
    base = math.atan2(dy, dx)
    half = math.asin(r / d)
    return tuple(
        (cue[0] + along * math.cos(base + s * half), cue[1] + along * math.sin(base + s * half))
        for s in (-1.0, 1.0)
    )


def both_edges_clear(
    cue_ball: str, target: str, balls: Mapping[str, Point], R: float, not_blocking: set[str]
) -> bool:
    """The cue ball can hit both extreme edges of `target` in straight lines, unobstructed by
    any ball outside `not_blocking` (the balls on, which do not count as obstructions)."""
    cue = balls[cue_ball]
    ignore = {cue_ball, target, *not_blocking}
    return all(path_clear(cue, c, balls, R, ignore) for c in edge_contacts(cue, balls[target], R))


def snookered(cue_ball: str, balls_on: set[str], balls: Mapping[str, Point], R: float) -> bool:
    """WPBSA: snookered when no ball on can be hit at both extreme edges in a straight line
    free of obstruction by balls not on (a ball on that is not on the table cannot be hit)."""
    return not any(
        both_edges_clear(cue_ball, b, balls, R, balls_on) for b in balls_on if b in balls
    )

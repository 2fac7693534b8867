"""The straight-line geometry the bot plans with: pots it can see, and how likely each is.

A pot is a ghost-ball aim: the cue ball's centre travels to the ghost ball (2R behind the
object ball on the line to the pocket) and the object ball leaves along that line. Its chance
under execution noise is estimated without simulating, from how a heading error grows on its
way: a cue ball that strays by d1·dθ sideways at the object ball turns the contact line by
d1·dθ / (2R cos cut), and the object ball then misses its line at the pocket by d2 times that;
the pot drops when that miss is within the pocket's tolerance (about half the mouth, narrowed
as the ball approaches the mouth at an angle, fitted to the engine's pockets). This estimate
ranks the pots the search simulates and values the position a shot leaves (the look-ahead);
the referee, on simulated shots, decides everything else.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from physics.tables import Pocket
from rules.aim import ghost, path_clear
from rules.bot.noise import Noise
from rules.spots import Point, Table

#: The pocket's tolerance: half the mouth less this share of the ball radius straight down the
#: axis, shrinking as (1 - (angle / limit)^SHAPE) with the angle between the ball's path and
#: the axis, to nothing at the limit (degrees). Fitted to the engine: 535 straight pots from
#: random nine-ball positions, 12 plays each under the tournament noise, cut the squared error
#: of the estimate against the rate seen from 68 to 11.
JAW_SHARE = 0.3
CORNER_LIMIT, SIDE_LIMIT = 90.0, 60.0
SHAPE = 3
#: Thinnest cut planned (cos of the cut angle): thinner cuts leave too little to aim at.
MIN_CUT_COS = 0.2
#: Heading error assumed by the estimate at the least (degrees): even a perfect hand misses a
#: little, so no pot is certain and long pots still rank below short ones.
MIN_HEADING_SD = 0.05


@dataclass(frozen=True, slots=True)
class Pot:
    """One straight pot: the cue ball at `cue` to the `ghost`, then `target` into `pocket`.

    d1, d2: the two straight distances (m). cos_cut: cosine of the cut angle. chance: the
    estimated probability that it drops (see the module docstring).
    """

    target: str
    pocket: str
    cue: Point
    ghost: Point
    d1: float
    d2: float
    cos_cut: float
    chance: float

    @property
    def heading(self) -> float:
        return math.degrees(math.atan2(self.ghost[1] - self.cue[1], self.ghost[0] - self.cue[0]))


def side_pocket(pocket: Pocket) -> bool:
    return pocket.name.startswith("middle")


def pocket_axis(table: Table, pocket: Pocket) -> Point:
    """The unit direction a ball travels when it enters `pocket` straight down its throat."""
    dx = -1.0 if pocket.center[0] < table.width / 2 else 1.0
    if side_pocket(pocket):
        return (dx, 0.0)
    dy = -1.0 if pocket.center[1] < table.length / 2 else 1.0
    return (dx / math.sqrt(2), dy / math.sqrt(2))


def tolerance(table: Table, pocket: Pocket, direction: Point) -> float:
    """How far (m) the object ball's centre may stray sideways from the pocket's centre and
    still drop, for a ball travelling along the unit `direction`; 0 when it cannot drop."""
    axis = pocket_axis(table, pocket)
    cos_in = direction[0] * axis[0] + direction[1] * axis[1]
    angle = math.degrees(math.acos(max(-1.0, min(1.0, cos_in))))
    limit = SIDE_LIMIT if side_pocket(pocket) else CORNER_LIMIT
    if angle >= limit:
        return 0.0
    mouth = table.spec.side_mouth if side_pocket(pocket) else table.spec.corner_mouth
    return (mouth / 2 - JAW_SHARE * table.R) * (1 - (angle / limit) ** SHAPE)


def chance(tol: float, d1: float, d2: float, cos_cut: float, R: float, noise: Noise) -> float:
    """Estimated pot probability: the object ball's sideways miss at the pocket is Gaussian
    with sd d2 * d1 * dθ / (2R cos cut), and must stay within `tol`."""
    if tol <= 0.0:
        return 0.0
    sd_heading = math.radians(max(noise.heading, MIN_HEADING_SD))
    sd_miss = d2 * max(d1, 2 * R) * sd_heading / (2 * R * cos_cut)
    return math.erf(tol / (math.sqrt(2) * sd_miss))


def pots(
    table: Table,
    cue: Point,
    balls: Mapping[str, Point],
    targets: frozenset[str],
    noise: Noise,
) -> list[Pot]:
    """Every straight pot of one of `targets` whose two paths are clear, likeliest first (ties
    by target and pocket name, so the order is fixed)."""
    R = table.R
    found = []
    for t in sorted(targets):
        tp = balls[t]
        for pocket in table.pockets:
            mouth = pocket.center
            d2 = math.dist(tp, mouth)
            out = ((mouth[0] - tp[0]) / d2, (mouth[1] - tp[1]) / d2)
            tol = tolerance(table, pocket, out)
            if tol <= 0.0:
                continue
            g = ghost(tp, mouth, R)
            d1 = math.dist(cue, g)
            if d1 < 1e-6:
                continue
            cos_cut = ((g[0] - cue[0]) * out[0] + (g[1] - cue[1]) * out[1]) / d1
            if cos_cut < MIN_CUT_COS:
                continue
            if not path_clear(cue, g, balls, R, ignore={"cue", t}):
                continue
            if not path_clear(tp, mouth, balls, R, ignore={"cue", t}):
                continue
            p = chance(tol, d1, d2, cos_cut, R, noise)
            found.append(Pot(t, pocket.name, cue, g, d1, d2, cos_cut, p))
    return sorted(found, key=lambda a: (-a.chance, a.target, a.pocket))


def cushion_bounces(table: Table, start: Point, end: Point) -> list[Point]:
    """Where a ball's centre, travelling from `start`, meets each of the four cushion lines
    (R inside the rails) on a one-cushion path that ends at `end`: mirror `end` in the line
    and intersect. Bounces within a ball of a pocket are left out (the ball would drop)."""
    R = table.R
    found = []
    for axis, line in ((0, R), (0, table.width - R), (1, R), (1, table.length - R)):
        image = list(end)
        image[axis] = 2 * line - end[axis]
        span = image[axis] - start[axis]
        if abs(span) < 1e-9:
            continue
        f = (line - start[axis]) / span
        if not 0.0 < f < 1.0:
            continue
        at = (start[0] + f * (image[0] - start[0]), start[1] + f * (image[1] - start[1]))
        if all(math.dist(at, p.center) > p.radius + 2 * R for p in table.pockets):
            found.append(at)
    return found

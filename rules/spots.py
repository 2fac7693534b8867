"""Where balls may go: the marked spots and regions of each table, and free-place searches.

The referees never invent positions: a respotted ball goes on a named spot or on a line from it,
a placed cue ball must lie in a named region, and every candidate position is checked against
the table edges and every other ball. All distances are centre to centre; two balls are apart
when their centres are at least 2R plus `CLEARANCE` apart, so that a respotted ball frozen to a
neighbour never overlaps it by a rounding error.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Literal

from physics.params import CAROM, POOL, SNOOKER
from physics.tables import (
    NINEBALL,
    NINEBALL_7FT,
    NINEBALL_8FT,
    SNOOKER_TABLE,
    THREE_CUSHION,
    Pocket,
    TableSpec,
)

Point = tuple[float, float]
#: A pool table's size in feet.
Size = Literal[7, 8, 9]

#: Gap (m) kept between a placed ball and its neighbours: a micrometre, far below what a player
#: could see, far above floating-point noise.
CLEARANCE = 1e-6


@dataclass(frozen=True, slots=True)
class Table:
    """A preset table with the ball radius played on it and its marked spots (m)."""

    preset: str
    spec: TableSpec
    R: float
    pockets: tuple[Pocket, ...] = ()

    @property
    def width(self) -> float:
        return self.spec.w

    @property
    def length(self) -> float:
        return self.spec.l

    @property
    def head_string(self) -> float:
        """Pool's head string (the kitchen's edge): a quarter of the length from the bottom."""
        return self.length / 4

    @property
    def head_spot(self) -> Point:
        """Pool's head spot (the carom table's too): centre of the head quarter."""
        return (self.width / 2, self.length / 4)

    @property
    def foot_spot(self) -> Point:
        """Pool's foot spot (the carom table's top spot): centre of the foot quarter."""
        return (self.width / 2, 3 * self.length / 4)


def _table(preset: str, spec: TableSpec, R: float) -> Table:
    return Table(preset, spec, R, spec.geometry().pockets)


POOL_TABLE = _table("nineball", NINEBALL, POOL.R)
#: The pool tables by size in feet (the playing surface's nominal length); 9 ft is the
#: standard table the leaderboards rank. Every spot, line and region of a pool table is a
#: fraction of its length and width, so each size has its own, scaled with the bed.
POOL_SIZES: dict[int, Table] = {
    7: _table("nineball_7ft", NINEBALL_7FT, POOL.R),
    8: _table("nineball_8ft", NINEBALL_8FT, POOL.R),
    9: POOL_TABLE,
}
STANDARD_SIZE = 9
SNOOKER = _table("snooker", SNOOKER_TABLE, SNOOKER.R)
CAROM_TABLE = _table("three_cushion", THREE_CUSHION, CAROM.R)

#: Snooker markings (WPBSA, 12 ft table): baulk line 737 mm from the baulk (bottom) cushion,
#: D of radius 292 mm, black spot 324 mm from the top cushion, pink midway between the centre
#: spot and the top cushion. Seen from the baulk end, green is left, yellow right.
BAULK_Y = 0.737
D_RADIUS = 0.292
SNOOKER_SPOTS: dict[str, Point] = {
    "yellow": (SNOOKER.width / 2 + D_RADIUS, BAULK_Y),
    "green": (SNOOKER.width / 2 - D_RADIUS, BAULK_Y),
    "brown": (SNOOKER.width / 2, BAULK_Y),
    "blue": (SNOOKER.width / 2, SNOOKER.length / 2),
    "pink": (SNOOKER.width / 2, 3 * SNOOKER.length / 4),
    "black": (SNOOKER.width / 2, SNOOKER.length - 0.324),
}


def on_table(p: Point, table: Table) -> bool:
    """The ball lies wholly on the playing surface (touching a cushion nose is allowed) and
    outside every pocket's capture circle (where the engine would count it as fallen)."""
    x, y = p
    R = table.R
    inside = R <= x <= table.width - R and R <= y <= table.length - R
    return inside and all(
        math.hypot(x - k.center[0], y - k.center[1]) >= k.radius + CLEARANCE for k in table.pockets
    )


def is_free(p: Point, balls: Mapping[str, Point], R: float, ignore: str | None = None) -> bool:
    """No ball other than `ignore` is closer than 2R + CLEARANCE to p."""
    limit = 2 * R + CLEARANCE
    return all(
        math.hypot(p[0] - q[0], p[1] - q[1]) >= limit for k, q in balls.items() if k != ignore
    )


def in_region(p: Point, region: str, table: Table) -> bool:
    """Whether a ball at p lies in a ball-in-hand region.

    anywhere: on the table. kitchen: on or behind pool's head string (y <= l/4; the cue ball
    may sit on the head spot for the break). D: inside snooker's D, the line included.
    """
    if not on_table(p, table):
        return False
    if region == "anywhere":
        return True
    if region == "kitchen":
        return p[1] <= table.head_string
    if region == "D":
        return p[1] <= BAULK_Y and math.hypot(p[0] - table.width / 2, p[1] - BAULK_Y) <= D_RADIUS
    raise ValueError(f"unknown region {region!r}")


def _region_box(region: str, table: Table) -> tuple[float, float, float, float]:
    """x0, x1, y0, y1 of a rectangle holding every point of a ball-in-hand region."""
    R = table.R
    if region == "D":
        cx = table.width / 2
        return cx - D_RADIUS, cx + D_RADIUS, BAULK_Y - D_RADIUS, BAULK_Y
    top = table.head_string if region == "kitchen" else table.length - R
    return R, table.width - R, R, top


def free_place(region: str, balls: Mapping[str, Point], table: Table) -> Point | None:
    """A point of the ball-in-hand `region` where a ball may be placed among `balls`: the
    first free one of a coarse grid over the table (a few dozen points, tried first), else of
    a grid of R/2 steps over the region, so that a crowded region (a set-up position's balls
    heaped in the D) still finds a gap a ball fits in; None when neither grid has one."""
    coarse = [
        (table.width * i / 8, table.length * j / 32) for j in range(1, 32) for i in range(1, 8)
    ]
    x0, x1, y0, y1 = _region_box(region, table)
    step = table.R / 2
    nx, ny = int((x1 - x0) / step) + 1, int((y1 - y0) / step) + 1
    fine = ((x0 + i * step, y0 + j * step) for j in range(ny) for i in range(nx))
    for p in (*coarse, *fine):
        if in_region(p, region, table) and is_free(p, balls, table.R):
            return p
    return None


def nearest_free_on_ray(
    start: Point, direction: Point, balls: Mapping[str, Point], table: Table
) -> Point | None:
    """The free point closest to `start` on the ray start + t * direction (t >= 0), or None.

    Exact, not a scan: the free part of the ray is a union of intervals, each beginning at
    t = 0 or where the ray leaves a neighbour's exclusion disc, so the answer is the smallest
    such candidate that is free and on the table (a ball frozen to the one in its way, as the
    rules ask).
    """
    dx, dy = direction
    norm = math.hypot(dx, dy)
    dx, dy = dx / norm, dy / norm
    limit = 2 * table.R + CLEARANCE
    candidates = [0.0]
    for q in balls.values():
        ox, oy = start[0] - q[0], start[1] - q[1]
        b = ox * dx + oy * dy
        disc = b * b - (ox * ox + oy * oy - limit * limit)
        if disc > 0:
            candidates.append(-b + math.sqrt(disc) + 1e-12)
    for t in sorted(c for c in candidates if c >= 0):
        p = (start[0] + t * dx, start[1] + t * dy)
        if on_table(p, table) and is_free(p, balls, table.R):
            return p
    return None


def place_near(
    spot: Point, directions: tuple[Point, ...], balls: Mapping[str, Point], table: Table
) -> Point:
    """The first free point found on the rays from `spot`, tried in order.

    Raises RuntimeError when every ray is blocked: a table that full cannot arise in play.
    """
    for d in directions:
        p = nearest_free_on_ray(spot, d, balls, table)
        if p is not None:
            return p
    raise RuntimeError(f"no free place near {spot}")

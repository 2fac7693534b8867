"""Table geometry: the playing surface, cushion segments, rounded jaws and pockets.

Coordinates: origin at the corner of the playing surface where the cushion noses meet, x across
the width `w`, y along the length `l`. The cushion noses are the lines x=0, x=w, y=0, y=l, broken
at the pocket mouths. Each rail ends in a jaw: a circle of radius `jaw_radius` tangent to the nose
line at the end of the rail, so a ball glancing off the end of a rail turns smoothly into the
pocket. A ball is captured when its centre enters a pocket's capture circle, which sits `depth`
behind the middle of the mouth.

Pocket sizes are the usual ones of a WPA-spec nine-ball table and of a snooker table; pooltool's
published defaults were used as a cross-check for the pool values.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

from physics.params import CAROM, POOL, SNOOKER, Params


@dataclass(frozen=True, slots=True)
class Segment:
    """A straight cushion nose from p1 to p2, with the unit normal pointing into the table."""

    name: str
    p1: tuple[float, float]
    p2: tuple[float, float]
    normal: tuple[float, float]


@dataclass(frozen=True, slots=True)
class Jaw:
    """The rounded end of a rail at a pocket mouth: a circle the ball can hit from outside.

    normal: the inward normal of the rail it ends; the circle touches that rail's nose line at
    center + radius * normal, where the straight nose stops.
    """

    name: str
    pocket: str
    center: tuple[float, float]
    radius: float
    normal: tuple[float, float]


@dataclass(frozen=True, slots=True)
class Pocket:
    """A pocket's capture circle: a ball whose centre enters it drops."""

    name: str
    center: tuple[float, float]
    radius: float


@dataclass(frozen=True, slots=True)
class TableSpec:
    """The numbers that define a table; `geometry()` turns them into segments, jaws, pockets.

    corner_mouth / side_mouth: distance between the jaw tips of a corner / side pocket (m).
    *_depth: how far behind the middle of the mouth the capture circle's centre sits (m).
    *_radius: capture circle radius (m). jaw_radius: radius of the rounded rail ends (m).
    cushion_height: height of the cushion nose's contact point above the cloth (m); sets the
    contact angle of both cushion models: sin(theta) = cushion_height / R - 1.
    """

    name: str
    w: float
    l: float
    pockets: bool
    cushion_height: float
    corner_mouth: float = 0.118
    corner_depth: float = 0.0398
    corner_radius: float = 0.062
    side_mouth: float = 0.137
    side_depth: float = 0.00437
    side_radius: float = 0.0645
    jaw_radius: float = 0.02095

    def geometry(self) -> Geometry:
        """The table's pieces (the same object for the same numbers: a table is built once
        per process, not once per scene)."""
        return _geometry(self)


@dataclass(frozen=True, slots=True)
class Geometry:
    """Everything the collision detector needs about a table, precomputed once per scene."""

    spec: TableSpec
    segments: tuple[Segment, ...]
    jaws: tuple[Jaw, ...]
    pockets: tuple[Pocket, ...]

    def __reduce__(self) -> tuple:
        """Pickled as its numbers alone (a scene sent to a batch worker carries no pieces):
        the pieces follow from them."""
        return _geometry, (self.spec,)


def _corner(name: str, corner: tuple[float, float], inward: tuple[float, float], spec: TableSpec):
    """Rails, jaws and capture circle of the corner pocket at `corner`.

    `inward` is (+-1, +-1): the directions along x and y that point into the table.
    Returns the x-rail and y-rail end points (where the straight noses stop) and the pieces.
    """
    cx, cy = corner
    sx, sy = inward
    c = spec.corner_mouth / math.sqrt(2.0)
    r = spec.jaw_radius
    end_x = (cx + sx * c, cy)  # end of the rail that runs along x (the short rail)
    end_y = (cx, cy + sy * c)  # end of the rail that runs along y (the long rail)
    jaws = (
        Jaw(f"{name}_x", name, (end_x[0], cy - sy * r), r, (0.0, float(sy))),
        Jaw(f"{name}_y", name, (cx - sx * r, end_y[1]), r, (float(sx), 0.0)),
    )
    mid = (cx + sx * c / 2, cy + sy * c / 2)
    d = spec.corner_depth / math.sqrt(2.0)
    pocket = Pocket(name, (mid[0] - sx * d, mid[1] - sy * d), spec.corner_radius)
    return end_x, end_y, jaws, pocket


def _side(name: str, x: float, inward: float, spec: TableSpec):
    """Jaws and capture circle of a side pocket in the long rail x = `x` at mid length."""
    ym = spec.l / 2
    h = spec.side_mouth / 2
    r = spec.jaw_radius
    jaws = (
        Jaw(f"{name}_low", name, (x - inward * r, ym - h), r, (inward, 0.0)),
        Jaw(f"{name}_high", name, (x - inward * r, ym + h), r, (inward, 0.0)),
    )
    pocket = Pocket(name, (x - inward * spec.side_depth, ym), spec.side_radius)
    return (ym - h, ym + h), jaws, pocket


@functools.lru_cache(maxsize=64)
def _geometry(spec: TableSpec) -> Geometry:
    return build_geometry(spec)


def build_geometry(spec: TableSpec) -> Geometry:
    w, l = spec.w, spec.l
    if not spec.pockets:
        segments = (
            Segment("bottom", (0.0, 0.0), (w, 0.0), (0.0, 1.0)),
            Segment("top", (w, l), (0.0, l), (0.0, -1.0)),
            Segment("left", (0.0, l), (0.0, 0.0), (1.0, 0.0)),
            Segment("right", (w, 0.0), (w, l), (-1.0, 0.0)),
        )
        return Geometry(spec, segments, (), ())
    bl_x, bl_y, bl_j, bl_p = _corner("bottom_left", (0.0, 0.0), (1, 1), spec)
    br_x, br_y, br_j, br_p = _corner("bottom_right", (w, 0.0), (-1, 1), spec)
    tl_x, tl_y, tl_j, tl_p = _corner("top_left", (0.0, l), (1, -1), spec)
    tr_x, tr_y, tr_j, tr_p = _corner("top_right", (w, l), (-1, -1), spec)
    (ml_lo, ml_hi), ml_j, ml_p = _side("middle_left", 0.0, 1.0, spec)
    (mr_lo, mr_hi), mr_j, mr_p = _side("middle_right", w, -1.0, spec)
    segments = (
        Segment("bottom", bl_x, br_x, (0.0, 1.0)),
        Segment("top", tr_x, tl_x, (0.0, -1.0)),
        Segment("left_bottom", (0.0, ml_lo), bl_y, (1.0, 0.0)),
        Segment("left_top", tl_y, (0.0, ml_hi), (1.0, 0.0)),
        Segment("right_bottom", br_y, (w, mr_lo), (-1.0, 0.0)),
        Segment("right_top", (w, mr_hi), tr_y, (-1.0, 0.0)),
    )
    jaws = bl_j + br_j + ml_j + mr_j + tl_j + tr_j
    pockets = (bl_p, br_p, ml_p, mr_p, tl_p, tr_p)
    return Geometry(spec, segments, jaws, pockets)


def mouth(g: Geometry, pocket: Pocket, R: float) -> tuple[tuple[float, float], ...]:
    """The polygon of ball-centre positions past the cushion lines that lead into `pocket`.

    Its corners: where the first rail's nose line, moved a radius into the table, ends (the top
    of the jaw circle grown by R), that jaw's centre, the capture circle's centre, the second
    jaw's centre, and the second rail's end. `check_table` makes each jaw circle grown by R
    overlap the capture circle, so every edge of the polygon lies inside a rail, a grown jaw or
    the capture circle: a ball centre in the mouth (not in a jaw or the capture circle) is
    inside this polygon, and one inside it is fenced in by the rails, the jaws and the pocket.
    """
    first, second = (j for j in g.jaws if j.pocket == pocket.name)

    def rail_end(j: Jaw) -> tuple[float, float]:
        k = j.radius + R
        return (j.center[0] + k * j.normal[0], j.center[1] + k * j.normal[1])

    return (rail_end(first), first.center, pocket.center, second.center, rail_end(second))


def inside(polygon: tuple[tuple[float, float], ...], x: float, y: float) -> bool:
    """True when (x, y) is inside the simple polygon (crossing number; an edge point may go
    either way)."""
    crossings = False
    x1, y1 = polygon[-1]
    for x2, y2 in polygon:
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            crossings = not crossings
        x1, y1 = x2, y2
    return crossings


def check_table(spec: TableSpec, R: float) -> None:
    """Raise ValueError naming the first thing that makes `spec` unplayable with balls of radius R.

    - The cushion nose touches the ball between its equator and 0.8 R above it
      (cushion_height in [R, 1.8 R]): below the equator a cushion would lift the ball, and near
      the top the cushion models' contact angle degenerates (cos(theta) -> 0). Real tables are at
      1.2-1.4 R.
    - A ball fits between the jaw tips (mouths wider than 2R), and every straight rail keeps at
      least a ball's radius of length between its pockets.
    - Each pocket closes its mouth: its capture circle overlaps both of its jaw circles grown by
      R, so a ball that passes the cushion line in a mouth either meets a jaw or drops; nothing
      lets it leave the table (see `mouth`).
    """
    if not R <= spec.cushion_height <= 1.8 * R:
        raise ValueError(f"table.cushion_height must be between R and 1.8 R ({R} m balls)")
    if not spec.pockets:
        return
    for name in ("corner_mouth", "side_mouth"):
        if getattr(spec, name) <= 2.0 * R:
            raise ValueError(f"table.{name} must be wider than a ball (2 R = {2 * R} m)")
    corner = spec.corner_mouth / math.sqrt(2.0)
    if min(spec.w - 2.0 * corner, spec.l / 2.0 - spec.side_mouth / 2.0 - corner) < R:
        raise ValueError("table: the pockets leave no room for the rails between them")
    g = spec.geometry()
    for jaw in g.jaws:
        pocket = next(p for p in g.pockets if p.name == jaw.pocket)
        reach = math.dist(jaw.center, pocket.center)
        if not reach < pocket.radius + jaw.radius + R:
            raise ValueError(
                f"table: pocket {pocket.name} does not close its mouth (its capture circle "
                f"misses jaw {jaw.name}); enlarge its radius or reduce its depth"
            )


@functools.lru_cache(maxsize=64)
def table_problem(spec: TableSpec, R: float) -> str | None:
    """What `check_table` finds wrong with `spec` for balls of radius R, or None; remembered,
    since every scene on a preset table would check the same table again."""
    try:
        check_table(spec, R)
    except ValueError as exc:
        return str(exc)
    return None


def _clear_of(disks: list[tuple[float, float, float]], box: tuple[float, ...]) -> bool:
    x0, y0, x1, y1 = box
    return all(
        math.hypot(max(x0 - cx, 0.0, cx - x1), max(y0 - cy, 0.0, cy - y1)) >= r
        for cx, cy, r in disks
    )


@functools.lru_cache(maxsize=64)
def clear_interior(spec: TableSpec, R: float, tol: float) -> tuple[float, float, float, float]:
    """A rectangle (x0, y0, x1, y1) of the cloth where every centre is a valid rest: inside
    the cushion lines' margin of R - tol, and clear of every pocket's capture circle and of
    every jaw grown by R - tol. Most balls lie in it, and `position_problem` then needs no
    distance to a pocket or a jaw. It is the cloth rectangle shrunk by the least margin (found
    by bisection, then rounded inwards) that clears them all; empty (x0 > x1) if none does.
    Keyed by the spec, not its geometry, whose hash costs more than the distances it saves."""
    g = spec.geometry()
    w, l = spec.w, spec.l
    disks = [(p.center[0], p.center[1], p.radius) for p in g.pockets]
    disks += [(j.center[0], j.center[1], j.radius + R - tol) for j in g.jaws]
    box = lambda m: (m, m, w - m, l - m)  # noqa: E731
    lo, hi = R - tol, min(w, l) / 2
    if _clear_of(disks, box(lo)):
        return box(lo)
    if not _clear_of(disks, box(hi)):
        return (1.0, 1.0, 0.0, 0.0)
    for _ in range(60):
        mid = (lo + hi) / 2
        lo, hi = (lo, mid) if _clear_of(disks, box(mid)) else (mid, hi)
    return box(hi + 1e-9)


def position_problem(g: Geometry, R: float, x: float, y: float, tol: float) -> str | None:
    """Why a ball of radius R cannot rest with its centre at (x, y); None when it can.

    It can on the cloth (at least R - tol from every cushion nose line) or in a pocket's mouth
    (inside the `mouth` polygon), but never inside a pocket's capture circle nor pressed more
    than tol into a jaw. This is exactly where the engine leaves a ball at rest, so a shot's
    final positions are always a valid start for the next.
    """
    x0, y0, x1, y1 = clear_interior(g.spec, R, tol)
    if x0 <= x <= x1 and y0 <= y <= y1:
        return None
    return edge_problem(g, R, x, y, tol)


def edge_problem(g: Geometry, R: float, x: float, y: float, tol: float) -> str | None:
    """`position_problem` found the long way: every pocket and jaw, then the cloth."""
    w, l = g.spec.w, g.spec.l
    for pocket in g.pockets:
        if math.hypot(x - pocket.center[0], y - pocket.center[1]) < pocket.radius:
            return f"inside pocket {pocket.name}"
    for jaw in g.jaws:
        if math.hypot(x - jaw.center[0], y - jaw.center[1]) < jaw.radius + R - tol:
            return f"in jaw {jaw.name}"
    if R - tol <= x <= w - R + tol and R - tol <= y <= l - R + tol:
        return None
    if any(inside(mouth(g, pocket, R), x, y) for pocket in g.pockets):
        return None
    return "off the table or in a cushion"


#: A 9 ft pool table (100 x 50 in playing surface) for nine-ball and eight-ball; the cushion
#: nose at 63.5% of the ball's diameter.
NINEBALL = TableSpec("nineball", w=1.27, l=2.54, pockets=True, cushion_height=0.635 * 2 * 0.028575)
#: The smaller pool tables (WPA playing surfaces: 8 ft 88 x 44 in, 7 ft 78 x 39 in): the same
#: balls, cushions and pockets on a shorter bed, still twice as long as wide.
NINEBALL_8FT = replace(NINEBALL, name="nineball_8ft", w=1.1176, l=2.2352)
NINEBALL_7FT = replace(NINEBALL, name="nineball_7ft", w=0.9906, l=1.9812)

#: A 12 ft snooker table (3569 x 1778 mm) with its tighter, rounder pockets; the nose at 7R/5,
#: the height Mathavan 2010 measured (sin theta = 2/5).
SNOOKER_TABLE = TableSpec(
    "snooker",
    w=1.778,
    l=3.569,
    pockets=True,
    cushion_height=1.4 * 0.02625,
    corner_mouth=0.086,
    corner_depth=0.03,
    corner_radius=0.05,
    side_mouth=0.1,
    side_depth=0.01,
    side_radius=0.052,
    jaw_radius=0.03,
)

#: A match carom table (2.84 x 1.42 m playing surface), no pockets; the cushion nose's height
#: fitted to recorded shots with the carom constants (physics.params.CAROM).
THREE_CUSHION = TableSpec("three_cushion", w=1.42, l=2.84, pockets=False, cushion_height=0.0366)

#: Each named table with the balls and cloth it is played with.
PRESETS: dict[str, tuple[TableSpec, Params]] = {
    "nineball": (NINEBALL, POOL),
    "nineball_8ft": (NINEBALL_8FT, POOL),
    "nineball_7ft": (NINEBALL_7FT, POOL),
    "snooker": (SNOOKER_TABLE, SNOOKER),
    "three_cushion": (THREE_CUSHION, CAROM),
}

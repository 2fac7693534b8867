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
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass, replace
from enum import StrEnum

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
#: Each pocket's frame (`_pocket_frame`) by table preset, ball radius and pocket: fixed per
#: table, and asked for by every line the look-ahead tries, so kept once worked out.
_FRAMES: dict[tuple[str, float, Pocket], tuple[Point, float, float]] = {}
#: An object ball's line to a pocket: (target, pocket, tolerance, distance to the pocket).
_Line = tuple[str, Pocket, float, float]
#: The lines (`_lines`) by table and the targets' places, up to LINES_KEPT of them (then all
#: forgotten at once).
_LINES: dict[tuple, tuple[_Line, ...]] = {}
LINES_KEPT = 20_000
#: Thinnest cut planned (cos of the cut angle): thinner cuts leave too little to aim at.
MIN_CUT_COS = 0.2
#: A bank's error grows this much more than its path length alone says.
BANK_SPREAD = 1.5
#: Thinnest cut of the second ball of a combination (cos of the cut angle).
COMBO_MIN_COS = 0.7
#: Heading error assumed by the estimate at the least (degrees): even a perfect hand misses a
#: little, so no pot is certain and long pots still rank below short ones.
MIN_HEADING_SD = 0.05


class Via(StrEnum):
    """How the pot reaches its pocket: straight, off one cushion, or through a second ball."""

    DIRECT = "direct"
    BANK = "bank"
    COMBO = "combo"


@dataclass(frozen=True, slots=True)
class Pot:
    """One pot: the cue ball at `cue` to the `ghost`, sending `target` into `pocket` (`via`
    a cushion or a second ball, or straight).

    d1: the cue ball's distance to the ghost (m). cos_cut: cosine of the cut angle on the
    target. travel: the length of the object balls' paths to the pocket (m). chance: the
    estimated probability that it drops (see the module docstring).
    """

    target: str
    pocket: str
    cue: Point
    ghost: Point
    d1: float
    cos_cut: float
    travel: float
    chance: float
    via: Via = Via.DIRECT

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
    key = (table.preset, table.R, pocket)
    frame = _FRAMES.get(key)
    if frame is None:
        frame = _FRAMES[key] = _pocket_frame(table, pocket)
    (ax, ay), limit, widest = frame
    cos_in = direction[0] * ax + direction[1] * ay
    angle = math.degrees(math.acos(max(-1.0, min(1.0, cos_in))))
    if angle >= limit:
        return 0.0
    return widest * (1 - (angle / limit) ** SHAPE)


def _pocket_frame(table: Table, pocket: Pocket) -> tuple[Point, float, float]:
    """A pocket's axis, angle limit and straight-in tolerance."""
    side = side_pocket(pocket)
    mouth = table.spec.side_mouth if side else table.spec.corner_mouth
    widest = mouth / 2 - JAW_SHARE * table.R
    return pocket_axis(table, pocket), SIDE_LIMIT if side else CORNER_LIMIT, widest


def chance(tol: float, spread: float, noise: Noise) -> float:
    """Estimated pot probability: the object ball's sideways miss at the pocket is Gaussian
    with sd `spread` times the heading error (radians), and must stay within `tol`."""
    if tol <= 0.0:
        return 0.0
    sd_miss = spread * math.radians(max(noise.heading, MIN_HEADING_SD))
    return math.erf(tol / (math.sqrt(2) * sd_miss))


@dataclass(frozen=True, slots=True)
class _Leg:
    """The cue ball's way to the ghost that sends a ball toward a point: the ghost, the
    distance to it, and the cosine of the cut."""

    ghost: Point
    d1: float
    cos_cut: float


def _direction(a: Point, b: Point) -> Point:
    d = math.dist(a, b)
    return ((b[0] - a[0]) / d, (b[1] - a[1]) / d)


def _leg(
    table: Table,
    balls: Mapping[str, Point],
    mover: str,
    t: str,
    toward: Point,
    checked: bool = True,
) -> _Leg | None:
    """The leg of ball `mover` to the ghost that sends `t` toward `toward`, if the cut is not
    too thin and (when `checked`) the path is clear of every other ball."""
    cue, tp = balls[mover], balls[t]
    g = ghost(tp, toward, table.R)
    d1 = math.dist(cue, g)
    if d1 < 1e-6:
        return None
    out = _direction(tp, toward)
    cos_cut = ((g[0] - cue[0]) * out[0] + (g[1] - cue[1]) * out[1]) / d1
    if cos_cut < MIN_CUT_COS:
        return None
    if checked and not path_clear(cue, g, balls, table.R, ignore={mover, t}):
        return None
    return _Leg(g, d1, cos_cut)


def _turn(leg: _Leg, R: float) -> float:
    """How much a heading error (radians) turns the object ball's path: d1 / (2R cos cut)."""
    return max(leg.d1, 2 * R) / (2 * R * leg.cos_cut)


def pots(
    table: Table,
    cue: Point,
    balls: Mapping[str, Point],
    targets: frozenset[str],
    noise: Noise,
) -> list[Pot]:
    """Every straight pot of one of `targets` whose two paths are clear, likeliest first (ties
    by target and pocket name, so the order is fixed)."""
    placed = {**balls, "cue": cue}
    found = (_straight(table, placed, line, noise) for line in _open_lines(table, balls, targets))
    return _likeliest([a for a in found if a is not None])


def _straight(
    table: Table, placed: Mapping[str, Point], line: _Line, noise: Noise, checked: bool = True
) -> Pot | None:
    """The straight pot along an object ball's `line` with the cue ball where `placed` has it,
    if the cut is not too thin and (when `checked`) the cue ball's path is clear."""
    t, pocket, tol, d2 = line
    leg = _leg(table, placed, "cue", t, pocket.center, checked)
    if leg is None:
        return None
    p = chance(tol, d2 * _turn(leg, table.R), noise)
    return Pot(t, pocket.name, placed["cue"], leg.ghost, leg.d1, leg.cos_cut, d2, p)


def _lines(table: Table, balls: Mapping[str, Point], targets: frozenset[str]) -> tuple[_Line, ...]:
    """Each (target, pocket, tolerance, distance to the pocket) that can drop, its path not yet
    checked, targets in name order and pockets in the table's. A pure function of the targets'
    places, kept once worked out (_LINES): a ball in hand asks it from every place it tries."""
    key = (table.preset, table.R, tuple((t, balls[t]) for t in sorted(targets)))
    found = _LINES.get(key)
    if found is None:
        if len(_LINES) >= LINES_KEPT:
            _LINES.clear()
        found = _LINES[key] = tuple(_walk_lines(table, balls, targets))
    return found


def _walk_lines(
    table: Table, balls: Mapping[str, Point], targets: frozenset[str]
) -> Iterator[_Line]:
    for t in sorted(targets):
        tp = balls[t]
        for pocket in table.pockets:
            tol = tolerance(table, pocket, _direction(tp, pocket.center))
            if tol > 0.0:
                yield t, pocket, tol, math.dist(tp, pocket.center)


def _line_open(table: Table, balls: Mapping[str, Point], line: _Line) -> bool:
    """Whether the object ball's path along `line` is clear of every ball but the cue ball."""
    t, pocket = line[0], line[1]
    return path_clear(balls[t], pocket.center, balls, table.R, ignore={"cue", t})


def _cue_clear(table: Table, balls: Mapping[str, Point], a: Pot) -> bool:
    """Whether the cue ball's path of pot `a` (aimed unchecked) is clear of every ball but
    its target (`balls`' own cue ball, wherever it is, is not in the way)."""
    return path_clear(a.cue, a.ghost, balls, table.R, ignore={"cue", a.target})


def _open_lines(
    table: Table, balls: Mapping[str, Point], targets: frozenset[str]
) -> Iterator[_Line]:
    """The lines (`_lines`) whose object-ball path is open: the half of a straight pot that
    does not depend on where the cue ball is."""
    return (line for line in _lines(table, balls, targets) if _line_open(table, balls, line))


def best_pots(
    table: Table,
    cue: Point,
    balls: Mapping[str, Point],
    targets: frozenset[str],
    noise: Noise,
    n: int,
    worth: Callable[[Pot], float],
) -> list[Pot]:
    """The first `n` of `pots` ordered by `worth` (ties: likeliest first), the same answer
    for less: every pot is aimed without looking at the other balls, and the paths are
    checked from the best down only until `n` are clear (the look-ahead wants a position's
    best pot or two, not every one, and checking paths is most of its cost)."""
    placed = {**balls, "cue": cue}
    aimed = []
    for line in _lines(table, balls, targets):
        a = _straight(table, placed, line, noise, checked=False)
        if a is not None:
            aimed.append((a, line))
    ranked = sorted(_likeliest_lines(aimed), key=lambda al: -worth(al[0]))
    found: list[Pot] = []
    for a, line in ranked:
        if len(found) == n:
            break
        if _cue_clear(table, placed, a) and _line_open(table, balls, line):
            found.append(a)
    return found


def best_chances(
    table: Table,
    places: list[Point],
    balls: Mapping[str, Point],
    targets: frozenset[str],
    noise: Noise,
) -> dict[str, float]:
    """For each of `targets`, the chance of its likeliest straight pot with the cue ball at any
    of `places` (`pots` from each place; 0 when none is open), paths checked from the likeliest
    down only until one is clear, each object ball's way to a pocket at most once."""
    aimed = []
    for line in _lines(table, balls, targets):
        for place in places:
            a = _straight(table, {**balls, "cue": place}, line, noise, checked=False)
            if a is not None:
                aimed.append((a, line))
    best = dict.fromkeys(targets, 0.0)
    line_open: dict[tuple[str, str], bool] = {}
    for a, line in sorted(aimed, key=lambda al: -al[0].chance):
        if best[a.target] > 0.0:
            continue
        key = (a.target, a.pocket)
        if key not in line_open:
            line_open[key] = _line_open(table, balls, line)
        if line_open[key] and _cue_clear(table, balls, a):
            best[a.target] = a.chance
    return best


def _order(a: Pot) -> tuple:
    return (-a.chance, a.target, a.pocket, a.via, a.ghost)


def _likeliest(found: list[Pot]) -> list[Pot]:
    return sorted(found, key=_order)


def _likeliest_lines(aimed: list[tuple[Pot, _Line]]) -> list[tuple[Pot, _Line]]:
    return sorted(aimed, key=lambda al: _order(al[0]))


def banks(
    table: Table, cue: Point, balls: Mapping[str, Point], targets: frozenset[str], noise: Noise
) -> list[Pot]:
    """One-cushion banks of `targets`: the object ball sent at the mirror image of a pocket,
    its error on the way grown by BANK_SPREAD (a cushion is no perfect mirror)."""
    R = table.R
    found = []
    for t in sorted(targets):
        tp = balls[t]
        for pocket in table.pockets:
            for bounce in cushion_bounces(table, tp, pocket.center):
                tol = tolerance(table, pocket, _direction(bounce, pocket.center))
                clear = path_clear(tp, bounce, balls, R, {"cue", t})
                if tol <= 0.0 or not clear:
                    continue
                if not path_clear(bounce, pocket.center, balls, R, {"cue", t}):
                    continue
                leg = _leg(table, {**balls, "cue": cue}, "cue", t, bounce)
                if leg is None:
                    continue
                length = math.dist(tp, bounce) + math.dist(bounce, pocket.center)
                p = chance(tol, BANK_SPREAD * length * _turn(leg, R), noise)
                pot = Pot(t, pocket.name, cue, leg.ghost, leg.d1, leg.cos_cut, length, p, Via.BANK)
                found.append(pot)
    return _likeliest(found)


def combos(
    table: Table, cue: Point, balls: Mapping[str, Point], targets: frozenset[str], noise: Noise
) -> list[Pot]:
    """Two-ball combinations: a legal ball sent into another ball that goes to a pocket (the
    errors of both cuts multiply)."""
    R = table.R
    with_cue = {**balls, "cue": cue}
    found = []
    for t in sorted(targets):
        for o in sorted(b for b in balls if b not in ("cue", t)):
            op = balls[o]
            for pocket in table.pockets:
                tol = tolerance(table, pocket, _direction(op, pocket.center))
                if tol <= 0.0 or not path_clear(op, pocket.center, balls, R, {"cue", o}):
                    continue
                second = _leg(table, with_cue, t, o, pocket.center)
                if second is None or second.cos_cut < COMBO_MIN_COS:
                    continue
                first = _leg(table, with_cue, "cue", t, second.ghost)
                if first is None:
                    continue
                d2 = math.dist(op, pocket.center)
                p = chance(tol, d2 * _turn(second, R) * _turn(first, R), noise)
                travel = second.d1 / second.cos_cut + d2
                pot = Pot(t, pocket.name, cue, first.ghost, first.d1, first.cos_cut, travel, p)
                found.append(replace(pot, via=Via.COMBO))
    return _likeliest(found)


def _rails(table: Table) -> tuple[tuple[int, float], ...]:
    """The four lines a ball's centre meets a cushion on: (axis, coordinate), R inside."""
    R = table.R
    return ((0, R), (0, table.width - R), (1, R), (1, table.length - R))


def _mirrored(p: Point, rail: tuple[int, float]) -> Point:
    axis, at = rail
    q = [p[0], p[1]]
    q[axis] = 2 * at - p[axis]
    return (q[0], q[1])


def _crossing(table: Table, start: Point, image: Point, rail: tuple[int, float]) -> Point | None:
    """Where the segment from `start` to `image` meets `rail`, if it does on the table and
    not within a ball of a pocket (the ball would drop)."""
    axis, at = rail
    span = image[axis] - start[axis]
    if abs(span) < 1e-9:
        return None
    f = (at - start[axis]) / span
    if not 0.0 < f < 1.0:
        return None
    p = (start[0] + f * (image[0] - start[0]), start[1] + f * (image[1] - start[1]))
    R, eps = table.R, 1e-9
    inside = R - eps <= p[0] <= table.width - R + eps and R - eps <= p[1] <= table.length - R + eps
    if inside and all(math.dist(p, k.center) > k.radius + 2 * R for k in table.pockets):
        return p
    return None


def cushion_bounces(table: Table, start: Point, end: Point) -> list[Point]:
    """Where a ball's centre, travelling from `start`, meets each of the four cushion lines
    (R inside the rails) on a one-cushion path that ends at `end`: mirror `end` in the line
    and intersect. Bounces within a ball of a pocket are left out (the ball would drop)."""
    found = []
    for rail in _rails(table):
        at = _crossing(table, start, _mirrored(end, rail), rail)
        if at is not None:
            found.append(at)
    return found


def two_cushion_paths(table: Table, start: Point, end: Point) -> list[tuple[Point, Point]]:
    """The two bounces of each two-cushion path from `start` to `end` (the cushions taken as
    mirrors: `end` mirrored in the second line, that image in the first), first bounce first."""
    found = []
    for first in _rails(table):
        for second in _rails(table):
            if first == second:
                continue
            image = _mirrored(end, second)
            b1 = _crossing(table, start, _mirrored(image, first), first)
            b2 = None if b1 is None else _crossing(table, b1, image, second)
            if b2 is not None:
                found.append((b1, b2))
    return found

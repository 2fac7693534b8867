"""Where the bot considers putting the cue ball when it has ball in hand.

Anywhere on the table: behind the ghost ball of the open pots, straight and at a cut angle
either side (a straight pot scratches too easily, a cut sends the cue ball away for position),
near and far; when no pot is open, a grid over the table. Behind the head string or
in the D: a spread over the region. Every point is on the input's placement grid, inside the
region and clear of the other balls, so the referee accepts it as it is.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from rules.aim import ghost, path_clear
from rules.bot.geometry import tolerance
from rules.inputs import PLACE_STEPS, quantise
from rules.referee import referee
from rules.spots import BAULK_Y, D_RADIUS, Point, Table, in_region, is_free
from rules.state import State

#: Ball in hand anywhere: distances (m) behind the ghost ball, cut angles (degrees) of the
#: line from it, and how many open pots (the object balls nearest their pockets) are served.
BEHIND = (0.2, 0.45)
ANGLES = (0.0, 20.0, -20.0)
OPEN_POTS = 4
#: The D: radii as fractions of its radius, and angles (degrees) from the baulk line; the
#: coarse set (one arc) is for valuing a ball in hand in the D rather than placing it, which
#: the look-ahead does for every foul it foresees, so it must be cheap.
D_RADII = (0.2, 0.55, 0.9)
D_ANGLES = (0, 30, 60, 90, 120, 150, 180)
D_RADII_COARSE = (0.55,)


def on_grid(p: Point) -> Point:
    return (quantise(p[0], PLACE_STEPS), quantise(p[1], PLACE_STEPS))


def _behind_targets(state: State, table: Table, balls: Mapping[str, Point]) -> list[Point]:
    """Behind the ghost ball of each open pot (the nearest pockets first), straight and at
    the cut angles of ANGLES on either side, near and far."""
    R = table.R
    pairs = []
    for t in sorted(referee(state.game).targets(state, balls)):
        tp = balls[t]
        for pocket in table.pockets:
            d = math.dist(tp, pocket.center)
            out = ((pocket.center[0] - tp[0]) / d, (pocket.center[1] - tp[1]) / d)
            if tolerance(table, pocket, out) > 0 and path_clear(tp, pocket.center, balls, R, {t}):
                pairs.append((d, t, pocket.name, ghost(tp, pocket.center, R), out))
    found = []
    for _, _, _, g, out in sorted(pairs)[:OPEN_POTS]:
        base = math.atan2(-out[1], -out[0])
        for angle in ANGLES:
            a = base + math.radians(angle)
            found += [(g[0] + k * math.cos(a), g[1] + k * math.sin(a)) for k in BEHIND]
    return found


def _spread(region: str, table: Table, coarse: bool) -> list[Point]:
    """Points spread over a region: arcs in the D (one when `coarse`), a grid behind the head
    string, a grid over the whole table (for a ball in hand anywhere when no pot is open)."""
    if region == "D":
        cx = table.width / 2
        return [
            (
                cx + f * D_RADIUS * math.cos(math.radians(a)),
                BAULK_Y - f * D_RADIUS * math.sin(math.radians(a)),
            )
            for f in (D_RADII_COARSE if coarse else D_RADII)
            for a in D_ANGLES
        ]
    if region == "anywhere":
        return [
            (table.width * i / 6, table.length * j / 12) for j in range(1, 12) for i in range(1, 6)
        ]
    head = table.length / 4
    return [
        (table.width * i / 8, head - table.length * j / 16) for j in (0, 1, 2) for i in range(1, 8)
    ]


def placements(
    state: State, table: Table, balls: Mapping[str, Point], coarse: bool = False
) -> list[Point]:
    """Candidate cue-ball places for the ball in hand of `state` (`balls`: the others); fewer
    in the D when `coarse`."""
    region = state.ball_in_hand
    if region is None:
        return []

    def usable(points: list[Point]) -> list[Point]:
        placed = dict.fromkeys(on_grid(p) for p in points)
        return [p for p in placed if in_region(p, region, table) and is_free(p, balls, table.R)]

    near = usable(_behind_targets(state, table, balls)) if region == "anywhere" else []
    return near or usable(_spread(region, table, coarse))

"""Where the bot considers putting the cue ball when it has ball in hand.

Anywhere on the table: straight behind each legal ball on its line to each pocket, near and
far (a straight pot, and the length the shot needs for position). Behind the head string or
in the D: a spread over the region. Every point is on the input's placement grid, inside the
region and clear of the other balls, so the referee accepts it as it is.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

from rules.inputs import PLACE_STEPS, quantise
from rules.referee import referee
from rules.spots import BAULK_Y, D_RADIUS, Point, Table, in_region, is_free
from rules.state import State

#: Distances (m) behind an object ball, on its line to a pocket, for a ball in hand anywhere.
BEHIND = (0.15, 0.35)
#: The D: radii as fractions of its radius, and angles (degrees) from the baulk line.
D_RADII = (0.2, 0.55, 0.9)
D_ANGLES = (0, 30, 60, 90, 120, 150, 180)


def on_grid(p: Point) -> Point:
    return (quantise(p[0], PLACE_STEPS), quantise(p[1], PLACE_STEPS))


def _behind_targets(state: State, table: Table, balls: Mapping[str, Point]) -> list[Point]:
    found = []
    for t in sorted(referee(state.game).targets(state, balls)):
        tp = balls[t]
        for pocket in table.pockets:
            d = math.dist(tp, pocket.center)
            ux, uy = (pocket.center[0] - tp[0]) / d, (pocket.center[1] - tp[1]) / d
            found += [(tp[0] - k * ux, tp[1] - k * uy) for k in BEHIND]
    return found


def _spread(region: str, table: Table) -> list[Point]:
    if region == "D":
        cx = table.width / 2
        return [
            (
                cx + f * D_RADIUS * math.cos(math.radians(a)),
                BAULK_Y - f * D_RADIUS * math.sin(math.radians(a)),
            )
            for f in D_RADII
            for a in D_ANGLES
        ]
    head = table.length / 4
    return [
        (table.width * i / 8, head - table.length * j / 16) for j in (0, 1, 2) for i in range(1, 8)
    ]


def placements(state: State, table: Table, balls: Mapping[str, Point]) -> list[Point]:
    """Candidate cue-ball places for the ball in hand of `state` (`balls`: the others)."""
    region = state.ball_in_hand
    if region is None:
        return []
    found = _behind_targets(state, table, balls) if region == "anywhere" else _spread(region, table)
    placed = dict.fromkeys(on_grid(p) for p in found)
    return [p for p in placed if in_region(p, region, table) and is_free(p, balls, table.R)]

"""Starting layouts of the four games, with the free choices drawn from a seed.

A rack is a dict of ball id -> (x, y) in the table coordinates of `physics.tables`: the break
end (pool's kitchen, snooker's baulk, carom's head string) at small y, the rack at large y.

- Nine-ball: a diamond with the 1 at the apex on the foot spot and the 9 in the middle; the
  other seven placed from the seed. Cue ball on the head spot.
- Eight-ball: a triangle with the apex on the foot spot, the 8 in the middle of the third row,
  a stripe and a solid in the two back corners (which side each goes from the seed), the other
  twelve from the seed (WPA). Cue ball on the head spot.
- Snooker: colours on their spots, fifteen reds (or six or ten: a triangle of three or four
  rows) in a triangle whose apex sits just behind the pink without touching it; the cue ball
  in the D beside the brown.
- Three-cushion: red on the top (foot) spot, the opponent's yellow on the head spot, the
  breaker's white on the head string 15.2 cm to one side of it (the side from the seed).

`gap` is the largest extra space between neighbouring rack balls: the lattice is laid out with
spacing 2R + gap and every ball but the apex is moved by a seeded random offset of at most
gap/2, so neighbours never overlap and the gaps vary as in a real rack. gap=0 gives a frozen
rack. Python's `random.Random`, whose sequence for a given seed is stable across versions, makes
the rack reproducible for replays.
"""

from __future__ import annotations

import math
import random
from enum import StrEnum

from rules.spots import (
    CAROM_TABLE,
    CLEARANCE,
    POOL_SIZES,
    POOL_TABLE,
    SNOOKER,
    SNOOKER_SPOTS,
    STANDARD_SIZE,
    Point,
    Table,
)


class Game(StrEnum):
    """The four rule sets; the value is the name records and the wire use."""

    NINEBALL = "nineball"
    EIGHTBALL = "eightball"
    SNOOKER = "snooker"
    THREE_CUSHION = "three_cushion"


#: Ball ids of the pool games and of snooker.
SOLIDS = tuple(str(n) for n in range(1, 8))
STRIPES = tuple(str(n) for n in range(9, 16))
REDS = tuple(f"red{n}" for n in range(1, 16))
#: Snooker's full set of reds, and the smaller sets played by each number of triangle rows.
REDS_FULL = len(REDS)
RED_ROWS = {6: 3, 10: 4, 15: 5}

#: Offset of the carom breaker's ball from the head spot along the head string (m).
CAROM_BREAK_OFFSET = 0.152

#: The snooker cue ball starts on the baulk line this far right of the brown (inside the D).
D_CUE_OFFSET = 0.1


def _triangle(apex: Point, rows: int, R: float, gap: float) -> list[list[Point]]:
    """Lattice positions row by row, the apex first, rows growing toward the top cushion."""
    d = 2 * R + gap
    dy = d * math.sqrt(3) / 2
    return [
        [(apex[0] + (j - k / 2) * d, apex[1] + k * dy) for j in range(k + 1)] for k in range(rows)
    ]


def _jitter(p: Point, gap: float, rng: random.Random) -> Point:
    """p moved by a random offset uniformly distributed in a disc of radius gap/2."""
    r = gap / 2 * math.sqrt(rng.random())
    a = 2 * math.pi * rng.random()
    return (p[0] + r * math.cos(a), p[1] + r * math.sin(a))


def _place(ids: list[str], spots: list[Point], gap: float, rng: random.Random):
    return {b: _jitter(p, gap, rng) for b, p in zip(ids, spots, strict=True)}


def nineball(seed: int, gap: float = 0.0, table: Table = POOL_TABLE) -> dict[str, Point]:
    rng = random.Random(seed)
    rows = _triangle(table.foot_spot, 5, table.R, gap)
    # The diamond is the first three rows of a triangle plus the middle of rows four and five.
    diamond = [*rows[0], *rows[1], *rows[2], rows[3][1], rows[3][2], rows[4][2]]
    apex, middle = diamond[0], diamond[4]
    others = [p for i, p in enumerate(diamond) if i not in (0, 4)]
    ids = [str(n) for n in range(2, 9)]
    rng.shuffle(ids)
    balls = {"cue": table.head_spot, "1": apex, "9": _jitter(middle, gap, rng)}
    balls.update(_place(ids, others, gap, rng))
    return balls


def eightball(seed: int, gap: float = 0.0, table: Table = POOL_TABLE) -> dict[str, Point]:
    rng = random.Random(seed)
    rows = _triangle(table.foot_spot, 5, table.R, gap)
    corners = [rows[4][0], rows[4][4]]
    middle = rows[2][1]
    others = [p for row in rows for p in row if p not in (*corners, middle)]
    solids, stripes = list(SOLIDS), list(STRIPES)
    rng.shuffle(solids)
    rng.shuffle(stripes)
    corner_ids = [solids.pop(), stripes.pop()]
    rng.shuffle(corner_ids)
    rest = solids + stripes
    rng.shuffle(rest)
    balls = {"cue": table.head_spot, "8": _jitter(middle, gap, rng)}
    balls.update(_place(corner_ids, corners, gap, rng))
    # The apex ball stays exactly on the foot spot.
    balls[rest[0]] = others[0]
    balls.update(_place(rest[1:], others[1:], gap, rng))
    return balls


def snooker(seed: int, gap: float = 0.0, reds: int = REDS_FULL) -> dict[str, Point]:
    rng = random.Random(seed)
    R = SNOOKER.R
    pink = SNOOKER_SPOTS["pink"]
    apex = (pink[0], pink[1] + 2 * R + gap + CLEARANCE)
    spots = [p for row in _triangle(apex, RED_ROWS[reds], R, gap) for p in row]
    # Reds are interchangeable, but shuffling their ids keeps each id's place seeded too.
    ids = list(REDS[:reds])
    rng.shuffle(ids)
    balls = dict(SNOOKER_SPOTS)
    balls["cue"] = (SNOOKER.width / 2 + D_CUE_OFFSET, SNOOKER_SPOTS["brown"][1])
    balls[ids[0]] = spots[0]
    balls.update(_place(ids[1:], spots[1:], gap, rng))
    return balls


def three_cushion(seed: int, gap: float = 0.0) -> dict[str, Point]:
    """The break position; `gap` is unused (no rack) but accepted like the others."""
    side = random.Random(seed).choice((-1.0, 1.0))
    hx, hy = CAROM_TABLE.head_spot
    return {
        "white": (hx + side * CAROM_BREAK_OFFSET, hy),
        "yellow": (hx, hy),
        "red": CAROM_TABLE.foot_spot,
    }


RACKS = {
    Game.NINEBALL: nineball,
    Game.EIGHTBALL: eightball,
    Game.SNOOKER: snooker,
    Game.THREE_CUSHION: three_cushion,
}


POOL_GAMES = (Game.NINEBALL, Game.EIGHTBALL)


def table(game: Game, size: int = STANDARD_SIZE) -> Table:
    """The table `game` is played on; `size` (feet: 7, 8 or 9) counts only in pool."""
    if game in POOL_GAMES:
        if size not in POOL_SIZES:
            raise ValueError(f"pool is played on {sorted(POOL_SIZES)} ft tables, not {size!r}")
        return POOL_SIZES[size]
    if size != STANDARD_SIZE:
        raise ValueError("only pool is played on tables of other sizes")
    return SNOOKER if game is Game.SNOOKER else CAROM_TABLE


def rack(
    game: Game, seed: int, gap: float = 0.0, reds: int = REDS_FULL, size: int = STANDARD_SIZE
) -> dict[str, Point]:
    """The starting layout of `game` for `seed` (see the module docstring); `reds` counts
    only in snooker, `size` only in pool (its rack and head spot scale with the table)."""
    if not (math.isfinite(gap) and 0.0 <= gap <= 0.005):
        raise ValueError(f"rack gap must be between 0 and 0.005 m, got {gap!r}")
    on = table(game, size)
    if game is Game.SNOOKER:
        if reds not in RED_ROWS:
            raise ValueError(f"snooker is played with {sorted(RED_ROWS)} reds, not {reds!r}")
        return snooker(seed, gap, reds)
    if game in POOL_GAMES:
        return RACKS[game](seed, gap, on)
    return RACKS[game](seed, gap)

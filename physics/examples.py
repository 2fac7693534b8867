"""Example scenes: the breaks and the single shot the benchmark times and the tests take apart.

These are physics fixtures, not game racks (rules/ builds those from a seed): balls frozen in
an exact triangular lattice with a chosen gap, so a test can ask for gap 0 or 1e-9 m.
"""

from __future__ import annotations

import math
from typing import Any

from physics.tables import PRESETS


def triangle(
    apex: tuple[float, float], rows: int, R: float, gap: float = 0.0, toward: float = 1.0
) -> list[tuple[float, float]]:
    """Ball centres of a triangle of `rows` rows, apex first, rows advancing along +y*toward."""
    d = 2 * R + gap
    pts = []
    for row in range(rows):
        for k in range(row + 1):
            pts.append((apex[0] + (k - row / 2) * d, apex[1] + toward * row * d * math.sqrt(3) / 2))
    return pts


def nineball_break(speed: float = 8.0, gap: float = 0.0) -> dict[str, Any]:
    """A nine-ball diamond on the foot spot, the cue ball struck from the head string."""
    spec, p = PRESETS["nineball"]
    w, l = spec.w, spec.l
    tri = triangle((w / 2, 0.75 * l), 5, p.R, gap)
    diamond = [tri[k] for k in (0, 1, 2, 3, 4, 5, 7, 8, 12)]  # rows of 1, 2, 3, 2, 1
    ids = ["1", "2", "3", "4", "9", "5", "6", "7", "8"]
    balls = {"cue": [w / 2 + 0.1, 0.25 * l]} | {
        n: list(pos) for n, pos in zip(ids, diamond, strict=True)
    }
    heading = math.degrees(math.atan2(0.75 * l - 0.25 * l, w / 2 - (w / 2 + 0.1)))
    return {
        "table": "nineball",
        "balls": balls,
        "strike": {"ball": "cue", "speed": speed, "heading": heading, "b": 0.1},
    }


def fifteen_ball_break(speed: float = 8.0, gap: float = 0.0) -> dict[str, Any]:
    """An eight-ball style rack of fifteen on a nine-ball table, hit full in the apex."""
    spec, p = PRESETS["nineball"]
    w, l = spec.w, spec.l
    tri = triangle((w / 2, 0.75 * l), 5, p.R, gap)
    balls = {"cue": [w / 2, 0.25 * l]} | {str(k + 1): list(pos) for k, pos in enumerate(tri)}
    return {
        "table": "nineball",
        "balls": balls,
        "strike": {"ball": "cue", "speed": speed, "heading": 90.0, "a": 0.02},
    }


def snooker_break_off(speed: float = 7.0, gap: float = 0.0) -> dict[str, Any]:
    """Fifteen reds behind the pink and the colours on their spots; the cue ball in the D
    clips the back of the pack off the side, as a real break-off does."""
    spec, p = PRESETS["snooker"]
    w, l, R = spec.w, spec.l, p.R
    baulk = 0.737  # the baulk line, from the bottom cushion
    pink = (w / 2, 0.75 * l)
    reds = triangle((w / 2, pink[1] + 2 * R + 0.001), 5, R, gap)
    balls = {f"red{k + 1}": list(pos) for k, pos in enumerate(reds)}
    balls |= {
        "yellow": [w / 2 + 0.292, baulk],
        "green": [w / 2 - 0.292, baulk],
        "brown": [w / 2, baulk],
        "blue": [w / 2, l / 2],
        "pink": list(pink),
        "black": [w / 2, l - 0.324],
    }
    cue = (w / 2 + 0.2, baulk - 0.05)
    balls["cue"] = list(cue)
    target = (reds[-1][0] + 2 * R * 0.7, reds[-1][1])  # thin on the end red of the back row
    heading = math.degrees(math.atan2(target[1] - cue[1], target[0] - cue[0]))
    return {
        "table": "snooker",
        "balls": balls,
        "strike": {"ball": "cue", "speed": speed, "heading": heading, "a": -0.2},
    }


def single_shot(speed: float = 1.0, heading: float = 67.0) -> dict[str, Any]:
    """The typical shot of a game (and of the bot's search): the cue ball into one object ball,
    which runs on into two cushions, about ten events in all."""
    return {
        "table": "nineball",
        "balls": {"cue": [0.4, 0.7], "1": [0.7, 1.5]},
        "strike": {"ball": "cue", "speed": speed, "heading": heading, "b": 0.1},
    }


BREAKS = {
    "nineball_break": nineball_break,
    "snooker_break_off": snooker_break_off,
    "fifteen_ball_break": fifteen_ball_break,
}

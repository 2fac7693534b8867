"""What the engine computes beside Python's `math`, in the form the compiled kernel computes
it faster (physics/pymath.pxd, which also gives the kernel Python's `math` itself)."""

from __future__ import annotations

import math


def clears(x: float, y: float, ax: float, ay: float, h: float, clearance: float) -> bool:
    """math.hypot(x, y) - 0.125 * math.hypot(ax, ay) * h * h > clearance.

    (A distance, less the most a parabola of acceleration (ax, ay) strays from its chord over
    a time h, beyond a clearance: physics.roots.path_misses.) The kernel decides all but the
    borderline cases from the squares, without either hypot, to the same answer.
    """
    return math.hypot(x, y) - 0.125 * math.hypot(ax, ay) * h * h > clearance

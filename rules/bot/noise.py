"""Execution noise: how far a stroke as played strays from the stroke as meant.

The model is the one the computational-pool tournaments used (the FastFiz server's defaults):
independent Gaussian errors on the tip offsets a and b (standard deviation 0.5 mm), on the cue
elevation (0.1 degree), on the heading (0.125 degree) and on the cue speed (0.075 m/s), all
multiplied by one factor (1 = the tournament noise, 0 = none). The engine knows nothing of it:
the arena perturbs every input it plays, a bot level perturbs its own, and the bot's search
perturbs the shots it tries, so that it prefers the ones that still work when played badly.

A perturbation is drawn from a seeded stream keyed by what it is for (`draws`), so the same
seed and key give the same errors on every run and machine, and a perturbed shot is returned
canonical and inside the input bounds (`perturb`), so the referee never refuses it.
"""

from __future__ import annotations

import hashlib
import math
import random
from dataclasses import dataclass

from physics.cue import MAX_ELEVATION, MAX_SPEED, MISCUE_LIMIT
from rules.inputs import SPEED_STEPS, Shot, Strike

#: FastFiz's default standard deviations: tip offsets (m), elevation and heading (degrees),
#: cue speed (m/s).
TIP_SD = 0.0005
ELEVATION_SD = 0.1
HEADING_SD = 0.125
SPEED_SD = 0.075

#: Slowest stroke a perturbation may leave (m/s): one speed step, the least the input allows.
MIN_SPEED = 1 / SPEED_STEPS
#: A perturbed tip offset is pulled back this far inside the miscue circle (fraction of R), so
#: that quantising it cannot push it out again.
TIP_MARGIN = 0.002


@dataclass(frozen=True, slots=True)
class Noise:
    """Standard deviations of one stroke's errors: heading and elevation in degrees, speed in
    m/s, tip offsets in metres (turned into fractions of the ball radius when applied)."""

    heading: float = HEADING_SD
    elevation: float = ELEVATION_SD
    speed: float = SPEED_SD
    tip: float = TIP_SD

    def scaled(self, factor: float) -> Noise:
        if not (math.isfinite(factor) and factor >= 0):
            raise ValueError(f"a noise factor is a finite number >= 0, got {factor!r}")
        return Noise(
            self.heading * factor, self.elevation * factor, self.speed * factor, self.tip * factor
        )

    @property
    def silent(self) -> bool:
        return self.heading == self.elevation == self.speed == self.tip == 0.0


#: The tournament noise at factor 1.
FASTFIZ = Noise()


def tournament(factor: float) -> Noise:
    """The FastFiz noise scaled by `factor`."""
    return FASTFIZ.scaled(factor)


#: One stroke's errors in standard units: heading, elevation, speed, a, b.
Draw = tuple[float, float, float, float, float]


def stream(seed: int, *key: object) -> random.Random:
    """A random stream fixed by `seed` and `key` (hashed, so keys never collide by accident;
    `random.Random`'s sequence for an integer seed is stable across Python versions)."""
    text = repr((seed, *key)).encode()
    return random.Random(int.from_bytes(hashlib.sha256(text).digest()[:8], "big"))


def draws(seed: int, n: int, *key: object) -> list[Draw]:
    """n independent standard-normal error vectors from the stream of (seed, key)."""
    rng = stream(seed, *key)
    return [tuple(rng.gauss(0.0, 1.0) for _ in range(5)) for _ in range(n)]


def perturb(shot: Shot, noise: Noise, draw: Draw, R: float) -> Shot:
    """`shot` with its stroke moved by `draw` (standard units) scaled by `noise`, clamped into
    the input bounds and quantised; placement and declarations are kept. R: the ball radius,
    to express the tip errors as fractions of it."""
    if noise.silent:
        return shot
    s = shot.strike
    zh, ze, zs, za, zb = draw
    a = s.a + noise.tip / R * za
    b = s.b + noise.tip / R * zb
    reach = math.hypot(a, b)
    if reach > MISCUE_LIMIT - TIP_MARGIN:
        shrink = (MISCUE_LIMIT - TIP_MARGIN) / reach
        a, b = a * shrink, b * shrink
    strike = Strike(
        ball=s.ball,
        heading=s.heading + noise.heading * zh,
        elevation=min(MAX_ELEVATION, max(0.0, s.elevation + noise.elevation * ze)),
        speed=min(MAX_SPEED, max(MIN_SPEED, s.speed + noise.speed * zs)),
        a=a,
        b=b,
    )
    return shot.model_copy(update={"strike": strike})

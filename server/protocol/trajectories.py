"""The engine's motion of one shot in the compact wire form the outcome message carries.

Per ball, its polynomial segments as arrays `[t, state, rx, ry, vx, vy, ax, ay, wx, wy, wz,
dwx, dwy, dwz]` (docs/protocol.md, the outcome message), numbers rounded to
`TRAJECTORY_DIGITS` significant digits: enough to animate, about half the bytes of full
precision. The exact resting positions travel in the referee's state, not here.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from physics.trajectory import Event
from physics.trajectory import Shot as EngineShot

#: Significant digits kept in a published trajectory (animation only; rest positions are exact).
TRAJECTORY_DIGITS = 7

#: One segment on the wire: [t, state, rx, ry, vx, vy, ax, ay, wx, wy, wz, dwx, dwy, dwz].
WireSegment = tuple[
    float, str, float, float, float, float, float, float, float, float, float, float, float, float
]


class Trajectory(BaseModel):
    """The engine's per-ball polynomial motion of one shot, compact (see docs/protocol.md)."""

    model_config = ConfigDict(frozen=True)

    duration: float
    events: list[Event]
    balls: dict[str, list[WireSegment]]


def _round(x: float) -> float:
    return float(f"{x:.{TRAJECTORY_DIGITS}g}")


def wire_trajectory(shot: EngineShot) -> Trajectory:
    """The engine's segments as compact arrays."""
    balls: dict[str, list[WireSegment]] = {}
    for ball, segments in shot.trajectories.items():
        balls[ball] = [
            (_round(s.t), s.state, *map(_round, (*s.r, *s.v, *s.a, *s.w, *s.dw))) for s in segments
        ]
    return Trajectory(duration=shot.duration, events=shot.events, balls=balls)

"""What a shot produces: events, per-ball piecewise-polynomial motion, and the final table.

The output is meant for clients without physics code: within a segment a ball's motion is
exactly polynomial in tau = t - seg.t,

    position(tau)         = r + v tau + a tau^2 / 2
    velocity(tau)         = v + a tau
    angular_velocity(tau) = w + dw tau

so any client can draw the exact position at any time. Everything here is a pydantic model that
serialises to JSON and to msgpack.
"""

from __future__ import annotations

from typing import Literal

import msgpack
from pydantic import BaseModel, ConfigDict

EventType = Literal[
    "strike",
    "ball_ball",
    "ball_cushion",
    "ball_jaw",
    "ball_pocket",
    "sliding_rolling",
    "rolling_spinning",
    "rolling_stationary",
    "spinning_stationary",
]

MotionState = Literal["stationary", "spinning", "sliding", "rolling", "pocketed"]


class Event(BaseModel):
    """One thing that happened at time t.

    balls: the balls involved (one, or two for ball_ball in the order (moving, struck) as the
    detector found them). cushion: the segment name (ball_cushion) or jaw name (ball_jaw).
    pocket: the pocket a ball fell in (ball_pocket) or whose jaw it hit (ball_jaw).
    """

    model_config = ConfigDict(frozen=True)

    t: float
    type: EventType
    balls: tuple[str, ...]
    cushion: str | None = None
    pocket: str | None = None


class Segment(BaseModel):
    """A stretch of one ball's motion in one state, from t to the next segment's t."""

    model_config = ConfigDict(frozen=True)

    t: float
    state: MotionState
    r: tuple[float, float]
    v: tuple[float, float]
    a: tuple[float, float]
    w: tuple[float, float, float]
    dw: tuple[float, float, float]


class BallFinal(BaseModel):
    model_config = ConfigDict(frozen=True)

    pos: tuple[float, float] | None = None
    state: MotionState
    pocket: str | None = None


class ModelsUsed(BaseModel):
    model_config = ConfigDict(frozen=True)

    ball_ball: Literal["alciatore", "frictionless"] = "alciatore"
    cushion: Literal["mathavan", "han"] = "mathavan"
    spin: bool = True
    cushion_height: float | None = None


class Shot(BaseModel):
    """The whole result of a shot."""

    events: list[Event]
    trajectories: dict[str, list[Segment]]
    final: dict[str, BallFinal]
    duration: float
    models: ModelsUsed

    def summary(self) -> dict:
        """The JSON document `billiards simulate` prints (no trajectories)."""
        return {
            "events": [e.model_dump(exclude_none=True) for e in self.events],
            "final": {k: f.model_dump() for k, f in self.final.items()},
            "duration": self.duration,
            "models": self.models.model_dump(),
        }

    def to_msgpack(self) -> bytes:
        return msgpack.packb(self.model_dump(mode="json", exclude_none=True))

    def __reduce__(self) -> tuple:
        """Pickle as plain tuples (rebuilt by `physics.records.shot`): a batch's shots come
        back from the worker processes this way, and pydantic's own pickling of the hundreds
        of small models in a shot costs more than simulating it."""
        from physics import records  # which imports this module

        events = [(e.t, e.type, e.balls, e.cushion, e.pocket) for e in self.events]
        trajectories = {
            name: [(s.t, s.state, *s.r, *s.v, *s.a, s.w, s.dw) for s in segs]
            for name, segs in self.trajectories.items()
        }
        final = {name: (f.pos, f.state, f.pocket) for name, f in self.final.items()}
        return records.shot, (events, trajectories, final, self.duration, self.models)

    @classmethod
    def from_msgpack(cls, data: bytes) -> Shot:
        return cls.model_validate(msgpack.unpackb(data))

    def position(self, ball: str, t: float) -> tuple[float, float] | None:
        """Where `ball` is at time t, evaluated from the segments alone (None once pocketed)."""
        segs = self.trajectories[ball]
        seg = segs[0]
        for s in segs:
            if s.t <= t:
                seg = s
            else:
                break
        if seg.state == "pocketed":
            return None
        tau = max(0.0, t - seg.t)
        return (
            seg.r[0] + seg.v[0] * tau + 0.5 * seg.a[0] * tau * tau,
            seg.r[1] + seg.v[1] * tau + 0.5 * seg.a[1] * tau * tau,
        )

"""The Shot's models built from the engine's raw records, unvalidated.

The engine keeps what it records as plain tuples while it runs and builds the pydantic models
of the Shot (physics.trajectory) once, at the end; a batch's shots come back from the worker
processes as the same tuples (Shot.__reduce__) and are built again here. A full break is a few
hundred models, and pydantic's general `model_construct` (aliases, defaults, private
attributes) costs several times what these models need, which is only their fields' values
and the names of those given: `trusted` sets exactly that (tests/physics_kernel/test_records.py
checks that the two agree). In the compiled kernel `object.__new__` and `object.__setattr__`
are the C functions they call, without the Python calls (physics/cobject.pxd).
"""

from __future__ import annotations

import gc
from typing import Any

from physics.trajectory import BallFinal, Event, ModelsUsed, Segment, Shot

#: What the engine records of an event: (t, type, balls, cushion, pocket), None where absent.
EventRecord = tuple[float, str, tuple[str, ...], str | None, str | None]
#: What the engine records of a segment: Segment's fields in their order, the position,
#: velocity and acceleration written out (t, state, x, y, vx, vy, ax, ay, w, dw; w and dw are
#: the ball's own tuples, not copied). Three tuples where there were six make a batch's
#: records pickle in two thirds of the time; the models are built from the same numbers.
SegmentRecord = tuple[Any, ...]
#: What the engine records of a ball at the end: (pos, state, pocket).
FinalRecord = tuple[Any, str, str | None]
#: A whole shot: the arguments of `shot`.
ShotRecord = tuple[
    list[EventRecord], dict[str, list[SegmentRecord]], dict[str, FinalRecord], float, ModelsUsed
]


class PausedCollector:
    """A context in which Python's cyclic garbage collector does not run.

    A shot, or a batch of them, makes thousands of small tuples and models, none of them in a
    reference cycle (refcounting frees them all); left running, the collector would pass over
    them again and again as they pile up, and over every shot a batch has already kept, for
    nothing: a fifth of the engine's time in a shot, more than half in a long batch. Nested
    contexts leave the collector as the outermost found it.
    """

    def __enter__(self) -> None:
        self.collecting = gc.isenabled()
        gc.disable()

    def __exit__(self, *exc: object) -> None:
        if self.collecting:
            gc.enable()


_EVENT_FIELDS = frozenset({"t", "type", "balls"})
_SEGMENT_FIELDS = frozenset(Segment.model_fields)
#: A Segment's fields, in their order, as the dict each Segment's own starts as a copy of: the
#: dict literal of the kernel grows a new dict key by key, resizing it at the sixth.
_SEGMENT_DICT = dict.fromkeys(Segment.model_fields)


def trusted(cls: type, values: dict[str, Any], given: set[str]) -> Any:
    """What `cls.model_construct(**given values)` makes, from `values` holding every field and
    `given`, the names of those passed (a set of its own, as model_construct's is)."""
    m = object.__new__(cls)
    object.__setattr__(m, "__dict__", values)
    object.__setattr__(m, "__pydantic_fields_set__", given)
    object.__setattr__(m, "__pydantic_extra__", None)
    object.__setattr__(m, "__pydantic_private__", None)
    return m


def event(t: float, kind: str, balls: tuple[str, ...], cushion: Any, pocket: Any) -> Event:
    """An Event from its record (cushion and pocket None where the event has none)."""
    given = set(_EVENT_FIELDS)
    if cushion is not None:
        given.add("cushion")
    if pocket is not None:
        given.add("pocket")
    values = {"t": t, "type": kind, "balls": balls, "cushion": cushion, "pocket": pocket}
    return trusted(Event, values, given)


def segment(s: SegmentRecord) -> Segment:
    """A Segment from its record."""
    values = _SEGMENT_DICT.copy()  # a copy of the keys, then the values: no dict grown
    values["t"] = s[0]
    values["state"] = s[1]
    values["r"] = (s[2], s[3])
    values["v"] = (s[4], s[5])
    values["a"] = (s[6], s[7])
    values["w"] = s[8]
    values["dw"] = s[9]
    return trusted(Segment, values, set(_SEGMENT_FIELDS))


def shot(
    events: list[EventRecord],
    trajectories: dict[str, list[SegmentRecord]],
    final: dict[str, FinalRecord],
    duration: float,
    models: ModelsUsed,
) -> Shot:
    """The whole Shot from the records (also what unpickles a Shot, see Shot.__reduce__)."""
    built: dict[str, Any] = {}
    for name, segs in trajectories.items():
        built[name] = [segment(s) for s in segs]
    finals: dict[str, Any] = {}
    for name, f in final.items():
        finals[name] = trusted(
            BallFinal, {"pos": f[0], "state": f[1], "pocket": f[2]}, {"pos", "state", "pocket"}
        )
    values = {
        "events": [event(e[0], e[1], e[2], e[3], e[4]) for e in events],
        "trajectories": built,
        "final": finals,
        "duration": duration,
        "models": models,
    }
    return trusted(Shot, values, {"events", "trajectories", "final", "duration", "models"})

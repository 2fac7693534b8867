"""physics.records makes what model_construct makes, at less cost, with the collector paused."""

import gc

import pytest

from physics import BudgetExceeded, parse_scene, records, simulate
from physics.engine import MAX_WORK, Simulation
from physics.examples import BREAKS
from physics.trajectory import BallFinal, Event, ModelsUsed, Segment, Shot


def same_model(a, b):
    assert type(a) is type(b)
    assert a.__dict__ == b.__dict__
    assert a.model_fields_set == b.model_fields_set
    assert a == b
    assert a.model_dump(exclude_none=True) == b.model_dump(exclude_none=True)


@pytest.mark.parametrize(
    "names", [{}, {"cushion": "top"}, {"cushion": "j1", "pocket": "tl"}, {"pocket": "tr"}]
)
def test_event(names):
    a = records.event(0.25, "ball_jaw", ("cue",), names.get("cushion"), names.get("pocket"))
    b = Event.model_construct(t=0.25, type="ball_jaw", balls=("cue",), **names)
    same_model(a, b)


FIELDS = (0.5, "sliding", (0.1, 0.2), (1.0, -1.0), (0.3, 0.4), (1.0, 2.0, 3.0), (0.0, 0.0, -1.0))
#: The same segment as the engine records it: r, v and a written out.
SEGMENT = (0.5, "sliding", 0.1, 0.2, 1.0, -1.0, 0.3, 0.4, (1.0, 2.0, 3.0), (0.0, 0.0, -1.0))


segment_fields = dict(zip(Segment.model_fields, FIELDS, strict=True))


def test_segment():
    a = records.segment(SEGMENT)
    b = Segment.model_construct(**segment_fields)
    same_model(a, b)
    assert a.model_copy(update={"t": 1.0}).t == 1.0  # its fields set is its own
    assert records.segment(SEGMENT).model_fields_set is not a.model_fields_set


def test_shot():
    models = ModelsUsed()
    a = records.shot(
        [(0.0, "strike", ("cue",), None, None), (0.5, "ball_pocket", ("1",), None, "tl")],
        {"cue": [SEGMENT], "1": [SEGMENT, SEGMENT]},
        {"cue": ((0.1, 0.2), "stationary", None), "1": (None, "pocketed", "tl")},
        0.75,
        models,
    )
    b = Shot.model_construct(
        events=[
            Event.model_construct(t=0.0, type="strike", balls=("cue",)),
            Event.model_construct(t=0.5, type="ball_pocket", balls=("1",), pocket="tl"),
        ],
        trajectories={
            name: [Segment.model_construct(**segment_fields)] * n
            for name, n in (("cue", 1), ("1", 2))
        },
        final={
            "cue": BallFinal.model_construct(pos=(0.1, 0.2), state="stationary", pocket=None),
            "1": BallFinal.model_construct(pos=None, state="pocketed", pocket="tl"),
        },
        duration=0.75,
        models=models,
    )
    same_model(a, b)
    for name in a.final:
        same_model(a.final[name], b.final[name])
    assert a.to_msgpack() == b.to_msgpack()


def test_the_collector_is_paused_only_for_the_shot():
    """A shot pauses the cyclic collector and gives it back as it found it, raise or not."""
    scene = BREAKS["nineball_break"]()
    seen = []

    class Watched(Simulation):
        def _transition(self, i):
            seen.append(gc.isenabled())
            super()._transition(i)

    assert gc.isenabled()
    Watched(parse_scene(scene)).run()
    assert seen and not any(seen) and gc.isenabled()
    budget = Simulation(parse_scene(scene))
    budget.contacts_checked = MAX_WORK  # past the budget at the first event
    with pytest.raises(BudgetExceeded):
        budget.run()
    assert gc.isenabled()
    gc.disable()
    try:
        simulate(scene)
        assert not gc.isenabled()
    finally:
        gc.enable()

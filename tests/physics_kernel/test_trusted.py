"""Event.trusted and Segment.trusted make what model_construct makes, at less cost."""

import pytest

from physics.trajectory import Event, Segment


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
    a = Event.trusted(0.25, "ball_jaw", ("cue",), **names)
    b = Event.model_construct(t=0.25, type="ball_jaw", balls=("cue",), **names)
    same_model(a, b)


def test_segment():
    fields = (
        0.5,
        "sliding",
        (0.1, 0.2),
        (1.0, -1.0),
        (0.3, 0.4),
        (1.0, 2.0, 3.0),
        (0.0, 0.0, -1.0),
    )
    a = Segment.trusted(*fields)
    b = Segment.model_construct(**dict(zip(Segment.model_fields, fields, strict=True)))
    same_model(a, b)
    assert a.model_copy(update={"t": 1.0}).t == 1.0  # its fields set is its own
    assert Segment.trusted(*fields).model_fields_set is not a.model_fields_set

"""Inputs are canonical: parsed strictly, bounded by the engine's own limits, quantised to the
steps the compact record stores, headings normalised to [0, 360)."""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from physics import parse_scene
from physics.cue import MAX_ELEVATION, MAX_SPEED, MISCUE_LIMIT
from rules.codes import Refusal, RuleError
from rules.game import Setup, check, start
from rules.inputs import Choice, Shot, Strike, accept

from .script import refused

CUE = {"ball": "cue", "speed": 3.0, "heading": 90.0}


def shot(**strike) -> dict:
    return {"strike": {**CUE, **strike}}


@pytest.mark.parametrize(
    "data",
    [
        shot(speed="3.0"),
        shot(speed=True),
        shot(heading="90"),
        shot(elevation=False),
        shot(speed=math.nan),
        shot(heading=math.inf),
        shot(speed=0.0),
        shot(speed=0.0004),  # rounds to 0 mm/s
        shot(speed=MAX_SPEED + 0.001),
        shot(elevation=MAX_ELEVATION + 0.5),  # the engine's bound, e.g. 89.5
        shot(elevation=-0.01),
        shot(a=0.4, b=0.4),
        shot(a=MISCUE_LIMIT + 0.01),
        shot(english=1.0),
        {**shot(), "place": ["0.5", 0.5]},
        {**shot(), "place": [1e300, 0.5]},
        {**shot(), "push_out": 1},
        {**shot(), "call": 3},
        {"option": "resign"},
        {"option": "play_on", "strike": CUE},
        [],
    ],
)
def test_malformed_inputs_are_refused_with_a_code(data):
    with refused(Refusal.MALFORMED):
        accept(data)
    with refused(Refusal.MALFORMED):
        accept(json.dumps(data))


@pytest.mark.parametrize(
    ("heading", "canonical"),
    [
        (-90.0, 270.0),
        (360.0, 0.0),
        (720.00004, 0.0),
        (-1e-9, 0.0),
        (359.99996, 0.0),
        (12.345678, 12.3457),
        (1e17, math.fmod(1e17, 360.0)),
    ],
)
def test_headings_are_normalised_and_quantised(heading, canonical):
    assert accept(shot(heading=heading)).strike.heading == round(canonical, 4)


def test_every_number_is_quantised_to_the_stored_steps():
    s = accept(
        {**shot(speed=2.00049, elevation=10.004, a=0.12345, b=-0.0996), "place": [0.51234, 1.00004]}
    )
    assert (s.strike.speed, s.strike.elevation, s.strike.a, s.strike.b) == (2.0, 10.0, 0.123, -0.1)
    assert s.place == (0.5123, 1.0)


numbers = st.floats(allow_nan=False, allow_infinity=False, width=64)


@given(
    speed=st.floats(0.0, MAX_SPEED + 1),
    heading=numbers,
    elevation=st.floats(-1, 91),
    a=st.floats(-0.6, 0.6),
    b=st.floats(-0.6, 0.6),
)
def test_an_accepted_strike_is_canonical_and_accepted_by_the_engine(
    speed, heading, elevation, a, b
):
    data = shot(speed=speed, heading=heading, elevation=elevation, a=a, b=b)
    try:
        first = accept(data)
    except RuleError:
        return
    assert accept(first.model_dump()) == first  # quantising is idempotent
    assert 0.0 <= first.strike.heading < 360.0
    # The engine takes every strike the rules accept: one source for the bounds.
    balls = {"cue": [0.5, 0.5]}
    parse_scene({"table": "nineball", "balls": balls, "strike": first.strike.model_dump()})


def test_an_input_that_bypassed_validation_is_refused_by_check():
    state = start(Setup(game="nineball", seed=1))
    sneaky = Shot.model_construct(
        strike=Strike.model_construct(
            ball="cue", speed=3.0, heading=90.00001, elevation=0.0, a=0.0, b=0.0
        ),
        place=None,
        push_out=False,
        call=None,
        nominate=None,
    )
    with refused(Refusal.MALFORMED):
        check(state, sneaky)
    with refused(Refusal.MALFORMED):
        check(state, Choice.model_construct(option="resign"))


def test_a_json_input_and_its_object_give_the_same_input():
    data = {**shot(heading=-45.5), "place": [0.5, 0.4]}
    assert accept(json.dumps(data)) == accept(data) == accept(json.dumps(data).encode())

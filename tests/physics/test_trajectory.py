"""Trajectory output: exact positions from the segments alone, compact on the wire."""

import json
from itertools import pairwise

import numpy as np

from physics import Shot, simulate
from physics.examples import nineball_break
from tests.physics.probe import positions


def test_segments_reproduce_every_final_position():
    shot = simulate(nineball_break())
    for name, final in shot.final.items():
        got = shot.position(name, shot.duration)
        if final.pos is None:
            assert got is None
        else:
            assert np.allclose(got, final.pos, atol=1e-12)


def test_segments_are_continuous_in_position():
    """Each segment starts where the previous one ends: no jumps at events."""
    shot = simulate(nineball_break())
    for segs in shot.trajectories.values():
        for prev, nxt in pairwise(segs):
            if nxt.state == "pocketed":
                continue
            tau = nxt.t - prev.t
            end = [prev.r[k] + prev.v[k] * tau + 0.5 * prev.a[k] * tau**2 for k in (0, 1)]
            assert np.allclose(end, nxt.r, atol=1e-12)


def test_round_trips_through_msgpack_and_json():
    shot = simulate(nineball_break())
    data = shot.to_msgpack()
    back = Shot.from_msgpack(data)
    assert back.to_msgpack() == data
    again = Shot.model_validate_json(shot.model_dump_json())
    ts = np.linspace(0, shot.duration, 50)
    a, b = positions(shot, ts), positions(again, ts)
    assert all(np.array_equal(a[k], b[k], equal_nan=True) for k in a)


def test_break_is_small_on_the_wire():
    shot = simulate(nineball_break())
    size = len(shot.to_msgpack())
    segments = sum(len(s) for s in shot.trajectories.values())
    # Every segment is 17 floats and a state; msgpack stores floats in 9 bytes.
    assert size < segments * (17 * 9 + 40) + 60 * len(shot.events) + 500
    assert len(json.dumps(shot.summary())) < size * 2

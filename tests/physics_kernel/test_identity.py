"""The compiled kernel and the pure-Python engine give the same shot to the last bit.

Same events, segments, final positions and work counted (so the budget ends a shot at the
same point), or the same error, for every example scene, the adversarial corpus and random
legal scenes. Whichever path this process runs, the worker runs the other one.
"""

import random

import pytest
from hypothesis import HealthCheck, given, settings

from bench.adversarial import valid_scene
from physics import kernel
from physics.examples import BREAKS, single_shot
from tests.physics.test_invariants import flush_by_a_pocket, scenes
from tests.physics_kernel.engines import engine_name, outcome


def test_both_engines_are_there(other):
    """The kernel is built (dev.sh builds it) and the worker runs the other path."""
    assert kernel.compiled() != kernel.pure_requested(), "the compiled kernel is not built"
    assert {engine_name(), other.submit(engine_name).result()} == {"compiled", "python"}


def same(other, scene):
    here = outcome(scene)
    there = other.submit(outcome, scene).result()
    assert here[:2] == there[:2], "different shot"
    assert here == there, "same shot, different work counted"
    return here


@pytest.mark.parametrize("name", sorted(BREAKS))
@pytest.mark.parametrize(("speed", "gap"), [(8.0, 0.0), (10.0, 1e-9), (3.0, 1e-4)])
def test_breaks(other, name, speed, gap):
    assert same(other, BREAKS[name](speed=speed, gap=gap))[0] == "shot"


@pytest.mark.parametrize("heading", [0.0, 67.0, 123.4, 250.0])
def test_single_shots(other, heading):
    for speed in (0.3, 1.0, 4.0, 11.0):
        same(other, single_shot(speed, heading))


@pytest.mark.parametrize(
    "models",
    [{"ball_ball": "frictionless"}, {"cushion": "han"}, {"spin": False}],
)
def test_breaks_with_other_models(other, models):
    for make in BREAKS.values():
        same(other, make() | {"models": models})


def test_adversarial_corpus(other):
    """Scenes at the edges of the format: 32-ball clusters, bounds, shots past the budget."""
    rng = random.Random(14)
    for _ in range(60):
        same(other, valid_scene(rng))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scenes())
def test_random_scenes(other, scene):
    same(other, scene)


@settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(flush_by_a_pocket())
def test_random_strikes_by_a_pocket(other, scene):
    same(other, scene)

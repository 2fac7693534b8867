"""Invariants over random legal scenes (hypothesis): what must hold for every shot."""

import math

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from physics import SceneError, parse_scene, simulate
from physics.engine import MAX_EVENTS
from physics.params import POOL
from physics.tables import NINEBALL
from tests.physics.probe import energy_steps, max_overlap, positions, sample_times

R = POOL.R
GEOMETRY = NINEBALL.geometry()
W, L = 1.27, 2.54


@st.composite
def scenes(draw):
    """Up to six balls placed without overlap (some frozen together or to a cushion), random
    velocities and spins, and a random choice of models."""
    n = draw(st.integers(1, 6))
    pts: list[tuple[float, float]] = []
    for _ in range(n):
        if pts and draw(st.booleans()):
            # Frozen to a ball already placed, in a random direction.
            bx, by = draw(st.sampled_from(pts))
            ang = draw(st.floats(0, 2 * math.pi))
            cand = (bx + 2 * R * math.cos(ang), by + 2 * R * math.sin(ang))
        else:
            x = draw(st.one_of(st.just(R), st.floats(R, W - R)))
            y = draw(st.floats(0.2, L - 0.2))
            cand = (x, y)
        if not (R <= cand[0] <= W - R and 0.2 <= cand[1] <= L - 0.2):
            continue
        if all(math.dist(cand, q) >= 2 * R for q in pts):
            pts.append(cand)
    balls = {f"b{k}": list(pt) for k, pt in enumerate(pts)}
    initial = {}
    for name in balls:
        if draw(st.booleans()) or not initial:
            speed = draw(st.floats(0.0, 8.0))
            ang = draw(st.floats(0, 2 * math.pi))
            spin = [draw(st.floats(-150.0, 150.0)) for _ in range(3)]
            initial[name] = {"v": [speed * math.cos(ang), speed * math.sin(ang)], "w": spin}
    scene_balls = {"table": "nineball", "balls": balls}
    try:
        parse_scene(scene_balls)
    except SceneError:
        assume(False)  # a ball drawn inside a pocket's capture circle
    models = {
        "ball_ball": draw(st.sampled_from(["alciatore", "frictionless"])),
        "cushion": draw(st.sampled_from(["mathavan", "han"])),
        "spin": draw(st.booleans()),
    }
    return {"table": "nineball", "balls": balls, "initial": initial, "models": models}


@settings(max_examples=1000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scenes())
def test_random_scenes_keep_the_invariants(scene):
    shot = simulate(scene)
    # Bounded: the shot ends, well inside the engine's hard limit.
    assert len(shot.events) < MAX_EVENTS // 10
    assert all(f.state in ("stationary", "pocketed") for f in shot.final.values())
    # No two balls ever overlap by more than 1e-9 m.
    ts = sample_times(shot, step=2e-3)
    assert max_overlap(shot, R, ts) < 1e-9
    # No ball leaves the table except into a pocket: its centre stays a radius inside the
    # cushion noses, but where it is in a pocket's mouth.
    for name, pos in positions(shot, ts).items():
        for x, y in pos[~np.isnan(pos[:, 0])]:
            on_cloth = R - 1e-9 <= x <= W - R + 1e-9 and R - 1e-9 <= y <= L - R + 1e-9
            assert on_cloth or _in_a_mouth(x, y), (name, x, y)
    # Kinetic plus rotational energy never increases at an event.
    for kind, before, after in energy_steps(scene):
        assert after <= before * (1 + 1e-12) + 1e-15, kind
    # Bit-identical on a second run.
    assert simulate(scene).to_msgpack() == shot.to_msgpack()


def _in_a_mouth(x: float, y: float) -> bool:
    """Within reach of a pocket: its capture circle grown by a ball's diameter."""
    return any(math.dist((x, y), p.center) < p.radius + 2 * R for p in GEOMETRY.pockets)

"""The scene format: every invalid scene is refused with a clear message and exit status 2."""

import json
import math
import subprocess
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from physics import (
    BudgetExceeded,
    SceneError,
    SimulationError,
    parse_scene,
    scene_from_json,
    simulate_scene,
)
from physics.scene import CONTACT_TOLERANCE, MAX_SCENE_BYTES
from physics.tables import PRESETS, clear_interior, edge_problem

R = 0.028575
GOOD = {"table": "nineball", "balls": {"cue": [0.5, 0.5], "1": [0.5, 1.5]}}


def with_(**changes):
    return {**GOOD, **changes}


@pytest.mark.parametrize(
    ("scene", "message"),
    [
        (with_(balls={"cue": [0.5, 0.5], "1": [0.5, 0.5 + 2 * R - 1e-6]}), "overlap"),
        (with_(balls={"cue": [0.01, 0.5]}), "off the table"),
        (with_(balls={"cue": [5.0, 0.5]}), "off the table"),
        (with_(balls={"cue": [float("nan"), 0.5]}), "balls.cue"),
        (with_(balls={"cue": [float("inf"), 0.5]}), "balls.cue"),
        (with_(balls={"bad id!": [0.5, 0.5]}), "balls"),
        (with_(balls={}), "balls"),
        (with_(initial={"9": {"v": [1.0, 0.0]}}), "unknown ball ids: 9"),
        (with_(initial={"cue": {"v": [20.0, 0.0]}}), "speed above"),
        (with_(initial={"cue": {"w": [0.0, 0.0, 1e4]}}), "spin above"),
        (with_(strike={"ball": "7", "speed": 2.0, "heading": 0.0}), "unknown ball ids: 7"),
        (with_(strike={"ball": "cue", "speed": 50.0, "heading": 0.0}), "strike"),
        (with_(strike={"ball": "cue", "speed": 2.0, "heading": 0.0, "a": 0.6}), "strike"),
        (with_(table="pool"), "^table: Input should be 'nineball'"),
        (with_(table={"w": -1.0, "l": 2.0}), "table.w"),
        (with_(table={"w": 1.0, "l": 2.0, "lenght": 3}), "table.lenght: Extra inputs"),
        (with_(params={"u_s": -0.1}), "params.u_s"),
        (with_(params={"e_b": 1.5}), "params.e_b"),
        (with_(params={"spin": 1.0}), "params.spin: Extra inputs"),
        (with_(params={"mathavan_steps": 4.5}), "params.mathavan_steps"),
        (with_(models={"cushion": "bogus"}), "models.cushion"),
        (with_(extra=1), "extra"),
        (with_(balls={"cue": [0.01, 0.5]}), "off the table or in a cushion"),
        (with_(balls={"cue": [0.03, 0.05]}), "pocket"),
        # Wrong types and absurd numbers (the hostile scenes), each a one-line refusal.
        (
            with_(table={"corner_depth": "x"}),
            "^table.corner_depth: Input should be a valid number$",
        ),
        (with_(table={"pockets": 1}), "table.pockets"),
        (with_(balls={"cue": ["0.5", 0.5]}), "balls.cue.0"),
        (with_(balls={"cue": [True, 0.5]}), "balls.cue.0"),
        (with_(params={"m": 1e308}), "^params.m: Input should be less than or equal to 0.5$"),
        (with_(params={"R": 10**5000}), "params.R"),
        (with_(params={"mathavan_steps": 100_000}), "params.mathavan_steps"),
        (with_(params={"u_r": 1e-9}), "params.u_r"),
        (with_(table={"w": 1e308}), "table.w"),
        (with_(params={"u\n_r": 1.0}), "Extra inputs"),  # printed escaped, on one line
        (with_(params={"u_r": None}), "params: Value error, null is not a value \\(u_r\\)"),
        (with_(strike={"ball": "cue", "speed": 2.0, "heading": 1e6}), "strike.heading"),
        # Geometry that would let a ball off the table, or leave no table.
        (with_(table={"corner_radius": 0.001}), "pocket bottom_left does not close its mouth"),
        (with_(table={"side_depth": 0.2}), "pocket middle_left does not close its mouth"),
        (with_(table={"corner_mouth": 0.05}), "corner_mouth must be wider than a ball"),
        (with_(table={"l": 0.5, "side_mouth": 0.3, "corner_mouth": 0.3}), "no room for the rails"),
        (with_(table={"cushion_height": 0.06}), "cushion_height must be between R and 1.8 R"),
        (with_(table={"cushion_height": 0.02}), "cushion_height must be between R and 1.8 R"),
    ],
)
def test_invalid_scene_is_refused(scene, message):
    with pytest.raises(SceneError, match=message) as caught:
        parse_scene(scene)
    assert "\n" not in str(caught.value)


def test_a_table_that_fits_is_accepted():
    """The bounds refuse broken tables, not unusual ones: a small bar table with deep pockets."""
    scene = parse_scene(with_(table={"w": 0.99, "l": 1.98, "corner_depth": 0.05}))
    assert scene.geometry.spec.corner_depth == 0.05


def test_overrides_apply_per_scene():
    slow = parse_scene(with_(params={"u_r": 0.02}, table={"w": 0.9906, "l": 1.9812}))
    assert slow.params.u_r == 0.02 and slow.geometry.spec.w == 0.9906
    # The preset itself is untouched: parameters are per scene, never global.
    assert parse_scene(GOOD).params.u_r == 0.01


def test_two_cloths_side_by_side():
    """The same shot on two cloths in one process: the slower cloth stops the ball sooner."""
    shot = {"cue": {"v": [0.0, 0.5], "w": [-0.5 / R, 0.0, 0.0]}}
    fast = simulate_scene(with_(balls={"cue": [0.5, 0.5]}, initial=shot))
    slow = simulate_scene(with_(balls={"cue": [0.5, 0.5]}, initial=shot, params={"u_r": 0.02}))
    assert slow["final"]["cue"]["pos"][1] < fast["final"]["cue"]["pos"][1]
    again = simulate_scene(with_(balls={"cue": [0.5, 0.5]}, initial=shot))
    assert again == fast


def test_output_echoes_the_models_used():
    out = simulate_scene(with_(models={"ball_ball": "frictionless", "cushion": "han"}))
    assert out["models"]["ball_ball"] == "frictionless"
    assert out["models"]["cushion"] == "han"
    assert out["models"]["cushion_height"] == pytest.approx(0.635 * 2 * R)


def cli(*args, stdin=None):
    return subprocess.run(
        [sys.executable, "-m", "server.cli", "simulate", *args],
        input=stdin,
        capture_output=True,
        text=True,
        check=False,
    )


def test_cli_prints_the_documented_json(tmp_path):
    scene = with_(strike={"ball": "cue", "speed": 2.0, "heading": 90.0})
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    res = cli(str(path))
    assert res.returncode == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["events"][0] == {"t": 0.0, "type": "strike", "balls": ["cue"]}
    assert any(e["type"] == "ball_ball" and e["balls"] == ["cue", "1"] for e in out["events"])
    assert set(out["final"]) == {"cue", "1"} and out["duration"] > 0
    assert out == json.loads(json.dumps(simulate_scene(scene)))


def test_cli_reads_stdin_and_rejects_bad_scenes_with_status_2():
    ok = cli("-", stdin=json.dumps(GOOD))
    assert ok.returncode == 0 and json.loads(ok.stdout)["duration"] == 0.0
    bad = cli("-", stdin=json.dumps(with_(balls={"cue": [0.5, 0.5], "x": [0.5, 0.5]})))
    assert bad.returncode == 2 and "overlap" in bad.stderr
    garbage = cli("-", stdin="{not json")
    assert garbage.returncode == 2


#: A legal scene that runs into the engine's budget: 32 balls at full speed on the smallest
#: pocketless table, with the liveliest cushions and cloth the bounds allow.
RUNAWAY = {
    "table": {"w": 0.5, "l": 0.5, "pockets": False},
    "params": {"e_c": 0.98, "u_r": 0.005, "e_b": 1.0, "f_c": 0.0, "u_s": 0.05},
    "balls": {f"b{i}": [0.07 + 0.06 * (i % 7), 0.1 + 0.06 * (i // 7)] for i in range(32)},
    "initial": {f"b{i}": {"v": [11.9 * math.cos(i), 11.9 * math.sin(i)]} for i in range(32)},
}


def test_a_runaway_shot_ends_with_the_budget_error():
    with pytest.raises(BudgetExceeded, match="budget") as caught:
        simulate_scene(RUNAWAY)
    assert isinstance(caught.value, SimulationError)


@pytest.mark.parametrize(
    ("document", "message"),
    [
        (b"[" * 30_000 + b"]" * 30_000, "nested too deeply"),
        (b'{"balls": {"cue": [' + b"1" * 5000 + b", 0.5]}}", "not JSON"),
        (b'{"balls": {"cue": [1' + b"0" * 400 + b", 0.5]}}", "balls.cue.0"),
        ('{"table": "nineball"}'.encode("utf-16"), "UTF-8"),
        ('{"balls": {"café": [0.5, 0.5]}}'.encode("latin-1"), "UTF-8"),
        (b" " * (MAX_SCENE_BYTES + 1), "at most"),
        (b"[1, 2]", "JSON object"),
        (b'{"balls": {"cue": [0.5, 0.5], "cue": [0.6, 0.5]}}', "duplicate key 'cue'"),
        (json.dumps(RUNAWAY).encode(), "budget"),
    ],
)
def test_cli_refuses_hostile_input_in_one_line(document, message):
    res = subprocess.run(
        [sys.executable, "-m", "server.cli", "simulate", "-"],
        input=document,
        capture_output=True,
        check=False,
    )
    err = res.stderr.decode()
    assert res.returncode == 2, err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    with pytest.raises(SceneError if message != "budget" else SimulationError):
        simulate_scene(scene_from_json(document))


SCALARS = (
    st.none()
    | st.booleans()
    | st.integers(-(10**30), 10**30)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=8)
)
JSON = SCALARS | st.recursive(
    SCALARS,
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner),
    max_leaves=12,
)
PLACES = st.sampled_from(
    [
        ("table",),
        ("table", "w"),
        ("table", "corner_radius"),
        ("table", "pockets"),
        ("params",),
        ("params", "R"),
        ("params", "mathavan_steps"),
        ("balls",),
        ("balls", "cue"),
        ("initial",),
        ("initial", "cue"),
        ("strike",),
        ("strike", "speed"),
        ("strike", "ball"),
        ("models",),
        ("models", "spin"),
    ]
)


@settings(max_examples=400, deadline=None)
@given(place=PLACES, value=JSON)
def test_any_value_anywhere_is_a_scene_or_a_scene_error(place, value):
    """Whatever JSON value lands wherever in a scene, the answer is a scene or a SceneError."""
    scene = json.loads(json.dumps(with_(strike={"ball": "cue", "speed": 1.0, "heading": 0.0})))
    node = scene
    for key in place[:-1]:
        if not isinstance(node.get(key), dict):
            node[key] = {}
        node = node[key]
    node[place[-1]] = value
    try:
        parse_scene(scene)
    except SceneError as exc:
        assert "\n" not in str(exc)


@settings(max_examples=400, deadline=None)
@given(
    table=st.sampled_from(sorted(PRESETS)),
    u=st.floats(0.0, 1.0),
    v=st.floats(0.0, 1.0),
    custom=st.floats(0.02, 0.06),
)
def test_a_centre_in_the_clear_interior_is_a_valid_rest(table, u, v, custom):
    """position_problem answers None without the distances inside `clear_interior`: that is
    only right if the long way agrees there, on every preset and for other ball sizes."""
    spec, params = PRESETS[table]
    for R in (params.R, min(custom, spec.cushion_height)):
        g = spec.geometry()
        x0, y0, x1, y1 = clear_interior(spec, R, CONTACT_TOLERANCE)
        assert x0 >= R - CONTACT_TOLERANCE and x0 < x1 and y0 < y1
        x, y = x0 + u * (x1 - x0), y0 + v * (y1 - y0)
        assert edge_problem(g, R, x, y, CONTACT_TOLERANCE) is None


def test_the_clear_interior_is_no_larger_than_it_must_be():
    """Grown by 0.1 mm, its edge passes through a place where a ball cannot rest."""
    for spec, params in PRESETS.values():
        g = spec.geometry()
        x0, y0, x1, y1 = clear_interior(spec, params.R, CONTACT_TOLERANCE)
        x0, y0, x1, y1 = x0 - 1e-4, y0 - 1e-4, x1 + 1e-4, y1 + 1e-4
        n = 20_000
        edge = [(x0 + (x1 - x0) * k / n, y) for k in range(n + 1) for y in (y0, y1)]
        edge += [(x, y0 + (y1 - y0) * k / n) for k in range(n + 1) for x in (x0, x1)]
        assert any(edge_problem(g, params.R, x, y, CONTACT_TOLERANCE) for x, y in edge)

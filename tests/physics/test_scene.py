"""The scene format: every invalid scene is refused with a clear message and exit status 2."""

import json
import subprocess
import sys

import pytest

from physics import SceneError, parse_scene, simulate_scene

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
        (with_(table="pool"), "unknown table"),
        (with_(table={"w": -1.0, "l": 2.0}), "table.w"),
        (with_(table={"w": 1.0, "l": 2.0, "lenght": 3}), "unknown table fields"),
        (with_(params={"u_s": -0.1}), "params.u_s"),
        (with_(params={"e_b": 1.5}), "params.e_b"),
        (with_(params={"spin": 1.0}), "unknown params"),
        (with_(params={"mathavan_steps": 4.5}), "whole number"),
        (with_(models={"cushion": "bogus"}), "models.cushion"),
        (with_(extra=1), "extra"),
        (with_(balls={"cue": [0.02, 0.02]}), "off the table"),
        (with_(balls={"cue": [0.03, 0.05]}), "pocket"),
    ],
)
def test_invalid_scene_is_refused(scene, message):
    with pytest.raises(SceneError, match=message):
        parse_scene(scene)


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

"""billiards fit: the strike fit on recorded shots (shots.json here: two of a real table's
three-cushion shots, in the recording format docs/physics.md describes) and on a shot the
engine made itself with a known strike, the report's shape, and its determinism."""

from __future__ import annotations

import json
import math
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scipy")

from physics import fit_constants as fc
from physics import simulate
from physics.fit import fit_shot
from physics.fit_cli import parse_models
from physics.recorded import from_table, kinematic_guess, load, parse
from physics.tables import THREE_CUSHION
from server.cli import main

SHOTS = Path(__file__).with_name("shots.json")


def test_the_recorded_cushion_lines_are_the_tables():
    """The recording's ball-centre limits (45.18 R by 22.09 R, R = 0.03275 recorded units)
    land a ball's radius inside the match table's cushion lines."""
    R = 0.03075
    xy = np.array([[R, R], [THREE_CUSHION.w - R, THREE_CUSHION.l - R]])
    x, y = from_table(xy)
    assert np.allclose(np.abs(x), 45.18 * 0.03275, atol=2e-3)
    assert np.allclose(np.abs(y), 22.09 * 0.03275, atol=2e-3)


def test_the_fit_beats_the_kinematic_guess_on_recorded_shots():
    for rec in load(SHOTS):
        f = fit_shot(rec, {}, {}, max_nfev=10)
        assert f.rmse_cm < f.guess_rmse_cm / 3
        assert f.rmse_cm < 12.0
        assert f.rmse_all_cm < 20.0
        assert math.hypot(f.strike["a"], f.strike["b"]) <= 0.5


def _synthetic(strike: dict, t0: float) -> dict:
    """A recording of the shot the engine makes of `strike`, sampled at 50 Hz after a still
    start of t0 seconds, in the recording's frame and rounding."""
    balls = {"1": [0.5, 0.6], "2": [0.9, 1.6], "3": [0.3, 2.2]}
    shot = simulate({"table": "three_cushion", "balls": balls, "strike": {"ball": "1", **strike}})
    t = np.arange(0.0, min(shot.duration + t0, 8.0), 0.02)
    out = {}
    for name in balls:
        xy = np.array([shot.position(name, max(0.0, s - t0)) for s in t])
        x, y = from_table(xy)
        out[name] = {"t": t.tolist(), "x": np.round(x, 3).tolist(), "y": np.round(y, 3).tolist()}
    return {"id": 1, "balls": out}


def test_a_known_strike_is_recovered():
    known = {"speed": 3.0, "heading": 70.0, "a": 0.2, "b": 0.25}
    rec = parse(_synthetic(known, 0.013))
    assert rec.cue == "1"
    guess = kinematic_guess(rec)
    assert abs(guess.heading - 70.0) < 0.5
    assert 0.0 <= guess.t0 <= 0.02
    f = fit_shot(rec, {}, {}, max_nfev=20)
    assert f.rmse_cm < 1.0
    assert f.strike["heading"] == pytest.approx(70.0, abs=0.05)
    assert f.strike["speed"] == pytest.approx(3.0, rel=0.02)
    assert f.strike["a"] == pytest.approx(0.2, abs=0.03)
    assert f.strike["b"] == pytest.approx(0.25, abs=0.03)
    assert f.strike["t0"] == pytest.approx(0.013, abs=0.003)


def test_the_fit_is_deterministic():
    rec = load(SHOTS)[0]
    a = fit_shot(rec, {}, {}, max_nfev=5)
    b = fit_shot(rec, {}, {}, max_nfev=5)
    assert (a.strike, a.rmse_cm, a.simulations) == (b.strike, b.rmse_cm, b.simulations)


def test_json_report(capsys):
    assert main(["fit", str(SHOTS), "--json", "--workers", "1", "--models", "cushion=han"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert [s["id"] for s in report["shots"]] == [4, 14]
    for s in report["shots"]:
        assert {"id", "rmse_cm", "rmse_all_cm", "strike", "simulations", "seconds"} <= set(s)
        assert {"heading", "speed", "a", "b", "elevation"} <= set(s["strike"])
    assert report["median_rmse_cm"] == pytest.approx(
        float(np.median([s["rmse_cm"] for s in report["shots"]]))
    )
    assert report["models"] == {"cushion": "han"}


def test_bad_models_are_refused():
    assert parse_models(["spin=off", "ball_ball=frictionless"]) == {
        "spin": False,
        "ball_ball": "frictionless",
    }
    with pytest.raises(ValueError, match="cushion"):
        parse_models(["cushion=stronge"])
    assert main(["fit", str(SHOTS), "--models", "spin=maybe"]) == 2


def test_bad_constants_are_refused(tmp_path, capsys):
    bad = tmp_path / "constants.json"
    bad.write_text('{"u_r": 3.0}')
    assert main(["fit", str(SHOTS), "--constants", str(bad)]) == 2
    assert "u_r" in capsys.readouterr().err


def test_constants_are_fitted_and_held_out(tmp_path, monkeypatch):
    """Two folds of one shot each: each shot is reported with constants fitted on the other,
    and the constants written stay within their bounds."""
    monkeypatch.setattr(fc, "ROUNDS", 1)
    monkeypatch.setattr(fc, "MAX_EVALS", 9)
    out = tmp_path / "constants.json"
    recs = load(SHOTS)
    with ThreadPoolExecutor(1) as pool:
        report = fc.cross_validate(recs, {}, 2, pool, out)
    assert [s["id"] for s in report["shots"]] == [4, 14]
    written = json.loads(out.read_text())
    assert set(written) == set(fc.FITTED)
    for k, (_, lo, hi) in fc.FITTED.items():
        assert lo <= written[k] <= hi
    assert len(report["fold_constants"]) == 2


def test_the_model_table_holds_each_choice_out_with_its_own_constants(monkeypatch):
    """bench/fit_models.py --folds: every choice is cross-validated, so a shot's figure comes
    from constants fitted on the other fold with that choice's own models."""
    import bench.fit_models as fm

    monkeypatch.setattr(fc, "ROUNDS", 1)
    monkeypatch.setattr(fc, "MAX_EVALS", 9)
    trained: list[dict] = []
    train = fc.train

    def counted(recs, models, *rest):
        trained.append(models)
        return train(recs, models, *rest)

    monkeypatch.setattr(fc, "train", counted)
    choices = {k: fm.CHOICES[k] for k in ("mathavan + alciatore", "han + frictionless")}
    monkeypatch.setattr(fm, "CHOICES", choices)
    recs = load(SHOTS)
    with ThreadPoolExecutor(1) as pool:
        rows = fm.measure(recs, {}, pool, folds=2)
    fm.within_noise(rows)
    assert [r["models"] for r in rows] == list(choices)
    assert trained == [choices[name] for name in choices for _fold in range(2)]
    assert all(len(r["cue_cm"]) == len(recs) for r in rows)
    assert sum(r["vs_best_cm"] == [0.0, 0.0] for r in rows) >= 1

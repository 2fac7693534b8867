"""`billiards diagrams OUTDIR` writes the four model figures as PNG files; the diagrams page's
families of shots behave as the physics says they must; the shipped real shots' fits are the
engine's."""

from __future__ import annotations

import itertools
import json
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from physics import ENGINE_VERSION, real_shots
from physics import diagram_families as fam
from physics.accuracy_data import speed_vs_error
from physics.diagrams_cli import MISSING
from server.cli import main


def test_diagrams_command_writes_the_figures(tmp_path, capsys):
    rows = speed_vs_error(shots=["cut with throw"], steps=(1e-3,), repeats=1)
    assert {r["method"] for r in rows} >= {"event (reference)", "fixed step dt=0.001"}
    saved = tmp_path / "rows.json"
    saved.write_text(json.dumps(rows))
    out = tmp_path / "figures"
    assert main(["diagrams", str(out), "--accuracy", str(saved)]) == 0
    names = {"throw.png", "cushion_rebound.png", "ball_motion.png", "speed_vs_error.png"}
    assert {p.name for p in out.iterdir()} == names
    for name in names:
        data = (out / name).read_bytes()
        assert data.startswith(b"\x89PNG") and len(data) > 10_000
    assert capsys.readouterr().out.count(".png") == 4


def _python(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)


def test_without_matplotlib_the_command_says_so_in_one_line(tmp_path):
    """matplotlib is the optional `diagrams` extra: where it is not installed (None in
    sys.modules makes its import fail as a missing package does), the command explains."""
    res = _python(
        "import sys; sys.modules['matplotlib'] = None\n"
        "from server.cli import main\n"
        f"sys.exit(main(['diagrams', {str(tmp_path)!r}]))"
    )
    assert res.returncode == 2
    assert res.stderr == MISSING + "\n" and "pip install 'billiards[diagrams]'" in MISSING
    assert not any(tmp_path.iterdir())


def test_the_engine_and_the_server_never_import_matplotlib():
    res = _python(
        "import sys\n"
        "import physics, physics.cli, physics.diagrams_cli, rules.game, server.cli\n"
        "import server.http.app\n"
        "from physics.examples import nineball_break\n"
        "physics.simulate(nineball_break())\n"
        "print(sorted(m for m in sys.modules if m.startswith('matplotlib')))"
    )
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "[]"


def test_matplotlib_is_only_the_diagrams_extra():
    meta = tomllib.loads((Path(__file__).parents[2] / "pyproject.toml").read_text())["project"]
    assert not any(d.startswith("matplotlib") for d in meta["dependencies"])
    assert [d for d in meta["optional-dependencies"]["diagrams"] if d.startswith("matplotlib")]


# -- the diagrams page's families of shots (physics.diagram_families) -------------------------


@pytest.fixture(scope="module")
def rebounds() -> dict:
    return {f["name"]: f for f in fam.cushion_families(2.0, 0.5, 45.0)["families"]}


@pytest.fixture(scope="module")
def throws() -> dict:
    return {f["name"]: f for f in fam.throw_families(1.0, 30.0)["families"]}


def _by_value(family: dict, key: str) -> dict:
    return {s["value"]: s[key] for s in family["shots"]}


def test_every_family_is_there_and_starts_where_its_approach_ends(rebounds, throws):
    assert list(rebounds) == ["stun", "running", "check", "side", "slow_topspin", "hard_topspin"]
    assert list(throws) == ["stun", "roll", "varying_roll", "varying_side"]
    for family in [*rebounds.values(), *throws.values()]:
        assert len(family["shots"]) >= 5
        for shot in family["shots"]:
            cue = shot["tracks"]["cue"]
            assert len(cue) >= 2 and cue[0] == pytest.approx(shot["approach"][1], abs=1e-3)


def test_the_rebounds_stay_on_the_table_and_leave_the_cushion(rebounds):
    for family in rebounds.values():
        for shot in family["shots"]:
            track = np.array(shot["tracks"]["cue"])
            assert np.all(track[:, 0] <= fam.W - fam.R + 1e-3) and np.all(track[:, 0] >= 0)
            assert track[-1][0] < track[0][0] - 0.05  # it came back off the cushion


def test_running_side_widens_the_rebound_and_check_side_narrows_it(rebounds):
    """At every incidence the rolling ball with running side leaves the cushion further from
    the normal than the stun ball, and the one with check side nearer it than running."""
    stun = _by_value(rebounds["stun"], "rebound_deg")
    running = _by_value(rebounds["running"], "rebound_deg")
    check = _by_value(rebounds["check"], "rebound_deg")
    for incidence in fam.INCIDENCES:
        assert running[incidence] > stun[incidence]
        assert running[incidence] > check[incidence]
    assert check[30] < stun[30] < running[30]
    side = [s["rebound_deg"] for s in rebounds["side"]["shots"]]
    assert all(b > a for a, b in itertools.pairwise(side))


def test_the_rebound_angle_grows_with_running_side_at_every_speed():
    for speed in (0.5, 2.0, 4.0):
        curve = fam.rebound_against_side(speed, 45.0)
        assert curve["side"] == list(fam.SIDE_CURVE)
        off = curve["rebound_deg"]
        assert all(b > a for a, b in itertools.pairwise(off))
        assert off[-1] - off[0] > 10.0  # a whole turn of side moves it by degrees, not hairs


def test_topspin_bends_the_rebound_away_from_the_normal(rebounds):
    """A rolling ball leaves the cushion still turning forward: the cloth bends its path
    along the cushion until it rolls again, slowly or hard; the stun ball bends less."""
    for name in ("slow_topspin", "hard_topspin"):
        for shot in rebounds[name]["shots"]:
            if shot["value"] > 0:
                assert shot["settled_deg"] > shot["rebound_deg"] + 2.0
    stun = rebounds["stun"]["shots"][2]  # 30 degrees
    roll = rebounds["hard_topspin"]["shots"][2]
    assert roll["settled_deg"] - roll["rebound_deg"] > stun["settled_deg"] - stun["rebound_deg"]


def test_a_hard_rolling_ball_curves_over_a_longer_path_than_a_slow_one(rebounds):
    """The bend takes a distance that grows as the square of the speed: the hard ball is
    still bending where the slow one already runs straight."""
    for slow, hard in zip(
        rebounds["slow_topspin"]["shots"], rebounds["hard_topspin"]["shots"], strict=True
    ):
        if slow["value"] == 0:
            continue

        # Within 0.2 m of the cushion the slow ball's path has turned further than the hard one's.
        def turned(shot):
            t = np.array(shot["tracks"]["cue"])
            near = t[np.hypot(t[:, 0] - t[0, 0], t[:, 1] - t[0, 1]) < 0.2]
            d = near[-1] - near[-2]
            return math.degrees(math.atan2(d[1], -d[0]))

        assert turned(slow) > turned(hard) + 1.0


def test_stun_throws_more_than_roll_and_neither_at_a_full_hit(throws):
    stun = _by_value(throws["stun"], "throw_deg")
    roll = _by_value(throws["roll"], "throw_deg")
    assert stun[0] == pytest.approx(0.0, abs=1e-6) and roll[0] == pytest.approx(0.0, abs=1e-6)
    for cut in fam.CUTS[1:]:
        assert stun[cut] > roll[cut] > 0.0


def test_throw_falls_with_speed():
    for top in (0.0, 1.0):
        throws = [fam.throw_shot(v, 30.0, top, 0.0)["throw_deg"] for v in (0.3, 1.0, 3.0)]
        assert all(b < a for a, b in itertools.pairwise(throws))


def test_throw_is_largest_for_a_stun_ball(throws):
    """Draw or follow both leave the contact slipping faster, where the friction is weaker."""
    by_top = _by_value(throws["varying_roll"], "throw_deg")
    assert by_top[0.0] > by_top[0.5] > by_top[1.0] > 0
    assert by_top[0.0] > by_top[-0.5] > by_top[-1.0] > 0


def test_outside_side_gears_the_throw_out(throws):
    """Outside side (positive) takes the slip out of the contact: at s = sin(cut) the balls
    gear and the object ball leaves along the line of centres; more throws it the other way."""
    by_side = _by_value(throws["varying_side"], "throw_deg")
    assert by_side[0.0] > by_side[0.5] > by_side[1.0]
    assert by_side[0.5] == pytest.approx(0.0, abs=0.1)  # sin 30 degrees = 0.5
    assert by_side[1.0] < 0


def test_the_mathavan_figures_follow_the_paper():
    """Mathavan et al. 2010's figures for its snooker ball: rebound angle rises with the
    incidence for every topspin; more topspin rebounds faster (the nose friction turns it
    into speed) and wider; stun leaves nearer the normal than it came (friction)."""
    figures = fam.mathavan_figures(1.0)
    incidence = figures["incidence_deg"]
    curves = {c["k"]: c for c in figures["curves"]}
    assert sorted(curves) == [-1, 0, 1, 2]
    for c in curves.values():
        assert c["rebound_deg"][0] == pytest.approx(0.0, abs=1e-9)
        assert all(b > a for a, b in itertools.pairwise(c["rebound_deg"]))
        assert all(0.5 < s < 1.0 for s in c["speed"])
    for i, a in enumerate(incidence):
        if a <= 60:
            assert curves[2]["speed"][i] > curves[1]["speed"][i] > curves[0]["speed"][i]
        if 0 < a <= 60:
            assert curves[2]["rebound_deg"][i] > curves[0]["rebound_deg"][i]
    at_45 = incidence.index(45)
    assert curves[0]["rebound_deg"][at_45] < 45.0


# -- the shipped real shots (physics.real_shots) ---------------------------------------------


def test_the_shipped_fits_are_what_the_engine_gives_now():
    """bench/real_shots.py's fits simulated again: the same RMSE to the last bits, so the
    shipped file is the engine's (rerun the bench when ENGINE_VERSION changes)."""
    shipped = real_shots.fits()
    assert shipped["engine_version"] == ENGINE_VERSION
    assert len(shipped["shots"]) == len(real_shots.recordings()) == 91
    for entry in shipped["shots"][:3]:
        r = real_shots.refit(entry["id"], None, {}, real_shots.Bound(1, math.inf), refine=False)
        assert (r.rmse_cm, r.rmse_all_cm) == (entry["rmse_cm"], entry["rmse_all_cm"])
        assert (r.simulations, r.stopped) == (1, "evaluated")


def test_a_refit_keeps_to_its_bound_and_answers_its_best():
    entry = real_shots.fits()["shots"][1]
    start = {**entry["strike"], "heading": entry["strike"]["heading"] - 0.8}
    unbounded = real_shots.Bound(1, math.inf)
    before = real_shots.refit(entry["id"], start, {}, unbounded, refine=False).rmse_cm
    r = real_shots.refit(entry["id"], start, {}, real_shots.Bound(25, math.inf), refine=True)
    assert r.simulations <= 25 and r.stopped == "simulations"
    assert r.rmse_cm < before
    late = real_shots.refit(entry["id"], start, {}, real_shots.Bound(10**6, 0.0), refine=True)
    assert (late.stopped, late.simulations, late.rmse_cm) == ("time", 1, before)
    turned = {**start, "heading": start["heading"] + 360.0}
    again = real_shots.refit(entry["id"], turned, {}, unbounded, refine=False)
    assert again.rmse_cm == pytest.approx(before, rel=1e-6)
    assert -180.0 <= again.strike["heading"] < 180.0  # within a turn, as the wire requires

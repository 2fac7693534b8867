"""`billiards diagrams OUTDIR` writes the four model figures as PNG files."""

from __future__ import annotations

import json
import subprocess
import sys
import tomllib
from pathlib import Path

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

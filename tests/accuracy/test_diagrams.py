"""`billiards diagrams OUTDIR` writes the four model figures as PNG files."""

from __future__ import annotations

import json

from physics.accuracy_data import speed_vs_error
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

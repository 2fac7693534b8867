"""bench/bot.py: a row played, its seed printed so it can be played again, and why it lost."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _bench(*args: str) -> str:
    """What a bench script printed, run from the repository's root."""
    done = subprocess.run(
        [sys.executable, *args], cwd=ROOT, capture_output=True, text=True, check=True
    )
    return done.stdout


def test_a_row_prints_its_seed_its_bar_and_its_losses():
    out = _bench("bench/bot.py", "--rows", "ladder:1", "--seed", "1234")
    rows = [line for line in out.splitlines() if line.startswith("ladder ")]
    assert len(rows) == 8  # four steps in the table, four in the losses
    assert all("1234" in r and ">= 60% wins" in r for r in rows[:4])
    assert all("(only 1 of 100 games)" in r for r in rows[:4])
    assert all(" lost: " in r for r in rows[4:])


def test_escapes_judges_each_snookered_position_on_plays_of_its_own():
    out = _bench("bench/escapes.py", "--positions", "2", "--plays", "4").splitlines()
    rows = [line.split() for line in out[1:-2]]
    assert len(rows) == 2
    assert all(int(r[0]) >= 20_000 and r[4].endswith("%") for r in rows)
    assert -1.0 <= float(rows[0][3]) <= 1.0
    assert out[-1].startswith("2 snookered nineball positions from seed 20000")

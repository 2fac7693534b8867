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


def _untimed(row: str) -> list[str]:
    """A row of the table without its two decision-time columns (median s, p95 s)."""
    words = row.split()
    return words[:12] + words[14:]


def test_rows_played_at_once_are_the_rows_played_one_by_one():
    """--jobs changes how long the table takes, not what it says: each row is a function of
    its seed, and the rows print in the order asked for."""
    asked = ["bench/bot.py", "--rows", "ladder:1", "--seed", "77"]
    tables = [_bench(*asked, "--jobs", jobs).splitlines() for jobs in ("1", "2")]
    rows = [[_untimed(r) for r in t if r.startswith("ladder ")] for t in tables]
    assert len(rows[0]) == 8
    assert rows[0] == rows[1]


def test_runouts_tallies_how_each_visit_ended():
    out = _bench("bench/runouts.py", "--positions", "4", "--level", "1").splitlines()
    assert out[0] == "nineball level 1, 4 positions from seed 50000"
    rows = [[int(w) for w in line.split()[1:]] for line in out[2:] if line.split()[0].isdigit()]
    total = [int(w) for w in next(x for x in out if x.startswith("  all")).split()[1:]]
    assert total[0] == 4 == sum(total[1:])
    assert [sum(col) for col in zip(*rows, strict=True)] == total
    assert out[-2].startswith(f"won {total[1] / 4:.1%}")


def test_potrates_bands_every_chosen_pot_once():
    out = _bench("bench/potrates.py", "--positions", "8", "--plays", "3").splitlines()
    n, left_out = int(out[0].split()[0]), int(out[0].split(", ")[1].split()[0])
    assert out[0] == (
        f"{n} pots chosen on 8 positions from seed 90000, "
        f"{left_out} of them dropping nothing as meant (left out)"
    )
    rows = {line.split()[0]: line.split()[1:] for line in out[2:]}
    n -= left_out
    assert n > 0 and int(rows["all"][0]) == n
    assert sum(int(r[0]) for band, r in rows.items() if band != "all") == n
    assert all(0.0 <= float(r[1]) <= 1.0 and 0.0 <= float(r[2]) <= 1.0 for r in rows.values())


def test_strokes_compares_every_set_with_the_first_on_the_same_positions():
    out = _bench("bench/strokes.py", "--positions", "2", "--judge", "4", "--jobs", "1")
    rows = [[cell.strip() for cell in line.split("|")[1:-1]] for line in out.splitlines()[2:]]
    from bench.strokes import SETS

    assert [(r[0], r[1]) for r in rows] == [
        (game, name) for game in ("nineball", "eightball") for name in SETS
    ]
    assert all(r[2] == "2" and 0 <= int(r[3]) <= 2 for r in rows)
    first = [r for r in rows if r[1] == next(iter(SETS))]
    assert all(r[3] == "0" and r[4].startswith("+0.0000") for r in first)


def test_pot_chances_model_holds_the_bots_estimate_and_fits():
    """bench/pot_chances.py: its ChanceModel with nothing added is the estimate the bot plans
    with, pot for pot; the script measures pots, fits the model and prints both tables."""
    from bench.pot_chances import ChanceModel, geometry, measure
    from bench.runouts import positions
    from rules.racks import Game

    measured = [
        m
        for seed, state in positions(Game.NINEBALL, 500_000, 30)
        if not state.ball_in_hand
        for m in measure(seed, state, 2)
    ]
    assert len(measured) >= 10
    same = ChanceModel(turn_spread=1.0, object_spread=0.0, shift=0.0, slope=1.0)
    assert all(abs(same(m) - geometry(m)) < 1e-9 for m in measured)
    out = _bench("bench/pot_chances.py", "--positions", "30", "--plays", "4", "--fit")
    assert out.count("log-likelihood of the plays") == 2
    assert "ChanceModel(turn_spread=" in out

"""Which models a real table asks for: each model choice's error on recorded shots and its cost.

For each choice (cushion Mathavan or Han, ball-ball throw by Alciatore's friction or none,
spin on or off) every recorded shot's strike is fitted (`billiards fit`, physics.fit) and the
table prints the median and p90 cue-ball RMSE, the median all-balls RMSE, the CPU per shot
and per simulation, and whether the choice is within the measurement noise of the best: the
90% bootstrap interval (shots resampled, paired, a fixed seed) of its median's difference
from the best median reaches zero. Writes the speed-against-error PNG; progress on stderr.

The constants: with `--folds N` each choice is cross-validated, its own constants fitted on
N-1 folds for the shots of the other (`billiards fit --fit-constants`' held-out figures,
physics.fit_constants.held_out), so every choice is measured on shots its constants never
saw and none is held to constants fitted with another's models. Without it, every choice
plays at the carom defaults (or --constants), which were fitted with the default models.

    .venv/bin/python bench/fit_models.py SHOTS.json [--folds N | --constants FILE]
        [--out DIR] [--json FILE] [--every N]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from physics.fit_batch import fit_all, process_pool
from physics.fit_constants import held_out
from physics.recorded import load

#: The model choices compared (the scene's `models`; with spin off the others do not apply).
CHOICES = {
    "mathavan + alciatore": {"cushion": "mathavan", "ball_ball": "alciatore"},
    "han + alciatore": {"cushion": "han", "ball_ball": "alciatore"},
    "mathavan + frictionless": {"cushion": "mathavan", "ball_ball": "frictionless"},
    "han + frictionless": {"cushion": "han", "ball_ball": "frictionless"},
    "spin off": {"spin": False},
}
#: Bootstrap resamples of the shots, and the generator's seed (the same table every run).
RESAMPLES, SEED = 2000, 0


def measure(recs, constants, pool, folds: int | None = None) -> list[dict]:
    """One row per model choice, each shot's cue RMSE kept for the bootstrap (held out over
    `folds` when given)."""
    rows = []
    for name, models in CHOICES.items():
        if folds:
            fitted = held_out(recs, models, folds, pool)[0]
        else:
            fitted = fit_all(recs, constants, models, pool)
        cue = [f.rmse_cm for f in fitted]
        cpu = sum(f.seconds for f in fitted)
        sims = sum(f.simulations for f in fitted)
        rows.append(
            {
                "models": name,
                "median_cm": float(np.median(cue)),
                "p90_cm": float(np.percentile(cue, 90)),
                "median_all_cm": float(np.median([f.rmse_all_cm for f in fitted])),
                "cpu_s_per_shot": cpu / len(fitted),
                "cpu_ms_per_simulation": 1e3 * cpu / sims,
                "cue_cm": cue,
            }
        )
        print(f"{name}: median {rows[-1]['median_cm']:.2f} cm", file=sys.stderr, flush=True)
    return rows


def within_noise(rows: list[dict]) -> None:
    """Each row's 90% bootstrap interval of (its median - the best median), paired by shot."""
    best = min(rows, key=lambda r: r["median_cm"])
    rng = np.random.default_rng(SEED)
    n = len(best["cue_cm"])
    picks = rng.integers(0, n, size=(RESAMPLES, n))
    b = np.median(np.asarray(best["cue_cm"])[picks], axis=1)
    for r in rows:
        m = np.median(np.asarray(r["cue_cm"])[picks], axis=1)
        r["median_interval_cm"] = [float(v) for v in np.percentile(m, [5, 95])]
        low, high = np.percentile(m - b, [5, 95])
        r["vs_best_cm"] = [float(low), float(high)]
        r["within_noise"] = bool(low <= 0.0)


def figure(rows: list[dict], path: Path, held_out: bool) -> Path:
    """CPU per shot against the median cue-ball RMSE, one point per model choice, its bar the
    median's 90% bootstrap interval."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for k, r in enumerate(rows):
        low, high = r["median_interval_cm"]
        err = [[r["median_cm"] - low], [high - r["median_cm"]]]
        ax.errorbar(r["cpu_s_per_shot"], r["median_cm"], yerr=err, fmt="o", capsize=3)
        ax.annotate(r["models"], (r["cpu_s_per_shot"], r["median_cm"]), fontsize=8,
                    xytext=(5, 8 - 12 * (k % 3)), textcoords="offset points")  # fmt: skip
    ax.set_yscale("log")
    ax.set_xlabel("CPU per shot fitted (s)")
    which = "held-out median" if held_out else "median"
    ax.set_ylabel(f"{which} cue-ball RMSE (cm, recorded units)")
    ax.set_title("Model choices against a real table: cost and error")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shots", type=Path, help="recorded shots (JSON)")
    parser.add_argument("--constants", type=Path, help="constants JSON (default: carom's)")
    parser.add_argument(
        "--folds", type=int, help="cross-validate each choice over N folds (its own constants)"
    )
    parser.add_argument("--out", type=Path, default=Path("out"), help="PNG directory")
    parser.add_argument("--json", type=Path, help="also save the rows as JSON here")
    parser.add_argument("--every", type=int, default=1, help="fit every Nth shot only")
    args = parser.parse_args(argv)
    recs = load(args.shots)[:: args.every]
    if args.folds and args.constants:
        parser.error("--folds fits each choice's constants: --constants does not apply")
    constants = json.loads(args.constants.read_text()) if args.constants else {}
    with process_pool() as pool:
        rows = measure(recs, constants, pool, args.folds)
    within_noise(rows)
    if args.folds:
        said = f"each choice's own, fitted on the other of {args.folds} folds (held out)"
    else:
        said = constants or "carom defaults"
    print(f"{len(recs)} shots; constants: {said}")
    print(
        f"{'models':24s} {'median cm':>9s} {'p90 cm':>7s} {'all cm':>7s} {'CPU s/shot':>10s} "
        f"{'ms/sim':>7s} {'vs best (90%)':>16s}  within noise"
    )
    for r in rows:
        low, high = r["vs_best_cm"]
        print(
            f"{r['models']:24s} {r['median_cm']:9.2f} {r['p90_cm']:7.2f} "
            f"{r['median_all_cm']:7.2f} {r['cpu_s_per_shot']:10.3f} "
            f"{r['cpu_ms_per_simulation']:7.3f} {f'[{low:+.2f}, {high:+.2f}]':>16s}  "
            f"{'yes' if r['within_noise'] else 'no'}"
        )
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    args.out.mkdir(parents=True, exist_ok=True)
    png = figure(rows, args.out / "fit_models.png", bool(args.folds))
    print(f"plot: {png}" + (f", rows: {args.json}" if args.json else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())

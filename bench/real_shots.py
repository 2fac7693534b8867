"""The shipped recordings' fits: each shot's strike as `billiards fit` finds it with the
engine's default constants and models, written to physics/data/real_shots_fits.json for the
diagrams page's "real shots" view (physics.real_shots), and printed as a table.

The constants were fitted on these same shots (docs/physics.md, "Recorded shots"), so these
are not held-out figures: the held-out ones are the cross-validation's. Rerun whenever the
engine's results change (a new ENGINE_VERSION): tests/accuracy/test_diagrams.py checks that
the file's RMSEs are what the engine gives now.

    .venv/bin/python bench/real_shots.py [--workers N]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from physics import ENGINE_VERSION
from physics.fit_batch import fit_all, process_pool, stderr_progress
from physics.real_shots import DATA, FITS
from physics.recorded import load


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=None, help="processes (every core)")
    args = parser.parse_args()
    recs = load(DATA)
    began = time.perf_counter()
    with process_pool(args.workers) as pool:
        fitted = fit_all(recs, {}, {}, pool, stderr_progress)
    seconds = time.perf_counter() - began
    cue = np.array([f.rmse_cm for f in fitted])
    every = np.array([f.rmse_all_cm for f in fitted])
    report = {
        "engine_version": ENGINE_VERSION,
        "constants": "the carom defaults (physics.params.CAROM, the three_cushion table)",
        "models": {},
        "median_rmse_cm": float(np.median(cue)),
        "p90_rmse_cm": float(np.percentile(cue, 90)),
        "median_rmse_all_cm": float(np.median(every)),
        "shots": [
            {
                "id": f.id,
                "cue": rec.cue,
                "duration": max(float(tr.t[-1]) for tr in rec.tracks.values()),
                "rmse_cm": f.rmse_cm,
                "rmse_all_cm": f.rmse_all_cm,
                "simulations": f.simulations,
                "strike": {k: f.strike[k] for k in ("heading", "speed", "a", "b", "t0")},
            }
            for rec, f in zip(recs, fitted, strict=True)
        ],
    }
    FITS.write_text(json.dumps(report, indent=1) + "\n")
    print(f"{'shot':>5} {'cue cm':>7} {'all cm':>7} {'sims':>6}")
    for f in fitted:
        print(f"{f.id:>5} {f.rmse_cm:7.2f} {f.rmse_all_cm:7.2f} {f.simulations:6d}")
    print(
        f"median cue {report['median_rmse_cm']:.2f} cm, p90 {report['p90_rmse_cm']:.2f} cm, "
        f"median all balls {report['median_rmse_all_cm']:.2f} cm; {len(fitted)} shots in "
        f"{seconds:.0f} s of wall time; written to {FITS.name}"
    )


if __name__ == "__main__":
    main()

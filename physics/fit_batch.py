"""Fitting many recorded shots over every core, and the figures `billiards fit` reports.

Each shot's fit is independent of the others (physics.fit), so the shots go to worker
processes one at a time and come back in any order; the result is put back in the input
order, and a shot's fit does not depend on which worker did it, so the figures are the same
for any number of workers.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from multiprocessing import get_context
from typing import Any

import numpy as np

from physics.fit import MAX_NFEV, Fitted, fit_shot
from physics.recorded import Recording

Progress = Callable[[int, int, Fitted], None]


def stderr_progress(done: int, total: int, f: Fitted) -> None:
    """One line per fitted shot on standard error."""
    print(
        f"[{done}/{total}] shot {f.id}: cue {f.rmse_cm:.1f} cm, all {f.rmse_all_cm:.1f} cm, "
        f"{f.simulations} simulations, {f.seconds:.1f} s",
        file=sys.stderr,
        flush=True,
    )


def process_pool(workers: int | None = None) -> ProcessPoolExecutor:
    """Worker processes (every core by default), started by spawn as physics.batch's are."""
    return ProcessPoolExecutor(workers or os.cpu_count() or 1, mp_context=get_context("spawn"))


def fit_all(
    recs: Sequence[Recording],
    constants: dict[str, float],
    models: dict[str, Any],
    pool: Executor | None = None,
    progress: Progress | None = None,
    max_nfev: int = MAX_NFEV,
) -> list[Fitted]:
    """Every recording's fit, in the order given (in this process when pool is None)."""
    out: dict[int, Fitted] = {}
    if pool is None:
        for k, rec in enumerate(recs):
            out[k] = fit_shot(rec, constants, models, max_nfev)
            if progress:
                progress(k + 1, len(recs), out[k])
        return [out[k] for k in range(len(recs))]
    futures = {
        pool.submit(fit_shot, rec, constants, models, max_nfev): k for k, rec in enumerate(recs)
    }
    for future in as_completed(futures):
        out[futures[future]] = future.result()
        if progress:
            progress(len(out), len(recs), out[futures[future]])
    return [out[k] for k in range(len(recs))]


def summary(fitted: Sequence[Fitted], seconds: float) -> dict[str, Any]:
    """The `--json` document: each shot's row, then the median and p90 of the cue-ball and
    all-balls RMSE, the simulations, the wall time and the simulations per second."""
    cue = np.array([f.rmse_cm for f in fitted])
    every = np.array([f.rmse_all_cm for f in fitted])
    sims = sum(f.simulations for f in fitted)
    return {
        "shots": [f.row() for f in fitted],
        "median_rmse_cm": float(np.median(cue)),
        "p90_rmse_cm": float(np.percentile(cue, 90)),
        "median_rmse_all_cm": float(np.median(every)),
        "p90_rmse_all_cm": float(np.percentile(every, 90)),
        "under_10_cm": int((cue < 10).sum()),
        "simulations": sims,
        "seconds": seconds,
        "simulations_per_second": sims / seconds if seconds > 0 else None,
    }


def timed_fit(
    recs: Sequence[Recording],
    constants: dict[str, float],
    models: dict[str, Any],
    pool: Executor | None = None,
    progress: Progress | None = None,
) -> dict[str, Any]:
    """`fit_all` and its `summary`, timed on the wall clock."""
    began = time.perf_counter()
    fitted = fit_all(recs, constants, models, pool, progress)
    return summary(fitted, time.perf_counter() - began)

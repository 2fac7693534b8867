"""Fitting the constants a table's shots share, and measuring them on shots they never saw.

The cloth, cushion and ball constants (`FITTED`) are the same for every shot on a table,
while each shot has its own strike. The fit alternates: every training shot's strike is
fitted with the current constants (physics.fit), then the constants by least squares over
all training shots' residuals with those strikes held, `ROUNDS` times. Cross-validation
splits the shots into folds by their position in the file (shot k goes to fold k mod n):
each fold's shots are fitted (their strikes only) with constants fitted on the other folds,
and those held-out figures are the ones reported. The constants written are then fitted on
every shot.
"""

from __future__ import annotations

import json
import math
import sys
import time
from collections.abc import Sequence
from concurrent.futures import Executor
from pathlib import Path
from typing import Any

import numpy as np

from physics.fit import Fitted, Problem
from physics.fit_batch import fit_all, stderr_progress, summary
from physics.params import CAROM
from physics.recorded import Recording

#: The shared constants fitted, their starting values and bounds (within
#: physics.scene.ParamsIn's and TableIn's, and check_table's cushion height of R to 1.8 R).
#: The starting values are the textbook ones the carom table had before it was fitted to
#: recorded shots (engine version 3), not its defaults now: those were fitted on the very
#: shots a cross-validation holds out.
FITTED: dict[str, tuple[float, float, float]] = {
    "u_s": (0.2, 0.05, 1.0),
    "u_r": (0.007, 0.005, 0.05),
    "u_sp": (0.01, 0.002, 0.1),
    "e_b": (0.95, 0.5, 1.0),
    "e_c": (0.9, 0.3, 0.98),
    "f_c": (0.2, 0.0, 0.5),
    "cushion_height": (0.037, 1.01 * CAROM.R, 1.79 * CAROM.R),
}
#: Rounds of (strike fits from the grid, constants fit with strikes refined from those).
ROUNDS = 2
#: Evaluations of the constants' objective per round (Nelder-Mead).
MAX_EVALS = 100
#: Least-squares evaluations of each shot's strike refit within one evaluation.
REFIT_NFEV = 8


def _strike_vector(f: Fitted) -> np.ndarray:
    s = f.strike
    return np.array([s["heading"], s["speed"], s["a"], s["b"], s["t0"]])


def _refit_cost(
    rec: Recording, x: np.ndarray, constants: dict[str, float], models: dict[str, Any]
) -> tuple[float, int]:
    """A shot's RMSE (recorded units, weighted as the strike fit weighs) after its strike is
    refined from x with `constants`; and the simulations it took."""
    problem = Problem.build(rec, constants, models)
    _, cost = problem.refine(x, REFIT_NFEV)
    return math.sqrt(cost / problem.samples), problem.simulations


class _Objective:
    """The constants' objective: the sum over the shots of each one's RMSE once its strike is
    refitted with them. Holding the strikes fixed instead fails: a fitted strike sits where a
    small change in the constants makes a ball miss another, so that objective jumps under the
    smallest step. The RMSE, not its square, so a few shots the engine cannot reproduce do
    not outweigh the rest."""

    def __init__(self, recs, strikes, models, pool) -> None:
        self.recs, self.strikes, self.models, self.pool = recs, strikes, models, pool
        self.simulations = 0

    def __call__(self, c: np.ndarray) -> float:
        constants = dict(zip(FITTED, (float(v) for v in c), strict=True))
        n = len(self.recs)
        args = (self.recs, self.strikes, [constants] * n, [self.models] * n)
        results = list(self.pool.map(_refit_cost, *args, chunksize=max(1, n // 8)))
        self.simulations += sum(s for _, s in results)
        return float(sum(r for r, _ in results))


def fit_shared(recs, strikes, start, models, pool) -> tuple[dict[str, float], int]:
    """The constants that best reproduce `recs`, each shot's strike refined from `strikes`
    for every candidate (Nelder-Mead from `start`, within FITTED's bounds); the simulations."""
    from scipy.optimize import minimize

    names = list(FITTED)
    bounds = [(FITTED[k][1], FITTED[k][2]) for k in names]
    objective = _Objective(recs, strikes, models, pool)
    c0 = np.array([min(max(start[k], lo), hi) for k, (lo, hi) in zip(names, bounds, strict=True)])
    simplex = [c0]
    for i, (_, hi) in enumerate(bounds):  # a step of 15% of each, away from its upper bound
        step = 0.15 * c0[i] if 1.15 * c0[i] <= hi else -0.15 * c0[i]
        simplex.append(c0 + np.eye(len(c0))[i] * step)
    res = minimize(
        objective,
        c0,
        method="Nelder-Mead",
        bounds=bounds,
        options={"maxfev": MAX_EVALS, "initial_simplex": np.array(simplex), "fatol": 1e-3},
    )
    return dict(zip(names, (float(v) for v in res.x), strict=True)), objective.simulations


def train(
    recs: Sequence[Recording], models: dict[str, Any], pool: Executor, label: str
) -> tuple[dict[str, float], int]:
    """Constants fitted on `recs`, alternating strike fits and constant fits; the
    simulations this took."""
    constants = {k: v[0] for k, v in FITTED.items()}
    sims = 0
    for r in range(ROUNDS):
        fitted = fit_all(recs, constants, models, pool)
        sims += sum(f.simulations for f in fitted)
        median = float(np.median([f.rmse_cm for f in fitted]))
        print(f"{label} round {r + 1}: median cue {median:.2f} cm", file=sys.stderr)
        strikes = [_strike_vector(f) for f in fitted]
        constants, n = fit_shared(recs, strikes, constants, models, pool)
        sims += n
        print(f"{label} constants: {_brief(constants)}", file=sys.stderr, flush=True)
    return constants, sims


def _brief(constants: dict[str, float]) -> str:
    return ", ".join(f"{k} {v:.4g}" for k, v in constants.items())


def held_out(
    recs: Sequence[Recording], models: dict[str, Any], folds: int, pool: Executor
) -> tuple[list[Fitted], list[dict[str, float]], int]:
    """Every shot fitted with constants fitted on the other folds (shot i is in fold i mod
    `folds`): the fits in shot order, each fold's constants, and the simulations run."""
    held: dict[int, Fitted] = {}
    per_fold = []
    sims = 0
    for k in range(folds):
        training = [r for i, r in enumerate(recs) if i % folds != k]
        held_out = [(i, r) for i, r in enumerate(recs) if i % folds == k]
        constants, n = train(training, models, pool, f"fold {k + 1}/{folds}")
        fitted = fit_all([r for _, r in held_out], constants, models, pool, stderr_progress)
        sims += n + sum(f.simulations for f in fitted)
        held.update({i: f for (i, _), f in zip(held_out, fitted, strict=True)})
        per_fold.append(constants)
    return [held[i] for i in range(len(recs))], per_fold, sims


def cross_validate(
    recs: Sequence[Recording],
    models: dict[str, Any],
    folds: int,
    pool: Executor,
    out: Path,
) -> dict[str, Any]:
    """Held-out figures over `folds` folds, then the constants fitted on every shot, written
    to `out`; the report has the held-out rows and each fold's constants."""
    began = time.perf_counter()
    fitted, per_fold, sims = held_out(recs, models, folds, pool)
    constants, n = train(recs, models, pool, "all shots")
    sims += n
    out.write_text(json.dumps(constants, indent=1) + "\n")
    report = summary(fitted, time.perf_counter() - began)
    report["simulations"] = sims
    report["simulations_per_second"] = sims / report["seconds"]
    report["held_out"] = f"each shot fitted with constants fitted on the other {folds - 1} folds"
    report["fold_constants"] = per_fold
    report["constants"] = constants
    return report

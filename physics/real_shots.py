"""The recorded real-table shots that ship with the engine, their fitted strikes, and the
bounded work the diagrams page's "real shots" view asks of them.

`DATA` holds the 91 recordings (physics/data/README.md says where they come from) in the
recording format of physics.recorded, gzip-compressed: 158 KB, where the plain JSON is 624 KB.
They are needed whole: a refit compares the engine with every recorded sample. `FITS` holds
each shot's strike as `billiards fit` finds it with the engine's default constants and models
(bench/real_shots.py writes it: the full search costs 3,000-4,000 simulations and over a
second of CPU a shot, too much to do when someone opens the page), so the page shows a fit at
once and a refit is a refinement from a strike within a small budget (`Bound`).

Everything here is deterministic: the same shot, strike, models and bound give the same
answer to the bit, whoever asks (a bound in CPU seconds can stop a refit at a different step
on a slower machine; `Refit.stopped` says when it did).
"""

from __future__ import annotations

import json
import math
import time
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from physics.fit import Problem, on_cue_tip, positions
from physics.recorded import Recording, load

DATA = Path(__file__).with_name("data") / "real_shots.json.gz"
FITS = Path(__file__).with_name("data") / "real_shots_fits.json"

#: The simulated tracks are sampled this often (s) for drawing, besides at every segment's
#: start (so that a rebound is drawn at its cushion, not cut across).
DRAW_STEP = 0.02
#: The strike vector's fields, in physics.fit.Problem's order.
STRIKE = ("heading", "speed", "a", "b", "t0")


@cache
def recordings() -> dict[int, Recording]:
    """Every shipped recording by its id."""
    return {rec.id: rec for rec in load(DATA)}


@cache
def fits() -> dict[str, Any]:
    """The shipped fits: {"engine_version", "models", "shots": [{"id", "strike", ...}], ...}."""
    return json.loads(FITS.read_text())


def fitted_strike(shot_id: int) -> dict[str, float]:
    """The strike `FITS` holds for a shot."""
    return next(s["strike"] for s in fits()["shots"] if s["id"] == shot_id)


@dataclass(frozen=True)
class Bound:
    """The work one refit may do: simulations (the final one that draws the answer included)
    and CPU seconds (checked before each simulation)."""

    simulations: int
    seconds: float


@dataclass(frozen=True)
class Refit:
    """A strike's fit to one recording, and what was drawn from it.

    stopped: "evaluated" (no refinement asked for, or no simulation left for one),
    "converged" (the least-squares fit ended by itself), "simulations" or "time" (the bound
    ended it: the strike is the best one evaluated).
    recorded, simulated: each ball's track as rows (t, x, y), recording time (s) and the
    engine's frame (m); the simulated one at the recorded times' span, every `DRAW_STEP` and
    every segment's start.
    """

    id: int
    cue: str
    strike: dict[str, float]
    rmse_cm: float
    rmse_all_cm: float
    simulations: int
    seconds: float
    stopped: str
    recorded: dict[str, np.ndarray]
    simulated: dict[str, np.ndarray]


class _Spent(Exception):
    """The bound is reached: `args[0]` says which part of it."""


class BoundedProblem(Problem):
    """A Problem that refuses to simulate past its bound and remembers the best strike it
    evaluated, so a fit stopped by the bound still answers its best."""

    limit: int
    deadline: float
    best: tuple[float, np.ndarray]

    def start(self, limit: int, seconds: float, x: np.ndarray) -> None:
        self.limit, self.deadline = limit, time.process_time() + seconds
        self.best = (math.inf, np.array(x, dtype=float))

    def residuals(self, x: np.ndarray) -> np.ndarray:
        if self.simulations >= self.limit:
            raise _Spent("simulations")
        if time.process_time() > self.deadline:
            raise _Spent("time")
        r = super().residuals(x)
        cost = float(r @ r)
        if cost < self.best[0]:
            self.best = (cost, np.array(x, dtype=float))
        return r


def refit(
    shot_id: int,
    strike: dict[str, float] | None,
    models: dict[str, Any],
    bound: Bound,
    refine: bool,
) -> Refit:
    """The shot simulated from `strike` (None: the shipped fit's), refined by least squares
    within `bound` when `refine`, with the engine's default constants; KeyError for an
    unknown shot."""
    began = time.process_time()
    rec = recordings()[shot_id]
    problem = BoundedProblem.build(rec, {}, models)
    x0 = np.array([(strike or fitted_strike(shot_id))[k] for k in STRIKE], dtype=float)
    problem.start(bound.simulations - 1, bound.seconds, x0)  # one kept for the answer
    stopped = "evaluated"
    if refine and bound.simulations > 1:
        try:
            problem.refine(x0, max_nfev=bound.simulations)
            stopped = "converged"
        except _Spent as spent:
            stopped = spent.args[0]
    x = problem.best[1] if math.isfinite(problem.best[0]) else x0
    segments = problem.segments(x)
    rmse, rmse_all = problem.rmse_of(problem.at_samples(segments, float(x[4])))
    heading, speed, a, b, t0 = (float(v) for v in x)
    a, b = on_cue_tip(a, b)
    heading = (heading + 180.0) % 360.0 - 180.0  # a refit may turn it past a whole turn
    return Refit(
        id=rec.id,
        cue=rec.cue,
        strike={"heading": heading, "speed": speed, "a": a, "b": b, "t0": t0},
        rmse_cm=rmse,
        rmse_all_cm=rmse_all,
        simulations=problem.simulations,
        seconds=time.process_time() - began,
        stopped=stopped,
        recorded={k: np.column_stack((tr.t, tr.xy)) for k, tr in rec.tracks.items()},
        simulated=_drawn(rec, segments, t0),
    )


def _drawn(
    rec: Recording, segments: dict[str, list[tuple]] | None, t0: float
) -> dict[str, np.ndarray]:
    """Each ball's simulated track over the recording's span (empty if the engine gave up)."""
    if segments is None:
        return {k: np.empty((0, 3)) for k in rec.tracks}
    end = max(float(tr.t[-1]) for tr in rec.tracks.values())
    grid = np.arange(0.0, end + DRAW_STEP / 2, DRAW_STEP)
    out = {}
    for k in rec.tracks:
        starts = np.array([s[0] + t0 for s in segments[k]])
        t = np.unique(np.concatenate((grid, starts[(starts > 0) & (starts < end)])))
        out[k] = np.column_stack((t, positions(segments[k], t - t0)))
    return out

"""Fitting a recorded shot: the strike that makes the engine reproduce it.

For one recording (physics.recorded) the unknowns are the strike's heading, cue speed and tip
offsets, and the moment of the strike within the recording (its first sample is not the
strike). The cue elevation stays 0: a three-cushion stroke is near level, and a few degrees
change little a tip offset cannot (docs/physics.md, "Recorded shots"). The residuals are the
differences between each recorded sample and the simulated position at the same time (exact,
from the shot's polynomial segments), in recorded units; the cue ball's count fully, the
other balls' at `OTHERS_WEIGHT`, which steers the fit towards hitting the first object ball
the way the recording does without letting them outweigh the cue ball.

The objective is piecewise smooth (it jumps where a small change makes a ball miss another),
so the fit starts scipy's `least_squares` from the best of a few tip offsets around the
kinematic guess. Everything is deterministic: the same recording, constants and models give
the same strike to the bit.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from physics.cue import MAX_SPEED, MISCUE_LIMIT
from physics.cue import strike as cue_strike
from physics.engine import Simulation, SimulationError
from physics.params import CAROM
from physics.recorded import SCALE, Recording, cue_speed, kinematic_guess
from physics.scene import Motion, Scene, parse_scene

#: Weight of the other balls' residuals against the cue ball's.
OTHERS_WEIGHT = 0.5
#: The grid of starts tried around the kinematic guess before the local fit: heading offsets
#: (degrees: the first samples give the heading to about half a degree, and a tenth of one
#: changes the cut on a ball half a table away), cue speed factors and tip offsets (a, b).
HEADINGS = tuple(0.25 * k for k in range(-4, 5))
SPEEDS = (0.9, 1.0, 1.1)
TIPS = tuple(
    (a, b)
    for b in (0.0, 0.2, -0.2, 0.4, -0.4)
    for a in (0.0, 0.2, -0.2, 0.4, -0.4)
    if math.hypot(a, b) <= MISCUE_LIMIT
)
#: How many of the best starts the local fit refines.
REFINED = 40
#: Function evaluations (simulations) of each local fit, beyond its Jacobians' own.
MAX_NFEV = 30
#: The constants that are the table's rather than the balls' and cloth's (physics.tables).
TABLE_KEYS = frozenset({"cushion_height", "w", "l"})
#: The residual of a sample when the shot could not be simulated (recorded units).
FAILED = 10.0


@dataclass
class Problem:
    """One recording against the engine with given constants and models."""

    rec: Recording
    scene: Scene
    simulations: int = 0
    weights: dict[str, float] = field(default_factory=dict)

    @classmethod
    def build(cls, rec: Recording, constants: dict[str, float], models: dict[str, Any]) -> Problem:
        """The problem on the carom table with `constants` (Params fields and the table's
        `cushion_height`) overriding its defaults, validated as a scene's would be."""
        params = {k: v for k, v in constants.items() if k not in TABLE_KEYS}
        table: dict[str, Any] = {"preset": "three_cushion"}
        table.update((k, v) for k, v in constants.items() if k in TABLE_KEYS)
        R = params.get("R", CAROM.R)
        scene = parse_scene(
            {
                "table": table,
                "params": params,
                "balls": _separated(rec.start(), R),
                "strike": {"ball": rec.cue, "speed": 1.0, "heading": 0.0},
                "models": models,
            }
        )
        weights = {k: 1.0 if k == rec.cue else OTHERS_WEIGHT for k in rec.tracks}
        return cls(rec, scene, 0, weights)

    @property
    def samples(self) -> int:
        """How many residuals: two per recorded sample."""
        return 2 * sum(len(tr.t) for tr in self.rec.tracks.values())

    def segments(self, x: np.ndarray) -> dict[str, list[tuple]] | None:
        """Each ball's segment records (physics.records) of the shot of the strike vector
        x = (heading, speed, a, b, t0), in the shot's time (the strike at 0, which is t0 in
        the recording's); None if the engine gave up."""
        heading, speed, a, b, _ = (float(v) for v in x)
        a, b = on_cue_tip(a, b)
        v, w = cue_strike(min(max(speed, 1e-3), MAX_SPEED), heading, 0.0, a, b, self.scene.params)
        scene = replace(self.scene, strike_motion=Motion.model_construct(v=v, w=w))
        self.simulations += 1
        try:
            _, trajectories, _, _, _ = Simulation(scene).run_records()
        except SimulationError:
            return None
        return trajectories

    def simulate(self, x: np.ndarray) -> dict[str, np.ndarray] | None:
        """Each ball's simulated positions at its recorded sample times (engine frame, m),
        for the strike vector x; None if the engine gave up."""
        return self.at_samples(self.segments(x), float(x[4]))

    def at_samples(
        self, trajectories: dict[str, list[tuple]] | None, t0: float
    ) -> dict[str, np.ndarray] | None:
        """The positions of `trajectories` (a shot struck at t0) at each recorded sample."""
        if trajectories is None:
            return None
        return {k: positions(trajectories[k], tr.t - t0) for k, tr in self.rec.tracks.items()}

    def residuals(self, x: np.ndarray) -> np.ndarray:
        """Weighted differences, recorded units, for every ball's every sample (x then y)."""
        sim = self.simulate(x)
        out = []
        for k, tr in self.rec.tracks.items():
            d = np.full(tr.xy.shape, FAILED) if sim is None else (sim[k] - tr.xy) * SCALE
            out.append(self.weights[k] * d.ravel())
        return np.concatenate(out)

    def refine(self, x: np.ndarray, max_nfev: int) -> tuple[np.ndarray, float]:
        """A local least-squares fit from strike x (heading within 30 degrees of x's, the
        strike before the cue ball's second sample); the strike and its sum of squares."""
        from scipy.optimize import least_squares

        t = self.rec.tracks[self.rec.cue].t
        t_first = max(float(t[min(1, len(t) - 1)]), 1e-3)
        lower = [x[0] - 30, 0.05, -MISCUE_LIMIT, -MISCUE_LIMIT, 0.0]
        upper = [x[0] + 30, MAX_SPEED, MISCUE_LIMIT, MISCUE_LIMIT, t_first]
        res = least_squares(
            self.residuals,
            np.clip(x, lower, upper),
            bounds=(lower, upper),
            x_scale=np.array([0.2, 0.05, 0.05, 0.05, 0.005]),
            diff_step=1e-4,
            max_nfev=max_nfev,
        )
        return res.x, 2 * float(res.cost)

    def rmse_cm(self, x: np.ndarray) -> tuple[float, float]:
        """Cue-ball and all-balls RMSE (cm, recorded units) of strike x."""
        return self.rmse_of(self.simulate(x))

    def rmse_of(self, sim: dict[str, np.ndarray] | None) -> tuple[float, float]:
        """Cue-ball and all-balls RMSE (cm, recorded units) of simulated sample positions."""
        sq = {}
        for k, tr in self.rec.tracks.items():
            d = np.full(tr.xy.shape, FAILED) if sim is None else (sim[k] - tr.xy) * SCALE
            sq[k] = (d * d).sum(axis=1)
        every = np.concatenate(list(sq.values()))
        return 100 * math.sqrt(sq[self.rec.cue].mean()), 100 * math.sqrt(every.mean())


def positions(segments: list[tuple], t: np.ndarray) -> np.ndarray:
    """A ball's positions at times t from its segment records (physics.records): the last
    segment starting at or before each time, its polynomial evaluated; before 0, the start."""
    seg = np.array([(s[0], *s[2:8]) for s in segments])
    k = np.clip(np.searchsorted(seg[:, 0], t, side="right") - 1, 0, len(seg) - 1)
    tau = np.maximum(t - seg[k, 0], 0.0)[:, None]
    return seg[k, 1:3] + seg[k, 3:5] * tau + 0.5 * seg[k, 5:7] * tau * tau


def on_cue_tip(a: float, b: float) -> tuple[float, float]:
    """The tip offset pulled back just inside the miscue limit when beyond it."""
    r = math.hypot(a, b)
    if r <= MISCUE_LIMIT:
        return a, b
    k = MISCUE_LIMIT * (1.0 - 1e-9) / r  # rounding must not carry it past the limit
    return a * k, b * k


def _separated(start: dict[str, tuple[float, float]], R: float) -> dict[str, list[float]]:
    """Recorded start positions made a valid scene: each centre at least R from the cushions,
    and two balls the tracker placed overlapping pushed apart along their line of centres."""
    from physics.tables import THREE_CUSHION as T

    pos = {k: [min(max(x, R), T.w - R), min(max(y, R), T.l - R)] for k, (x, y) in start.items()}
    names = sorted(pos)
    for i, p in enumerate(names):
        for q in names[i + 1 :]:
            (xa, ya), (xb, yb) = pos[p], pos[q]
            d = math.hypot(xb - xa, yb - ya)
            if d < 2 * R + 1e-6:
                ux, uy = ((xb - xa) / d, (yb - ya) / d) if d > 0 else (1.0, 0.0)
                push = (2 * R + 1e-6 - d) / 2
                pos[p] = [xa - ux * push, ya - uy * push]
                pos[q] = [xb + ux * push, yb + uy * push]
    return pos


@dataclass(frozen=True)
class Fitted:
    """The result of fitting one recording."""

    id: int
    strike: dict[str, float]
    rmse_cm: float
    rmse_all_cm: float
    guess_rmse_cm: float
    simulations: int
    seconds: float

    def row(self) -> dict[str, Any]:
        """The shot's entry of `billiards fit --json`."""
        return {
            "id": self.id,
            "rmse_cm": self.rmse_cm,
            "rmse_all_cm": self.rmse_all_cm,
            "strike": self.strike,
            "simulations": self.simulations,
            "seconds": self.seconds,
            "kinematic_rmse_cm": self.guess_rmse_cm,
        }


def fit_shot(
    rec: Recording, constants: dict[str, float], models: dict[str, Any], max_nfev: int = MAX_NFEV
) -> Fitted:
    """The strike that best reproduces `rec`: the best of `STARTS` around the kinematic
    guess, refined by least squares."""
    began = time.process_time()
    problem = Problem.build(rec, constants, models)
    params = problem.scene.params
    g = kinematic_guess(rec)
    x0 = np.array([g.heading, cue_speed(g.speed, params), 0.0, 0.0, g.t0])
    guess_rmse = problem.rmse_cm(x0)[0]
    starts = [
        np.array([x0[0] + dh, x0[1] * f, a, b, x0[4]])
        for dh in HEADINGS
        for f in SPEEDS
        for a, b in TIPS
    ]
    costs = [float(np.sum(problem.residuals(x) ** 2)) for x in starts]
    order = sorted(range(len(starts)), key=lambda i: (costs[i], i))[:REFINED]
    best_x, best_cost = starts[order[0]], costs[order[0]]
    for i in order:
        x, cost = problem.refine(starts[i], max_nfev)
        if cost < best_cost:
            best_x, best_cost = x, cost
    rmse, rmse_all = problem.rmse_cm(best_x)
    heading, speed, a, b, t0 = (float(v) for v in best_x)
    a, b = on_cue_tip(a, b)
    strike = {"heading": heading, "speed": speed, "elevation": 0.0, "a": a, "b": b, "t0": t0}
    seconds = time.process_time() - began
    return Fitted(rec.id, strike, rmse, rmse_all, guess_rmse, problem.simulations, seconds)

"""Reading a Shot back the way a client would: positions and energies from the segments alone."""

from __future__ import annotations

import numpy as np

from physics import Shot, parse_scene
from physics.engine import Simulation


def positions(shot: Shot, ts: np.ndarray) -> dict[str, np.ndarray]:
    """Each ball's centre at every time in ts (NaN once pocketed), from its segments."""
    out = {}
    for name, segs in shot.trajectories.items():
        pos = np.full((len(ts), 2), np.nan)
        starts = np.array([s.t for s in segs])
        idx = np.searchsorted(starts, ts, side="right") - 1
        for k, s in enumerate(segs):
            mask = idx == k
            if s.state == "pocketed" or not mask.any():
                continue
            tau = ts[mask] - s.t
            for axis in (0, 1):
                pos[mask, axis] = s.r[axis] + s.v[axis] * tau + 0.5 * s.a[axis] * tau**2
        out[name] = pos
    return out


def sample_times(shot: Shot, step: float = 1e-3) -> np.ndarray:
    """A uniform grid plus every event time, where contacts happen."""
    grid = np.arange(0.0, shot.duration + step, step)
    return np.unique(np.concatenate([grid, [e.t for e in shot.events]]))


def max_overlap(shot: Shot, R: float, ts: np.ndarray | None = None) -> float:
    """The deepest interpenetration of any two balls over the sampled times (m)."""
    pos = positions(shot, sample_times(shot) if ts is None else ts)
    names = list(pos)
    worst = 0.0
    for a in range(len(names)):
        for b in range(a + 1, len(names)):
            d = np.linalg.norm(pos[names[a]] - pos[names[b]], axis=1)
            if np.any(~np.isnan(d)):
                worst = max(worst, 2 * R - float(np.nanmin(d)))
    return worst


class _Metered(Simulation):
    """The engine with an energy meter on every event handler (test instrumentation)."""

    def __init__(self, scene) -> None:
        super().__init__(scene)
        self.steps: list[tuple[str, float, float]] = []

    def _energy(self) -> float:
        p = self.p
        inertia = 0.4 * p.m * p.R**2
        total = 0.0
        for b in self.balls:
            if b.state == "pocketed":
                continue
            _, _, vx, vy = b.at(self.now)
            dt = self.now - b.t0
            w = [b.w[k] + b.dw[k] * dt for k in range(3)]
            total += 0.5 * p.m * (vx * vx + vy * vy) + 0.5 * inertia * sum(x * x for x in w)
        return total

    def _metered(self, name: str, *args, **kwargs) -> None:
        before = self._energy()
        getattr(super(), name)(*args, **kwargs)
        self.steps.append((name, before, self._energy()))

    def _collide_balls(self, *args) -> None:
        self._metered("_collide_balls", *args)

    def _collide_cushion(self, *args, **names) -> None:
        self._metered("_collide_cushion", *args, **names)

    def _transition(self, *args) -> None:
        self._metered("_transition", *args)

    def _spin_stop(self, *args) -> None:
        self._metered("_spin_stop", *args)

    def _pocket(self, *args) -> None:
        self._metered("_pocket", *args)


def energy_steps(scene: dict) -> list[tuple[str, float, float]]:
    """(handler, energy before, energy after) for every event of the shot."""
    sim = _Metered(parse_scene(scene))
    sim.run()
    return sim.steps

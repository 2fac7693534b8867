"""A fixed-step reference integrator: how browser billiards engines simulate a shot.

Every step of length dt: the forces of Han 2005 (with ERRATA.md items 1-3, as in
physics.motion) change each ball's velocity and spin (semi-implicit Euler: velocities first,
then positions with the new velocities); a ball whose next position would touch another ball,
a cushion or a jaw while approaching it is resolved there with the same collision models the
event engine uses (physics.ball_ball, physics.cushion); a ball whose centre enters a pocket's
capture circle drops. A frame of a browser engine is a handful of such steps ("substeps"); dt
here is the substep. The method exists to be measured against the event engine (see
bench/accuracy.py): its error comes from the collisions being found up to a step late and
from the slide ending within a step, and shrinks roughly in proportion to dt.

The balls are held in numpy arrays so that a step costs the same few array operations however
many balls move.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from physics.ball_ball import BALL_BALL_MODELS
from physics.cushion import CUSHION_MODELS
from physics.motion import EPS_SLIP
from physics.scene import Scene, parse_scene

#: Simulated time after which a shot is abandoned (s): far beyond any shot's length.
MAX_TIME = 120.0


def simulate_fixed(scene: Scene | dict[str, Any], dt: float) -> dict[str, Any]:
    """Simulate a shot in steps of dt seconds; returns the shape of physics.simulate_scene's
    summary: {"final": {ball: {"pos", "state", "pocket"}}, "duration", "models", "steps"}.
    """
    if not (math.isfinite(dt) and 1e-7 <= dt <= 0.01):
        raise ValueError(f"dt must be between 1e-7 and 0.01 s, got {dt}")
    if not isinstance(scene, Scene):
        scene = parse_scene(scene)
    return _Run(scene, dt).run()


class _Run:
    def __init__(self, scene: Scene, dt: float) -> None:
        p = scene.params
        self.scene, self.p, self.dt = scene, p, dt
        self.spin = scene.models.spin
        self.ball_ball = BALL_BALL_MODELS[scene.models.ball_ball if self.spin else "frictionless"]
        self.cushion = CUSHION_MODELS[scene.models.cushion]
        self.names = list(scene.positions)
        n = len(self.names)
        self.x = np.array([scene.positions[k] for k in self.names], dtype=float)
        self.v = np.zeros((n, 2))
        self.w = np.zeros((n, 3))
        self.alive = np.ones(n, dtype=bool)
        self.pocket: list[str | None] = [None] * n
        starts = dict(scene.initial)
        if scene.strike is not None and scene.strike_motion is not None:
            starts[scene.strike.ball] = scene.strike_motion
        for name, m in starts.items():
            k = self.names.index(name)
            self.v[k] = m.v
            self.w[k] = m.w if self.spin else self._rolling(m.v, 0.0)
        g = scene.geometry
        self.segments, self.jaws, self.pockets = g.segments, g.jaws, g.pockets
        self.seg_p1 = np.array([s.p1 for s in g.segments], dtype=float)
        self.seg_n = np.array([s.normal for s in g.segments], dtype=float)
        # Along-segment direction scaled so that the projection runs from 0 to 1.
        tangent = np.array([s.p2 for s in g.segments], dtype=float) - self.seg_p1
        self.seg_t = tangent / (tangent**2).sum(axis=1)[:, None]
        self.jaw_c = np.array([j.center for j in g.jaws], dtype=float).reshape(-1, 2)
        self.jaw_r = np.array([j.radius for j in g.jaws], dtype=float)

    def _rolling(self, v, wz: float) -> tuple[float, float, float]:
        R = self.p.R
        return (-v[1] / R, v[0] / R, wz)

    # -- forces --------------------------------------------------------------------------

    def _forces(self) -> None:
        """One semi-implicit Euler update of velocities and spins (Han 2005, ERRATA 1-3).

        A slip that friction would cancel within the step ends the slide exactly there
        (v loses 2/7 of the slip, the ball rolls); a roll or a spin about the vertical that
        would reverse stops at zero.
        """
        p, dt, R = self.p, self.dt, self.p.R
        v, w = self.v, self.w
        ux = v[:, 0] - R * w[:, 1]
        uy = v[:, 1] + R * w[:, 0]
        slip = np.hypot(ux, uy)
        slide_step = 3.5 * p.u_s * p.g * dt
        sliding = slip > slide_step
        ending = (slip > EPS_SLIP) & ~sliding
        if ending.any():  # the slide ends within this step
            v[ending, 0] -= ux[ending] / 3.5
            v[ending, 1] -= uy[ending] / 3.5
            w[ending, 0] = -v[ending, 1] / R
            w[ending, 1] = v[ending, 0] / R
        if sliding.any():
            k = p.u_s * p.g * dt / slip[sliding]
            ex, ey = ux[sliding] * k, uy[sliding] * k
            v[sliding, 0] -= ex
            v[sliding, 1] -= ey
            w[sliding, 0] -= 2.5 * ey / R
            w[sliding, 1] += 2.5 * ex / R
        rolling = ~sliding & ~ending
        speed = np.hypot(v[:, 0], v[:, 1])
        roll_step = p.u_r * p.g * dt
        stops = rolling & (speed <= roll_step) & (speed > 0.0)
        v[stops] = 0.0
        rolls = rolling & (speed > roll_step)
        if rolls.any():
            k = 1.0 - roll_step / speed[rolls]
            v[rolls] *= k[:, None]
        w[rolling, 0] = -v[rolling, 1] / R
        w[rolling, 1] = v[rolling, 0] / R
        spin_step = 2.5 * p.u_sp * p.g / R * dt
        wz = w[:, 2]
        w[:, 2] = np.where(np.abs(wz) <= spin_step, 0.0, wz - np.sign(wz) * spin_step)

    # -- collisions ----------------------------------------------------------------------

    def _collide(self) -> None:
        """Resolve the contacts the next position step would make: ball pairs in index order,
        then each ball's cushions and jaws. The candidates are found with array operations."""
        dt, R = self.dt, self.p.R
        moving = self.alive & (np.abs(self.v).sum(axis=1) > 0.0)
        if not moving.any():
            return
        nxt = self.x + self.v * dt
        d = nxt[:, None, :] - nxt[None, :, :]
        close = (d[..., 0] ** 2 + d[..., 1] ** 2) < (2.0 * R) ** 2
        close &= self.alive[:, None] & self.alive[None, :]
        close &= moving[:, None] | moving[None, :]
        for i, j in zip(*np.nonzero(np.triu(close, 1)), strict=True):
            self._ball_ball(int(i), int(j))
        nxt = self.x + self.v * dt
        rel = nxt[:, None, :] - self.seg_p1[None, :, :]
        depth = (rel * self.seg_n).sum(axis=2)
        along = (rel * self.seg_t).sum(axis=2)
        into = self.v @ self.seg_n.T < 0.0
        hits = moving[:, None] & into & (depth < R) & (along >= 0.0) & (along <= 1.0)
        for i, k in zip(*np.nonzero(hits), strict=True):
            n = self.segments[k].normal
            if self.v[i, 0] * n[0] + self.v[i, 1] * n[1] < 0.0:  # not already bounced
                self._bounce(int(i), n)
        if not len(self.jaws):
            return
        nxt = self.x + self.v * dt
        near = np.hypot(*(nxt[:, None, :] - self.jaw_c[None, :, :]).transpose(2, 0, 1))
        for i, k in zip(*np.nonzero(moving[:, None] & (near < self.jaw_r + R)), strict=True):
            n = self.x[i] - self.jaw_c[k]
            n = n / math.hypot(*n)
            if self.v[i, 0] * n[0] + self.v[i, 1] * n[1] < 0.0:
                self._bounce(int(i), (float(n[0]), float(n[1])))

    def _ball_ball(self, i: int, j: int) -> None:
        dx, dy = self.x[j] - self.x[i]
        dist = math.hypot(dx, dy)
        n = (dx / dist, dy / dist)
        va, wa, vb, wb = self.ball_ball(
            tuple(self.v[i]), tuple(self.w[i]), tuple(self.v[j]), tuple(self.w[j]), n, self.p
        )
        self._set(i, va, wa)
        self._set(j, vb, wb)

    def _set(self, i: int, v, w) -> None:
        self.v[i] = v
        self.w[i] = w if self.spin else self._rolling(v, 0.0)

    def _bounce(self, i: int, normal: tuple[float, float]) -> None:
        v, w = tuple(self.v[i]), tuple(self.w[i])
        if self.spin:
            v, w = self.cushion(v, w, normal, self.p, self.scene.sin_theta)
        else:
            k = (1.0 + self.p.e_c) * (v[0] * normal[0] + v[1] * normal[1])
            v = (v[0] - k * normal[0], v[1] - k * normal[1])
        self._set(i, v, w)

    def _drop(self) -> None:
        for pocket in self.pockets:
            d = np.hypot(self.x[:, 0] - pocket.center[0], self.x[:, 1] - pocket.center[1])
            for i in np.nonzero(self.alive & (d < pocket.radius))[0]:
                self.alive[i] = False
                self.pocket[i] = pocket.name
                self.v[i] = 0.0
                self.w[i] = 0.0

    # -- the loop ------------------------------------------------------------------------

    def run(self) -> dict[str, Any]:
        dt = self.dt
        steps = 0
        t = 0.0
        last_motion = 0.0
        while t < MAX_TIME:
            self._forces()
            self._collide()
            self.x += self.v * dt
            self._drop()
            steps += 1
            t = steps * dt
            if np.abs(self.v[self.alive]).sum() > 0.0:
                last_motion = t
            else:
                break
        final = {}
        for k, name in enumerate(self.names):
            if not self.alive[k]:
                final[name] = {"pos": None, "state": "pocketed", "pocket": self.pocket[k]}
            else:
                state = "spinning" if abs(self.w[k, 2]) > 0.0 else "stationary"
                final[name] = {"pos": tuple(map(float, self.x[k])), "state": state, "pocket": None}
        return {
            "final": final,
            "duration": last_motion,
            "steps": steps,
            "models": {
                "ball_ball": self.scene.models.ball_ball,
                "cushion": self.scene.models.cushion,
                "spin": self.spin,
                "cushion_height": self.scene.geometry.spec.cushion_height,
            },
        }

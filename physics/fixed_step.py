"""A fixed-step reference integrator: how browser billiards engines simulate a shot.

Every step of length dt: the forces of Han 2005 (with docs/physics.md's corrections 1-3,
as in physics.motion) change each ball's velocity and spin (semi-implicit Euler: velocities first,
then positions with the new velocities); a ball whose next position would touch another ball,
a cushion or a jaw while approaching it is resolved there with the same collision models the
event engine uses (physics.ball_ball, physics.cushion); a ball whose centre enters a pocket's
capture circle drops. A frame of a browser engine is a handful of such steps ("substeps"); dt
here is the substep. The method exists to be measured against the event engine (see
bench/accuracy.py): its error comes from collisions being found up to a step late and slides
ending within a step, and shrinks roughly in proportion to dt.

Only moving balls do work in a step, and a ball looks for cushions and jaws only when its next
position is within a ball's radius of the table's edge, so a step costs a few microseconds
per moving ball.
"""

from __future__ import annotations

import math
from typing import Any

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


class _Ball:
    __slots__ = ("name", "pocket", "vx", "vy", "w", "x", "y")

    def __init__(self, name: str, x: float, y: float) -> None:
        self.name = name
        self.x, self.y = x, y
        self.vx = self.vy = 0.0
        self.w = (0.0, 0.0, 0.0)
        self.pocket: str | None = None


class _Run:
    def __init__(self, scene: Scene, dt: float) -> None:
        p = scene.params
        self.scene, self.p, self.dt = scene, p, dt
        self.spin = scene.models.spin
        self.ball_ball = BALL_BALL_MODELS[scene.models.ball_ball if self.spin else "frictionless"]
        self.cushion = CUSHION_MODELS[scene.models.cushion]
        self.balls = [_Ball(k, x, y) for k, (x, y) in scene.positions.items()]
        starts = dict(scene.initial)
        if scene.strike is not None and scene.strike_motion is not None:
            starts[scene.strike.ball] = scene.strike_motion
        for b in self.balls:
            if b.name in starts:
                self._set(b, starts[b.name].v, starts[b.name].w)
        self.geometry = scene.geometry
        spec = scene.geometry.spec
        # Beyond these the next position is near enough to an edge to look for cushions/jaws.
        margin = p.R + max((j.radius for j in scene.geometry.jaws), default=0.0) * 2.0
        self.inner = (margin, spec.w - margin, margin, spec.l - margin)

    def _set(self, b: _Ball, v, w) -> None:
        b.vx, b.vy = v
        b.w = tuple(w) if self.spin else (-v[1] / self.p.R, v[0] / self.p.R, 0.0)

    # -- forces --------------------------------------------------------------------------

    def _forces(self, b: _Ball) -> None:
        """One semi-implicit Euler update of b's velocity and spin (Han 2005 with
        docs/physics.md's corrections 1-3).

        A slip that friction would cancel within the step ends the slide exactly there
        (v loses 2/7 of the slip, the ball rolls); a roll or a spin about the vertical that
        would reverse stops at zero.
        """
        p, dt, R = self.p, self.dt, self.p.R
        wx, wy, wz = b.w
        ux, uy = b.vx - R * wy, b.vy + R * wx
        slip = math.hypot(ux, uy)
        if slip > 3.5 * p.u_s * p.g * dt:
            k = p.u_s * p.g * dt / slip
            b.vx -= k * ux
            b.vy -= k * uy
            wx -= 2.5 * k * uy / R
            wy += 2.5 * k * ux / R
        else:
            if slip > EPS_SLIP:  # the slide ends within this step
                b.vx -= ux / 3.5
                b.vy -= uy / 3.5
            speed = math.hypot(b.vx, b.vy)
            step = p.u_r * p.g * dt
            if speed <= step:
                b.vx = b.vy = 0.0
            else:
                b.vx *= 1.0 - step / speed
                b.vy *= 1.0 - step / speed
            wx, wy = -b.vy / R, b.vx / R
        spin_step = 2.5 * p.u_sp * p.g / R * dt
        wz = 0.0 if abs(wz) <= spin_step else wz - math.copysign(spin_step, wz)
        b.w = (wx, wy, wz)

    # -- collisions ----------------------------------------------------------------------

    def _collide(self, moving: list[_Ball], on_table: list[_Ball]) -> None:
        """Resolve the contacts the next position step would make: each moving ball with
        every other ball (each pair once), then its cushions and jaws."""
        dt, D2 = self.dt, (2.0 * self.p.R) ** 2
        done = set()
        for a in moving:
            done.add(a.name)
            for b in on_table:
                if b.name in done:
                    continue
                dx = (b.x + b.vx * dt) - (a.x + a.vx * dt)
                dy = (b.y + b.vy * dt) - (a.y + a.vy * dt)
                if dx * dx + dy * dy < D2:
                    self._ball_ball(a, b)
        x0, x1, y0, y1 = self.inner
        for a in moving:
            fx, fy = a.x + a.vx * dt, a.y + a.vy * dt
            if not (x0 < fx < x1 and y0 < fy < y1):
                self._table(a, fx, fy)

    def _ball_ball(self, a: _Ball, b: _Ball) -> None:
        dx, dy = b.x - a.x, b.y - a.y
        dist = math.hypot(dx, dy)
        n = (dx / dist, dy / dist)
        va, wa, vb, wb = self.ball_ball((a.vx, a.vy), a.w, (b.vx, b.vy), b.w, n, self.p)
        self._set(a, va, wa)
        self._set(b, vb, wb)

    def _table(self, b: _Ball, fx: float, fy: float) -> None:
        R = self.p.R
        for seg in self.geometry.segments:
            nx, ny = seg.normal
            if b.vx * nx + b.vy * ny >= 0.0:
                continue
            if (fx - seg.p1[0]) * nx + (fy - seg.p1[1]) * ny >= R:
                continue
            tx, ty = seg.p2[0] - seg.p1[0], seg.p2[1] - seg.p1[1]
            s = ((fx - seg.p1[0]) * tx + (fy - seg.p1[1]) * ty) / (tx * tx + ty * ty)
            if 0.0 <= s <= 1.0:
                self._bounce(b, (nx, ny))
        for jaw in self.geometry.jaws:
            cx, cy = jaw.center
            if math.hypot(fx - cx, fy - cy) < jaw.radius + R:
                nx, ny = b.x - cx, b.y - cy
                norm = math.hypot(nx, ny)
                if b.vx * nx + b.vy * ny < 0.0:
                    self._bounce(b, (nx / norm, ny / norm))

    def _bounce(self, b: _Ball, normal: tuple[float, float]) -> None:
        v = (b.vx, b.vy)
        if self.spin:
            v, w = self.cushion(v, b.w, normal, self.p, self.scene.sin_theta)
        else:
            k = (1.0 + self.p.e_c) * (v[0] * normal[0] + v[1] * normal[1])
            v, w = (v[0] - k * normal[0], v[1] - k * normal[1]), b.w
        self._set(b, v, w)

    def _drop(self, b: _Ball) -> bool:
        for pocket in self.geometry.pockets:
            if math.hypot(b.x - pocket.center[0], b.y - pocket.center[1]) < pocket.radius:
                b.pocket = pocket.name
                b.vx = b.vy = 0.0
                b.w = (0.0, 0.0, 0.0)
                return True
        return False

    # -- the loop ------------------------------------------------------------------------

    def run(self) -> dict[str, Any]:
        dt = self.dt
        on_table = list(self.balls)
        steps = 0
        while steps * dt < MAX_TIME:
            for b in on_table:
                wx, wy, wz = b.w
                if b.vx or b.vy or wx or wy:
                    self._forces(b)
                elif wz:
                    self._forces(b)  # spinning in place: only w_z changes
            moving = [b for b in on_table if b.vx or b.vy]
            if not moving:
                break
            self._collide(moving, on_table)
            for b in moving:
                b.x += b.vx * dt
                b.y += b.vy * dt
            if self.geometry.pockets and any(self._drop(b) for b in moving):
                on_table = [b for b in on_table if b.pocket is None]
            steps += 1
        final = {}
        for b in self.balls:
            if b.pocket is not None:
                final[b.name] = {"pos": None, "state": "pocketed", "pocket": b.pocket}
            else:
                state = "spinning" if b.w[2] else "stationary"
                final[b.name] = {"pos": (b.x, b.y), "state": state, "pocket": None}
        return {
            "final": final,
            "duration": steps * dt,
            "steps": steps,
            "models": {
                "ball_ball": self.scene.models.ball_ball,
                "cushion": self.scene.models.cushion,
                "spin": self.spin,
                "cushion_height": self.scene.geometry.spec.cushion_height,
            },
        }

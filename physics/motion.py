"""Closed-form ball motion between events (Han 2005, with docs/physics.md's corrections 1-3).

In every state the acceleration and the angular acceleration are constant, so between events
a ball moves on a parabola and its spin changes linearly:

- sliding: the cloth contact point slips with u = v + R k x w; friction -u_s g u_hat acts on
  the centre and (5 u_s g / 2R) k x u_hat on the spin. u keeps its direction and shrinks at
  7/2 u_s g, so the slide ends after 2|u| / (7 u_s g): then the ball rolls.
- rolling: v decelerates at u_r g along -v_hat, the spin follows (w_xy = k x v / R), and the
  ball stops after |v| / (u_r g).
- spinning: in place, only the spin about the vertical is left.
- about the vertical, in every state: dw_z/dt = -5/2 u_sp g / R until w_z is zero.
"""

from __future__ import annotations

import math

from physics.params import Params

SLIDING = "sliding"
ROLLING = "rolling"
SPINNING = "spinning"
STATIONARY = "stationary"
POCKETED = "pocketed"

#: Below these a slip (m/s), a speed (m/s) or a spin about the vertical (rad/s) counts as zero.
EPS_SLIP = 1e-10
EPS_SPEED = 1e-10
EPS_SPIN = 1e-9


class Constants:
    """The constants of a ball's motion, read once per shot from its Params: the kernel reads
    these as C doubles (physics/motion.pxd), where each read of a Params attribute is a Python
    attribute lookup."""

    __slots__ = ("R", "g", "spin_decel", "u_r", "u_s")

    def __init__(self, p: Params) -> None:
        self.R, self.g, self.u_s, self.u_r = p.R, p.g, p.u_s, p.u_r
        #: |dw_z/dt| (rad/s^2) from the spin friction u_sp (docs/physics.md, correction 3).
        self.spin_decel = 2.5 * p.u_sp * p.g / p.R


def slip(v: tuple[float, float], w: tuple[float, float, float], R: float) -> tuple[float, float]:
    """Velocity of the cloth contact point: v + R k x w."""
    return (v[0] - R * w[1], v[1] + R * w[0])


def classify(v: tuple[float, float], w: tuple[float, float, float], consts: Constants) -> str:
    """The state a ball with this v and w is in."""
    ux, uy = slip(v, w, consts.R)
    eps = EPS_SLIP  # (typed locals keep the kernel's comparisons in C)
    if math.hypot(ux, uy) > eps:
        return SLIDING
    eps = EPS_SPEED
    if math.hypot(v[0], v[1]) > eps:
        return ROLLING
    wz, eps = w[2], EPS_SPIN
    if abs(wz) > eps:
        return SPINNING
    return STATIONARY


def rolling_spin(v: tuple[float, float], wz: float, R: float) -> tuple[float, float, float]:
    """The spin of a ball rolling without slip at velocity v."""
    return (-v[1] / R, v[0] / R, wz)


def accelerations(
    state: str, v: tuple[float, float], w: tuple[float, float, float], consts: Constants
) -> tuple[float, float, float, float, float]:
    """(a_x, a_y, dw_x/dt, dw_y/dt, dw_z/dt) of a ball in `state`; constant until its next
    event. (Flat, not two vectors: the kernel returns them as C doubles.)"""
    wz, eps = w[2], EPS_SPIN  # (typed locals keep the kernel's arithmetic in C)
    wz_rate = -math.copysign(consts.spin_decel, wz) if abs(wz) > eps else 0.0
    R, g = consts.R, consts.g
    if state == SLIDING:
        ux, uy = slip(v, w, R)
        s = math.hypot(ux, uy)
        f = consts.u_s * g / s
        kw = 2.5 * f / R
        return -f * ux, -f * uy, -kw * uy, kw * ux, wz_rate
    if state == ROLLING:
        vx, vy = v
        s = math.hypot(vx, vy)
        f = consts.u_r * g / s
        ax, ay = -f * vx, -f * vy
        return ax, ay, -ay / R, ax / R, wz_rate
    if state == SPINNING:
        return 0.0, 0.0, 0.0, 0.0, wz_rate
    return 0.0, 0.0, 0.0, 0.0, 0.0


def transition_time(
    state: str, v: tuple[float, float], w: tuple[float, float, float], consts: Constants
) -> float:
    """Time from now until the state changes (inf for a ball at rest)."""
    if state == SLIDING:
        ux, uy = slip(v, w, consts.R)
        return 2.0 * math.hypot(ux, uy) / (7.0 * consts.u_s * consts.g)
    if state == ROLLING:
        return math.hypot(v[0], v[1]) / (consts.u_r * consts.g)
    if state == SPINNING:
        wz = w[2]
        return abs(wz) / consts.spin_decel
    return math.inf


def spin_stop_time(w: tuple[float, float, float], consts: Constants) -> float:
    """Time from now until the spin about the vertical reaches zero."""
    wz, eps = w[2], EPS_SPIN  # (typed locals keep the kernel's arithmetic in C)
    return abs(wz) / consts.spin_decel if abs(wz) > eps else math.inf

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


def spin_decel(p: Params) -> float:
    """|dw_z/dt| (rad/s^2) from the spin friction u_sp (docs/physics.md, correction 3)."""
    u_sp, g, R = p.u_sp, p.g, p.R  # (typed locals keep the kernel's arithmetic in C)
    return 2.5 * u_sp * g / R


def slip(v: tuple[float, float], w: tuple[float, float, float], R: float) -> tuple[float, float]:
    """Velocity of the cloth contact point: v + R k x w."""
    return (v[0] - R * w[1], v[1] + R * w[0])


def classify(v: tuple[float, float], w: tuple[float, float, float], p: Params) -> str:
    """The state a ball with this v and w is in."""
    ux, uy = slip(v, w, p.R)
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
    state: str, v: tuple[float, float], w: tuple[float, float, float], p: Params
) -> tuple[tuple[float, float], tuple[float, float, float]]:
    """(a, dw/dt) of a ball in `state`; constant until its next event."""
    wz, eps = w[2], EPS_SPIN  # (typed locals keep the kernel's arithmetic in C)
    wz_rate = -math.copysign(spin_decel(p), wz) if abs(wz) > eps else 0.0
    R, g = p.R, p.g
    if state == SLIDING:
        ux, uy = slip(v, w, R)
        s = math.hypot(ux, uy)
        u_s = p.u_s
        f = u_s * g / s
        k = 2.5 * f / R
        return (-f * ux, -f * uy), (-k * uy, k * ux, wz_rate)
    if state == ROLLING:
        vx, vy = v
        s = math.hypot(vx, vy)
        u_r = p.u_r
        f = u_r * g / s
        ax, ay = -f * vx, -f * vy
        return (ax, ay), (-ay / R, ax / R, wz_rate)
    if state == SPINNING:
        return (0.0, 0.0), (0.0, 0.0, wz_rate)
    return (0.0, 0.0), (0.0, 0.0, 0.0)


def transition_time(
    state: str, v: tuple[float, float], w: tuple[float, float, float], p: Params
) -> float:
    """Time from now until the state changes (inf for a ball at rest)."""
    if state == SLIDING:
        ux, uy = slip(v, w, p.R)
        u_s, g = p.u_s, p.g  # (typed locals keep the kernel's arithmetic in C)
        return 2.0 * math.hypot(ux, uy) / (7.0 * u_s * g)
    if state == ROLLING:
        u_r, g = p.u_r, p.g
        return math.hypot(v[0], v[1]) / (u_r * g)
    if state == SPINNING:
        wz = w[2]
        return abs(wz) / spin_decel(p)
    return math.inf


def spin_stop_time(w: tuple[float, float, float], p: Params) -> float:
    """Time from now until the spin about the vertical reaches zero."""
    wz, eps = w[2], EPS_SPIN  # (typed locals keep the kernel's arithmetic in C)
    return abs(wz) / spin_decel(p) if abs(wz) > eps else math.inf

"""Families of shots for the diagrams page: rebounds off a cushion, throws off an object ball,
and the figures of Mathavan et al. 2010, all computed by the engine (the page draws them).

A family is a handful of shots on the carom table (its defaults: physics.params.CAROM, the
`three_cushion` table) that differ in one thing: the incidence, the spin or the cut. Each shot
is a ball *arriving* at its contact (the right-hand long cushion, or the object ball) in a given
state: a speed, a direction, topspin `top` and side spin `side` as multiples of v / R (top 1 is
natural roll, 0 a stun ball, -1 as much draw). The ball is placed `GAP` short of the contact with
that state and the engine plays the shot on; the approach before it is drawn as the straight
line the ball came along, which is exact: top, back and side spin make no slip across the
ball's path, so an arriving ball does not curve. A track ends at the ball's next cushion
(`TRACK_SECONDS` at most), where the rebound it shows is over.

Signs in this frame (x across the table, y up it; the cushion is x = w, its normal -x; the
ball arrives moving +x and up): running side (positive `side` in a cushion family) is
clockwise seen from above (w_z < 0), the side that turns the cushion's friction into speed
along the cushion and widens the rebound; check side the other. In a throw family the cue ball
moves +y and the cut sends the object ball to the right (+x); outside side (positive) is the
side that takes slip out of the contact (w_z < 0) and throws the object ball less.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from physics.cushion import CUSHION_MODELS
from physics.engine import Simulation
from physics.fit import positions
from physics.params import CAROM, SNOOKER, Params
from physics.scene import parse_scene
from physics.tables import THREE_CUSHION

#: How far short of its contact an arriving ball is placed (m).
GAP = 1e-3
#: The drawn approach: this long (m) before the ball's start.
APPROACH = 0.35
#: Tracks are sampled this often (s), besides at every segment's start.
STEP = 0.02
#: The longest track drawn (s).
TRACK_SECONDS = 4.0
#: Digits of the coordinates answered (1 mm).
DIGITS = 3

#: The incidences (degrees from the normal) of the cushion families that vary them.
INCIDENCES = (0, 15, 30, 45, 60, 75)
#: The side spins (multiples of v / R) of the families that vary them.
SIDES = (-1.0, -0.5, 0.0, 0.5, 1.0)
#: The topspins of the throw family that varies it (-1 full draw .. 1 natural roll).
TOPS = (-1.0, -0.5, 0.0, 0.5, 1.0)
#: The cut angles (degrees) of the throw families that vary them.
CUTS = (0, 10, 20, 30, 40, 50, 60)
#: The speeds (m/s) of the slow and the hard topspin families.
SLOW, HARD = 0.6, 3.5
#: Side spins of the rebound-angle curve.
SIDE_CURVE = tuple(round(-1.0 + 0.1 * k, 1) for k in range(21))

W, L, R = THREE_CUSHION.w, THREE_CUSHION.l, CAROM.R
#: Where an arriving ball meets the right-hand cushion (its centre then), and where the
#: object ball of the throw families stands.
CUSHION_CONTACT = (W - R, 0.9)
OBJECT_BALL = (0.55, 1.6)

#: Mathavan et al. 2010's snooker ball and constants: R 26.25 mm, M 0.1406 kg, the cushion
#: touching the ball at sin(theta) = 2/5 above its centre, restitution 0.98, friction 0.14
#: with the cushion and 0.212 with the cloth.
MATHAVAN_PAPER = replace(SNOOKER, R=0.02625, m=0.1406, e_c=0.98, f_c=0.14, u_s=0.212)
MATHAVAN_SIN_THETA = 0.4
#: The topspins of the paper's figures: w = k V0 / R about the axis that rolls the ball on.
MATHAVAN_TOPSPINS = (-1, 0, 1, 2)
MATHAVAN_INCIDENCES = tuple(range(0, 90, 5))


def _spin(v: tuple[float, float], top: float, side: float) -> tuple[float, float, float]:
    """The spin of a ball moving at v with topspin `top` and side `side` (multiples of |v|/R;
    w_z = side |v| / R)."""
    speed = math.hypot(*v)
    return (-top * v[1] / R, top * v[0] / R, side * speed / R)


def _run(balls: dict[str, tuple[float, float]], mover: str, v, w) -> tuple[list, dict]:
    """The engine's events and segment records of one ball set moving among `balls`."""
    scene = parse_scene(
        {
            "table": "three_cushion",
            "balls": {k: list(p) for k, p in balls.items()},
            "initial": {mover: {"v": list(v), "w": list(w)}},
        }
    )
    events, trajectories, _, _, _ = Simulation(scene).run_records()
    return events, trajectories


def _track(segments: list[tuple], end: float) -> list[list[float]]:
    """A ball's positions from 0 to `end` (every STEP and every segment's start)."""
    starts = np.array([s[0] for s in segments])
    t = np.unique(np.concatenate((np.arange(0.0, end, STEP), starts[starts < end], [end])))
    return np.round(positions(segments, t), DIGITS).tolist()


def _track_end(events: list, ball: str, cushions_seen: int) -> float:
    """When the ball meets its (cushions_seen + 1)-th cushion, or stops (TRACK_SECONDS at
    most)."""
    seen = 0
    for t, kind, balls, _, _ in events:
        if kind == "ball_cushion" and ball in balls:
            seen += 1
            if seen > cushions_seen:
                return min(float(t), TRACK_SECONDS)
    last = max((float(e[0]) for e in events if ball in e[2]), default=0.0)
    return min(last, TRACK_SECONDS)


def _after(segments: list[tuple], t: float) -> tuple[float, float]:
    """The ball's velocity just after time t (at the start of the segment begun there)."""
    seg = next(s for s in segments if s[0] >= t - 1e-12)
    return float(seg[4]), float(seg[5])


def _rolling_after(segments: list[tuple], t: float) -> tuple[float, float] | None:
    """The velocity of the ball's first rolling segment after t: the direction it settles
    on (None if it never rolls before it stops)."""
    for s in segments:
        if s[0] > t and s[1] == "rolling":
            return float(s[4]), float(s[5])
    return None


def _from_normal(v: tuple[float, float]) -> float:
    """The angle (degrees) of a velocity leaving the right-hand cushion from its normal (-x),
    positive up the table."""
    return math.degrees(math.atan2(v[1], -v[0]))


# -- cushion rebounds --------------------------------------------------------------------------


def rebound_shot(speed: float, incidence: float, top: float, side: float) -> dict[str, Any]:
    """A ball arriving at the right-hand cushion: its approach, its track to the next cushion,
    the rebound angle off the cushion and once rolling (degrees from the normal; the second
    None if it stops first)."""
    a = math.radians(incidence)
    d = (math.cos(a), math.sin(a))
    v = (speed * d[0], speed * d[1])
    # Running side is w_z < 0 here (module docstring): `side` counts running positive.
    w = _spin(v, top, -side)
    cx, cy = CUSHION_CONTACT
    start = (cx - GAP * d[0], cy - GAP * d[1])
    events, trajectories = _run({"cue": start}, "cue", v, w)
    segments = trajectories["cue"]
    hit = next(float(e[0]) for e in events if e[1] == "ball_cushion")
    rolling = _rolling_after(segments, hit)
    back = (start[0] - APPROACH * d[0], start[1] - APPROACH * d[1])
    return {
        "approach": [list(back), list(start)],
        "tracks": {"cue": _track(segments, _track_end(events, "cue", 1))},
        "rebound_deg": _from_normal(_after(segments, hit)),
        "settled_deg": None if rolling is None else _from_normal(rolling),
    }


def _family(name, title, vary, values, shot) -> dict[str, Any]:
    shots = []
    for value in values:
        s = shot(value)
        shots.append({"value": value, **s})
    return {"name": name, "title": title, "vary": vary, "shots": shots}


def cushion_families(speed: float, side: float, incidence: float) -> dict[str, Any]:
    """The rebound families: stun, running, check, varying side (at `incidence`), slow and
    hard topspin; the cushion line and the part of the table they use."""
    fan = "incidence_deg"
    families = [
        _family("stun", f"Stun, {speed:g} m/s", fan, INCIDENCES,
                lambda i: rebound_shot(speed, i, 0.0, 0.0)),
        _family("running", f"Rolling with running side {side:g}, {speed:g} m/s", fan,
                INCIDENCES, lambda i: rebound_shot(speed, i, 1.0, side)),
        _family("check", f"Rolling with check side {side:g}, {speed:g} m/s", fan, INCIDENCES,
                lambda i: rebound_shot(speed, i, 1.0, -side)),
        _family("side", f"Rolling at {incidence:g} deg, side from check to running", "side",
                SIDES, lambda s: rebound_shot(speed, incidence, 1.0, s)),
        _family("slow_topspin", f"Slow topspin (rolling), {SLOW:g} m/s", fan, INCIDENCES,
                lambda i: rebound_shot(SLOW, i, 1.0, 0.0)),
        _family("hard_topspin", f"Hard topspin (rolling), {HARD:g} m/s", fan, INCIDENCES,
                lambda i: rebound_shot(HARD, i, 1.0, 0.0)),
    ]  # fmt: skip
    return {
        "cushion": [[W, 0.0], [W, L]],
        "table": [W, L],
        "R": R,
        "families": families,
    }


def rebound_against_side(speed: float, incidence: float) -> dict[str, Any]:
    """The rebound angle of a rolling ball against its side spin (running positive) at one
    speed and incidence: off the cushion, and once it rolls again."""
    shots = [rebound_shot(speed, incidence, 1.0, s) for s in SIDE_CURVE]
    return {
        "side": list(SIDE_CURVE),
        "rebound_deg": [s["rebound_deg"] for s in shots],
        "settled_deg": [s["settled_deg"] for s in shots],
    }


# -- throw -------------------------------------------------------------------------------------


def throw_shot(speed: float, cut: float, top: float, side: float) -> dict[str, Any]:
    """The cue ball arriving along +y at the object ball with a cut of `cut` degrees (the
    object ball sent right): both tracks to their next cushion, the line of centres, and the
    throw (degrees off the line of centres, positive the way the cue ball drags the object
    ball) and the object ball's speed as a fraction of the cue ball's."""
    c = math.radians(cut)
    n = (math.sin(c), math.cos(c))
    ox, oy = OBJECT_BALL
    contact = (ox - 2 * R * n[0], oy - 2 * R * n[1])
    start = (contact[0], contact[1] - GAP)
    v = (0.0, speed)
    # Outside side is w_z < 0 here (module docstring): `side` counts outside positive.
    events, trajectories = _run({"cue": start, "object": OBJECT_BALL}, "cue", v,
                                _spin(v, top, -side))  # fmt: skip
    hit = next(float(e[0]) for e in events if e[1] == "ball_ball")
    vb = _after(trajectories["object"], hit)
    throw = math.degrees(math.atan2(n[0] * vb[1] - n[1] * vb[0], n[0] * vb[0] + n[1] * vb[1]))
    return {
        "approach": [[start[0], start[1] - APPROACH], list(start)],
        "centres": [list(contact), [ox + 0.6 * n[0], oy + 0.6 * n[1]]],
        "tracks": {k: _track(trajectories[k], _track_end(events, k, 0)) for k in ("cue", "object")},
        "throw_deg": throw,
        "object_speed": math.hypot(*vb) / speed,
    }


def throw_families(speed: float, cut: float) -> dict[str, Any]:
    """The throw families: stun and rolling cue balls over the cuts, and at `cut` the
    topspin from draw to roll and the side from inside to outside (stun)."""
    families = [
        _family("stun", f"Stun, {speed:g} m/s", "cut_deg", CUTS,
                lambda a: throw_shot(speed, a, 0.0, 0.0)),
        _family("roll", f"Rolling, {speed:g} m/s", "cut_deg", CUTS,
                lambda a: throw_shot(speed, a, 1.0, 0.0)),
        _family("varying_roll", f"Cut {cut:g} deg, draw to roll", "top", TOPS,
                lambda t: throw_shot(speed, cut, t, 0.0)),
        _family("varying_side", f"Cut {cut:g} deg stun, inside to outside side", "side",
                SIDES, lambda s: throw_shot(speed, cut, 0.0, s)),
    ]  # fmt: skip
    return {"object_ball": list(OBJECT_BALL), "table": [W, L], "R": R, "families": families}


# -- Mathavan 2010 -----------------------------------------------------------------------------


def mathavan_rebound(
    speed: float, incidence: float, k: float, p: Params = MATHAVAN_PAPER
) -> tuple[float, float]:
    """(rebound speed m/s, rebound angle degrees from the normal) of the paper's ball off its
    cushion: incoming at `speed`, `incidence` degrees from the normal, topspin k speed / R."""
    a = math.radians(incidence)
    v = (speed * math.sin(a), -speed * math.cos(a))
    w = (-k * v[1] / p.R, k * v[0] / p.R, 0.0)
    v1, _ = CUSHION_MODELS["mathavan"](v, w, (0.0, 1.0), p, MATHAVAN_SIN_THETA)
    return math.hypot(*v1), math.degrees(math.atan2(v1[0], v1[1]))


def mathavan_figures(speed: float) -> dict[str, Any]:
    """Rebound speed and angle against incidence for the paper's topspins at one speed."""
    curves = []
    for k in MATHAVAN_TOPSPINS:
        pairs = [mathavan_rebound(speed, i, k) for i in MATHAVAN_INCIDENCES]
        curves.append(
            {"k": k, "speed": [s for s, _ in pairs], "rebound_deg": [b for _, b in pairs]}
        )
    return {"incidence_deg": list(MATHAVAN_INCIDENCES), "curves": curves}

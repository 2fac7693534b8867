"""The numbers behind the model diagrams and the speed-against-error benchmark (no plotting).

Everything here returns plain lists and dicts so that the matplotlib figures
(physics.diagrams), the benchmark (bench/accuracy.py), the tests and a web page can all draw
from the same data.
"""

from __future__ import annotations

import copy
import math
import statistics
import time
from collections.abc import Callable, Iterable
from typing import Any

from physics import simulate, simulate_scene
from physics.ball_ball import BALL_BALL_MODELS
from physics.cushion import CUSHION_MODELS
from physics.examples import nineball_break, snooker_break_off
from physics.fixed_step import simulate_fixed
from physics.params import POOL, Params
from physics.tables import NINEBALL

#: The nose height of the nine-ball table as a contact angle: sin(theta) = h / R - 1.
NINEBALL_SIN_THETA = NINEBALL.cushion_height / POOL.R - 1.0


# -- ball-ball throw (Alciatore) ---------------------------------------------------------


def throw_angle(
    cut_deg: float, speed: float, spin: str, p: Params = POOL, model: str = "alciatore"
) -> float:
    """Throw (degrees) of the object ball off the line of centres for a cut of cut_deg.

    The cue ball moves along +y at `speed`, as a stun ball (no spin: "stun") or rolling
    naturally ("roll"); the line of centres is cut_deg from its path. Positive throw is in the
    direction the cue ball's motion drags the object ball (away from the line of centres,
    towards the cue ball's path).
    """
    a = math.radians(cut_deg)
    n = (math.sin(a), math.cos(a))
    va = (0.0, speed)
    wa = (-speed / p.R, 0.0, 0.0) if spin == "roll" else (0.0, 0.0, 0.0)
    _, _, vb, _ = BALL_BALL_MODELS[model](va, wa, (0.0, 0.0), (0.0, 0.0, 0.0), n, p)
    # Angle of vb from n, counted towards -x (the side the cue ball's velocity drags it).
    cross = n[0] * vb[1] - n[1] * vb[0]
    return math.degrees(math.atan2(cross, n[0] * vb[0] + n[1] * vb[1]))


def throw_curves(
    cuts: Iterable[float] = range(0, 91, 2), speeds: Iterable[float] = (0.5, 3.0)
) -> list[dict[str, Any]]:
    """Throw against cut angle for stun and rolling cue balls at each speed (m/s)."""
    cuts = list(cuts)
    return [
        {
            "spin": spin,
            "speed": speed,
            "cut_deg": cuts,
            "throw_deg": [throw_angle(c, speed, spin) for c in cuts],
        }
        for spin in ("stun", "roll")
        for speed in speeds
    ]


# -- cushion rebound (Mathavan, Han) -------------------------------------------------------


def rebound(
    model: str,
    speed: float,
    incidence_deg: float,
    spin: str,
    p: Params = POOL,
    sin_theta: float = NINEBALL_SIN_THETA,
) -> tuple[float, float]:
    """(rebound speed m/s, rebound angle degrees from the normal) off a straight cushion.

    The ball comes in at incidence_deg from the cushion's normal; spin is "stun" (none),
    "roll" (natural roll), "roll+side" (natural roll plus running side, w_z = v / R) or
    "roll-side" (reverse side).
    """
    a = math.radians(incidence_deg)
    v = (speed * math.sin(a), -speed * math.cos(a))
    wz = {"roll+side": 1.0, "roll-side": -1.0}.get(spin, 0.0) * speed / p.R
    w = (0.0, 0.0, 0.0) if spin == "stun" else (-v[1] / p.R, v[0] / p.R, wz)
    v1, _ = CUSHION_MODELS[model](v, w, (0.0, 1.0), p, sin_theta)
    return math.hypot(*v1), math.degrees(math.atan2(v1[0], v1[1]))


def rebound_curves(
    incidences: Iterable[float] = range(0, 86, 5),
    speed: float = 2.0,
    spins: Iterable[str] = ("stun", "roll", "roll+side", "roll-side"),
) -> list[dict[str, Any]]:
    """Rebound speed ratio and angle against incidence, per model and spin."""
    incidences = list(incidences)
    out = []
    for model in ("mathavan", "han"):
        for spin in spins:
            pairs = [rebound(model, speed, i, spin) for i in incidences]
            out.append(
                {
                    "model": model,
                    "spin": spin,
                    "speed": speed,
                    "incidence_deg": incidences,
                    "speed_ratio": [s / speed for s, _ in pairs],
                    "rebound_deg": [r for _, r in pairs],
                }
            )
    return out


# -- a ball's motion through slide, roll and spin ----------------------------------------


def motion_profile(
    v0: float = 1.0, top: float = -0.5, side: float = 3.0, samples: int = 400
) -> dict[str, Any]:
    """Speed and spin against time of one ball on an open carom table, from the engine's
    trajectory segments. The ball starts at v0 along +y with spin w_x = top * v0 / R (negative
    is follow, positive draw) and w_z = side * v0 / R: it slides, rolls, stops and spins."""
    p = POOL
    scene = {
        "table": {"preset": "three_cushion", "w": 40.0, "l": 40.0},
        "params": {"R": p.R, "m": p.m, "u_r": p.u_r},
        "balls": {"cue": [20.0, 1.0]},
        "initial": {"cue": {"v": [0.0, v0], "w": [-top * v0 / p.R, 0.0, side * v0 / p.R]}},
    }
    shot = simulate(scene)
    segments = shot.trajectories["cue"]
    end = shot.duration * 1.05
    times, speed, w_roll, w_z, states = [], [], [], [], []
    for k in range(samples + 1):
        t = end * k / samples
        seg = [s for s in segments if s.t <= t][-1]  # the last segment begun by t
        tau = t - seg.t
        if seg.state in ("stationary", "pocketed"):
            tau = 0.0
        vx, vy = seg.v[0] + seg.a[0] * tau, seg.v[1] + seg.a[1] * tau
        w = [seg.w[i] + seg.dw[i] * tau for i in range(3)]
        times.append(t)
        speed.append(math.hypot(vx, vy))
        w_roll.append(-w[0] * p.R)  # surface speed of the top/back spin
        w_z.append(w[2])
        states.append(seg.state)
    events = [(e.t, e.type) for e in shot.events]
    return {
        "t": times,
        "speed": speed,
        "roll_surface_speed": w_roll,
        "w_z": w_z,
        "state": states,
        "events": events,
    }


# -- speed against error -------------------------------------------------------------------


def straight_draw() -> dict[str, Any]:
    """A full-ball draw shot up the table: the cue ball comes back towards the player."""
    return {
        "table": "nineball",
        "balls": {"cue": [0.635, 0.6], "1": [0.635, 1.3]},
        "strike": {"ball": "cue", "speed": 3.0, "heading": 90.0, "b": -0.35},
    }


def cut_with_throw() -> dict[str, Any]:
    """A half-ball stun cut, where ball-ball friction throws the object ball most."""
    R = POOL.R
    return {
        "table": "nineball",
        "balls": {"cue": [0.5, 0.5], "1": [0.5 + R, 1.2 + 2 * R * math.cos(math.radians(30))]},
        "strike": {"ball": "cue", "speed": 1.5, "heading": 90.0, "b": 0.0},
    }


def three_rail_kick() -> dict[str, Any]:
    """A carom ball sent round three rails with running side, towards the other two balls."""
    return {
        "table": "three_cushion",
        "balls": {"cue": [0.45, 0.5], "red": [1.1, 2.3], "yellow": [0.3, 2.5]},
        "strike": {"ball": "cue", "speed": 4.0, "heading": 65.0, "a": 0.3, "b": 0.2},
    }


#: The benchmark's shots, by name.
SHOTS: dict[str, Callable[[], dict[str, Any]]] = {
    "straight draw": straight_draw,
    "cut with throw": cut_with_throw,
    "three-rail kick": three_rail_kick,
    "nine-ball break": nineball_break,
    "snooker break-off": snooker_break_off,
}

#: The cheaper model choices of the event engine, as scene "models" overrides.
CHEAP_MODELS: dict[str, dict[str, Any]] = {
    "event frictionless balls": {"ball_ball": "frictionless"},
    "event han cushion": {"cushion": "han"},
    "event no spin": {"spin": False},
}

#: Fixed-step sizes of the benchmark (s).
STEPS = (1e-3, 2e-4, 5e-5, 1e-5)


def position_error(ref: dict[str, Any], other: dict[str, Any]) -> dict[str, float]:
    """Final-position difference between two results (mm): RMS and max over the balls on the
    table in both, and how many balls ended in a different pocket (or on the table in one)."""
    diffs, mismatched = [], 0
    for name, a in ref["final"].items():
        b = other["final"][name]
        if a["pos"] is not None and b["pos"] is not None:
            diffs.append(1000.0 * math.dist(a["pos"], b["pos"]))
        elif a["pocket"] != b["pocket"]:
            mismatched += 1
    rms = math.sqrt(sum(d * d for d in diffs) / len(diffs)) if diffs else 0.0
    return {"rms_mm": rms, "max_mm": max(diffs, default=0.0), "pocket_mismatch": mismatched}


def _cpu(fn: Callable[[], dict[str, Any]], repeats: int) -> tuple[dict[str, Any], float]:
    """Result and median CPU time (s) of `repeats` calls."""
    times = []
    for _ in range(repeats):
        start = time.process_time()
        result = fn()
        times.append(time.process_time() - start)
    return result, statistics.median(times)


def nudged(scene: dict[str, Any], ball: str = "cue", dx: float = 1e-9) -> dict[str, Any]:
    """The same scene with one ball moved dx metres along x."""
    out = copy.deepcopy(scene)
    x, y = out["balls"][ball]
    out["balls"][ball] = [x + dx, y]
    return out


def speed_vs_error(
    shots: Iterable[str] = tuple(SHOTS),
    steps: Iterable[float] = STEPS,
    repeats: int = 5,
    progress: Callable[[str], None] | None = None,
) -> list[dict[str, Any]]:
    """For each shot and method: CPU time (s) and final-position error against the event
    engine at its defaults. Methods: the reference itself (error 0), the cheaper model choices,
    the fixed-step integrator at each dt, and the reference with the cue ball moved 1e-9 m
    (the shot's sensitivity: where any method's result stops being meaningful)."""
    rows = []
    for shot in shots:
        scene = SHOTS[shot]()
        ref, ref_time = _cpu(lambda scene=scene: simulate_scene(scene), repeats)
        runs = [("event (reference)", ref, ref_time)]
        for method, models in CHEAP_MODELS.items():
            variant = {**scene, "models": models}
            runs.append((method, *_cpu(lambda v=variant: simulate_scene(v), repeats)))
        runs.append(("event, cue ball +1e-9 m", simulate_scene(nudged(scene)), ref_time))
        for dt in steps:
            runs.append(
                (f"fixed step dt={dt:g}", *_cpu(lambda s=scene, dt=dt: simulate_fixed(s, dt), 1))
            )
        for method, result, cpu in runs:
            row = {"shot": shot, "method": method, "cpu_s": cpu, **position_error(ref, result)}
            rows.append(row)
            if progress:
                progress(f"{shot:18s} {method:26s} {cpu:9.4f} s {row['rms_mm']:10.3f} mm")
    return rows

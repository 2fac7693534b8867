"""The data behind the /diagrams page: physics curves computed from constants the user sets.

Three curves, each a `GET` whose query is one pydantic model with every field bounded:
- `/diagrams/throw`: object-ball throw against cut angle (Alciatore's friction fit), for a stun
  and a rolling cue ball at one speed;
- `/diagrams/cushion`: rebound angle and speed ratio against incidence off a straight cushion,
  Mathavan 2010 and Han 2005, for four spins;
- `/diagrams/motion`: one struck ball on an open table; the answer is the engine's trajectory
  segments (in the wire form of docs/protocol.md) and events, which the page samples itself
  with the same code that animates a shot.

The work per request is fixed by the grids below and the bounds (a few milliseconds: at most 46
throw evaluations, 144 cushion impacts, one single-ball shot), so it runs in the handler; an
unknown field, a value out of bounds, NaN or infinity gets a 400 JSON error with a code and
computes nothing.
"""

from __future__ import annotations

import json
from dataclasses import replace
from typing import Any

from aiohttp import web
from pydantic import BaseModel, ConfigDict, Field, ValidationError

import physics
from physics.accuracy_data import rebound, throw_angle
from physics.cue import MISCUE_LIMIT
from physics.params import POOL
from server.protocol.trajectories import wire_trajectory

#: Cut angles (degrees) of the throw curves, and incidences of the cushion curves.
CUTS = tuple(range(0, 91, 2))
INCIDENCES = tuple(range(0, 86, 5))
CUSHION_MODELS = ("mathavan", "han")
CUSHION_SPINS = ("stun", "roll", "roll+side", "roll-side")

#: The open table of the motion diagram: large enough that no cushion is reached.
OPEN_TABLE = {"preset": "three_cushion", "w": 40.0, "l": 40.0}


def bounded(lo: float, hi: float, default: float, description: str) -> Any:
    """A slider's field: a finite float in [lo, hi]; the page builds its slider from these."""
    return Field(default, ge=lo, le=hi, allow_inf_nan=False, description=description)


class Query(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")


class ThrowQuery(Query):
    """Throw of a stun and a rolling cue ball; the friction fit is mu(v) = a + b exp(-c v)."""

    speed: float = bounded(0.1, 8.0, 1.0, "cue-ball speed (m/s)")
    throw_a: float = bounded(0.0, 0.1, POOL.throw_a, "friction a")
    throw_b: float = bounded(0.0, 0.5, POOL.throw_b, "friction b")
    throw_c: float = bounded(0.0, 5.0, POOL.throw_c, "friction c (s/m)")


class CushionQuery(Query):
    """Rebound off a straight cushion whose nose touches the ball at `height` R above the cloth
    (sin theta = height - 1)."""

    speed: float = bounded(0.2, 6.0, 2.0, "incoming speed (m/s)")
    e_c: float = bounded(0.5, 1.0, POOL.e_c, "cushion restitution e_c")
    f_c: float = bounded(0.0, 0.5, POOL.f_c, "cushion friction f_c")
    height: float = bounded(1.1, 1.6, 1.27, "nose height (multiples of R)")


class MotionQuery(Query):
    """One ball struck along +y with tip offsets within the miscue limit."""

    speed: float = bounded(0.2, 6.0, 2.0, "cue speed (m/s)")
    b: float = bounded(-MISCUE_LIMIT, MISCUE_LIMIT, -0.3, "tip height b (fraction of R; < 0 draws)")
    a: float = bounded(-MISCUE_LIMIT, MISCUE_LIMIT, 0.2, "tip side a (fraction of R)")
    u_s: float = bounded(0.05, 0.5, POOL.u_s, "sliding friction u_s")
    u_r: float = bounded(0.002, 0.05, POOL.u_r, "rolling resistance u_r")
    u_sp: float = bounded(0.002, 0.05, POOL.u_sp, "spin friction u_sp")


def throw_curves(q: ThrowQuery) -> dict:
    p = replace(POOL, throw_a=q.throw_a, throw_b=q.throw_b, throw_c=q.throw_c)
    return {
        "cut_deg": list(CUTS),
        "curves": [
            {"spin": spin, "throw_deg": [throw_angle(c, q.speed, spin, p) for c in CUTS]}
            for spin in ("stun", "roll")
        ],
    }


def cushion_curves(q: CushionQuery) -> dict:
    p = replace(POOL, e_c=q.e_c, f_c=q.f_c)
    curves = []
    for model in CUSHION_MODELS:
        for spin in CUSHION_SPINS:
            pairs = [rebound(model, q.speed, i, spin, p, q.height - 1.0) for i in INCIDENCES]
            curves.append(
                {
                    "model": model,
                    "spin": spin,
                    "rebound_deg": [angle for _, angle in pairs],
                    "speed_ratio": [speed / q.speed for speed, _ in pairs],
                }
            )
    return {"incidence_deg": list(INCIDENCES), "curves": curves}


def motion_shot(q: MotionQuery) -> dict:
    scene = {
        "table": OPEN_TABLE,
        "params": {"R": POOL.R, "m": POOL.m, "u_s": q.u_s, "u_r": q.u_r, "u_sp": q.u_sp},
        "balls": {"cue": [20.0, 1.0]},
        "strike": {"ball": "cue", "speed": q.speed, "heading": 90.0, "a": q.a, "b": q.b},
    }
    shot = physics.simulate(scene)  # SceneError (a ValueError) for a miscue
    return {
        "R": POOL.R,
        "segments": wire_trajectory(shot).balls["cue"],
        "events": [{"t": e.t, "type": e.type} for e in shot.events],
        "duration": shot.duration,
    }


def inputs() -> dict[str, dict[str, dict[str, Any]]]:
    """Each curve's sliders: {curve: {field: {min, max, default, label}}}, from the models."""
    out = {}
    for name, (model, _) in CURVES.items():
        fields = model.model_json_schema()["properties"]
        out[name] = {
            key: {
                "min": f["minimum"],
                "max": f["maximum"],
                "default": f["default"],
                "label": f["description"],
            }
            for key, f in fields.items()
        }
    return out


CURVES = {
    "throw": (ThrowQuery, throw_curves),
    "cushion": (CushionQuery, cushion_curves),
    "motion": (MotionQuery, motion_shot),
}


#: The sliders never change: described once, at import.
INPUTS = inputs()


def json_error(status: type[web.HTTPError], code: str, message: str) -> web.HTTPError:
    return status(
        text=json.dumps({"code": code, "reason": message}), content_type="application/json"
    )


async def curve(request: web.Request) -> web.Response:
    name = request.match_info["curve"]
    if name not in CURVES:
        raise json_error(web.HTTPNotFound, "not_found", f"no curve {name!r}: {', '.join(CURVES)}")
    model, compute = CURVES[name]
    try:
        query = model.model_validate(dict(request.query))
        return web.json_response(compute(query))
    except ValidationError as e:
        errors = "; ".join(f"{'.'.join(map(str, x['loc']))}: {x['msg']}" for x in e.errors())
        raise json_error(web.HTTPBadRequest, "bad_request", errors) from None
    except ValueError as e:
        raise json_error(web.HTTPBadRequest, "bad_request", str(e)) from None


async def sliders(_: web.Request) -> web.Response:
    return web.json_response(INPUTS)


def mount_diagrams(app: web.Application) -> None:
    app.router.add_get("/diagrams/inputs", sliders)
    app.router.add_get("/diagrams/{curve}", curve)

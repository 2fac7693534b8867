"""The data behind the /diagrams page: physics curves computed from constants the user sets.

Each curve is a `GET /diagrams/{curve}` whose query is one pydantic model with every field
bounded. Four are cheap and computed in the handler (the work per request is fixed by the
grids below and the bounds, a few milliseconds at most: 46 throw evaluations, 144 or 72
cushion impacts, one single-ball shot):
- `throw`: object-ball throw against cut angle (Alciatore's friction fit), for a stun and a
  rolling cue ball at one speed;
- `cushion`: rebound angle and speed ratio against incidence off a straight cushion, Mathavan
  2010 and Han 2005, for four spins;
- `mathavan`: the figures of Mathavan et al. 2010 the engine reproduces: rebound speed and
  angle against incidence for the paper's ball, cushion and topspins (physics.diagram_families);
- `motion`: one struck ball on an open table; the answer is the engine's trajectory
  segments (in the wire form of docs/protocol.md) and events.

Three are families of whole shots on the carom table (physics.diagram_families, a few hundred
ms each), computed in the background worker, kept, and charged to the asker's address
(server/game/diagrams.py; 429 `rate_limited` once its worker time is spent):
- `rebounds`: the cushion rebound families (stun, running, check, varying side, slow and hard
  topspin), each shot's track;
- `rebound_side`: the rebound angle of a rolling ball against its side spin at one speed;
- `throws`: the throw families (stun, roll, varying roll, varying side), both balls' tracks.

An unknown field, a value out of bounds, NaN or infinity gets a 400 JSON error with a code and
computes nothing.
"""

from __future__ import annotations

import json
from dataclasses import replace
from typing import Any

from aiohttp import web
from pydantic import BaseModel, ConfigDict, Field, ValidationError

import physics
from physics import diagram_families as families
from physics.accuracy_data import rebound, throw_angle
from physics.cue import MISCUE_LIMIT
from physics.params import POOL
from server.game.diagrams import encoded
from server.game.service import SERVICE_KEY
from server.protocol.errors import ServiceError
from server.protocol.trajectories import wire_trajectory
from server.relay import client_address, relay_of

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


class MathavanQuery(Query):
    """The paper's snooker ball arriving at `speed` with topspins k = -1, 0, 1, 2."""

    speed: float = bounded(0.2, 6.0, 1.0, "incoming speed V0 (m/s)")


class ReboundsQuery(Query):
    """Balls arriving at a cushion (physics.diagram_families)."""

    speed: float = bounded(0.3, 5.0, 2.0, "arrival speed (m/s)")
    side: float = bounded(0.0, 1.0, 0.5, "side of the running and check families (v/R)")
    incidence: float = bounded(0.0, 80.0, 45.0, "incidence of the side family (degrees)")


class ReboundSideQuery(Query):
    """A rolling ball arriving at a cushion, its side spin varied."""

    speed: float = bounded(0.3, 5.0, 2.0, "arrival speed (m/s)")
    incidence: float = bounded(0.0, 80.0, 45.0, "incidence (degrees from the normal)")


class ThrowsQuery(Query):
    """The cue ball arriving at an object ball (physics.diagram_families)."""

    speed: float = bounded(0.2, 5.0, 1.0, "cue-ball speed (m/s)")
    cut: float = bounded(0.0, 70.0, 30.0, "cut of the varying roll and side families (degrees)")


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


def mathavan_curves(q: MathavanQuery) -> dict:
    return families.mathavan_figures(q.speed)


def inputs() -> dict[str, dict[str, dict[str, Any]]]:
    """Each curve's sliders: {curve: {field: {min, max, default, label}}}, from the models."""
    out = {}
    for name, (model, _) in {**CURVES, **FAMILIES}.items():
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
    "mathavan": (MathavanQuery, mathavan_curves),
}

#: The families of whole shots, computed in the background worker: their query and function.
FAMILIES = {
    "rebounds": (
        ReboundsQuery,
        lambda q: (families.cushion_families, (q.speed, q.side, q.incidence)),
    ),
    "rebound_side": (
        ReboundSideQuery,
        lambda q: (families.rebound_against_side, (q.speed, q.incidence)),
    ),
    "throws": (ThrowsQuery, lambda q: (families.throw_families, (q.speed, q.cut))),
}


#: The sliders never change: described once, at import.
INPUTS = inputs()


def json_error(status: type[web.HTTPError], code: str, message: str) -> web.HTTPError:
    return status(
        text=json.dumps({"code": code, "reason": message}), content_type="application/json"
    )


def _query(model: type[Query], request: web.Request) -> Any:
    try:
        return model.model_validate(dict(request.query))
    except ValidationError as e:
        errors = "; ".join(f"{'.'.join(map(str, x['loc']))}: {x['msg']}" for x in e.errors())
        raise json_error(web.HTTPBadRequest, "bad_request", errors) from None


async def curve(request: web.Request) -> web.Response:
    name = request.match_info["curve"]
    if name in FAMILIES:
        return await family(request, name)
    if name not in CURVES:
        known = ", ".join([*CURVES, *FAMILIES])
        raise json_error(web.HTTPNotFound, "not_found", f"no curve {name!r}: {known}")
    model, compute = CURVES[name]
    query = _query(model, request)
    try:
        return web.json_response(compute(query))
    except ValueError as e:
        raise json_error(web.HTTPBadRequest, "bad_request", str(e)) from None


async def family(request: web.Request, name: str) -> web.Response:
    """A family of shots from the background worker (server/game/diagrams.py)."""
    model, call = FAMILIES[name]
    query = _query(model, request)
    service = request.app.get(SERVICE_KEY)
    if service is None:
        raise json_error(web.HTTPServiceUnavailable, "unavailable", "no game service here")
    asker = client_address(request, relay_of(request).trusted_proxies)
    key = f"{name}:{query.model_dump_json()}"
    try:
        data = await service.diagrams.answer(key, encoded, call(query), asker, keep=True)
    except ServiceError as e:  # its worker time spent, or the worker busy
        return web.json_response({"code": e.code.value, "reason": e.reason}, status=e.status)
    return web.Response(body=data, content_type="application/json")


async def sliders(_: web.Request) -> web.Response:
    return web.json_response(INPUTS)


def mount_diagrams(app: web.Application) -> None:
    app.router.add_get("/diagrams/inputs", sliders)
    app.router.add_get("/diagrams/{curve}", curve)

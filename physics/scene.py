"""The scene format: what `billiards simulate` reads and `physics.simulate_scene` takes.

Parsing and validation live here so that the engine only ever sees a consistent scene: balls on
the table, not overlapping, not in a pocket, every number finite and in range. Anything else is
a `SceneError` whose message says what is wrong.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, StringConstraints, ValidationError

from physics.cue import strike as cue_strike
from physics.params import Params
from physics.tables import PRESETS, Geometry

BallId = Annotated[str, StringConstraints(pattern=r"^[A-Za-z0-9_-]{1,16}$")]
Finite = Annotated[float, Field(allow_inf_nan=False)]

#: The fastest ball a scene may set directly (m/s): harder than any break shot.
MAX_BALL_SPEED = 12.0
#: The largest spin a scene may set directly (rad/s): a 12 m/s ball rolling, on the smallest ball.
MAX_SPIN = 500.0
#: Overlap between balls in a scene that still counts as touching (m): float noise only.
OVERLAP_TOLERANCE = 1e-12


class SceneError(ValueError):
    """An invalid scene; the message says why."""


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Motion(_Strict):
    v: tuple[Finite, Finite] = (0.0, 0.0)
    w: tuple[Finite, Finite, Finite] = (0.0, 0.0, 0.0)


class Strike(_Strict):
    ball: BallId
    speed: Finite
    heading: Finite
    elevation: Finite = 0.0
    a: Finite = 0.0
    b: Finite = 0.0


class Models(_Strict):
    ball_ball: Literal["alciatore", "frictionless"] = "alciatore"
    cushion: Literal["mathavan", "han"] = "mathavan"
    spin: bool = True


class SceneIn(_Strict):
    table: str | dict[str, Finite | bool | str] = "nineball"
    params: dict[str, Finite] = Field(default_factory=dict)
    balls: dict[BallId, tuple[Finite, Finite]] = Field(min_length=1, max_length=32)
    initial: dict[BallId, Motion] = Field(default_factory=dict)
    strike: Strike | None = None
    models: Models = Models()


@dataclass(frozen=True, slots=True)
class Scene:
    """A validated scene, ready for the engine."""

    geometry: Geometry
    params: Params
    models: Models
    positions: dict[str, tuple[float, float]]
    initial: dict[str, Motion]
    strike: Strike | None
    #: The struck ball's velocity and spin from the cue model, when the scene has a strike.
    strike_motion: Motion | None = None

    @property
    def sin_theta(self) -> float:
        return self.geometry.spec.cushion_height / self.params.R - 1.0


def _check_params(p: Params) -> None:
    for name in ("R", "m", "g", "u_s", "u_r", "u_sp", "m_cue"):
        if not getattr(p, name) > 0.0:
            raise SceneError(f"params.{name} must be positive")
    for name in ("e_b", "e_c"):
        if not 0.0 <= getattr(p, name) <= 1.0:
            raise SceneError(f"params.{name} must be between 0 and 1")
    if p.f_c < 0.0 or p.throw_a < 0.0 or p.throw_b < 0.0:
        raise SceneError("friction coefficients must not be negative")
    if not 1 <= p.mathavan_steps <= 100_000:
        raise SceneError("params.mathavan_steps must be between 1 and 100000")


def _table(spec_in: str | dict[str, Any]):
    if isinstance(spec_in, str):
        if spec_in not in PRESETS:
            raise SceneError(f"unknown table {spec_in!r}; presets: {', '.join(PRESETS)}")
        return PRESETS[spec_in]
    overrides = dict(spec_in)
    base = overrides.pop("preset", "nineball")
    if base not in PRESETS:
        raise SceneError(f"unknown table preset {base!r}; presets: {', '.join(PRESETS)}")
    spec, params = PRESETS[base]
    try:
        spec = spec.with_overrides(overrides)
    except (TypeError, ValueError) as exc:
        raise SceneError(str(exc)) from None
    for name in ("w", "l", "cushion_height", "corner_mouth", "side_mouth", "jaw_radius"):
        value = getattr(spec, name)
        if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
            raise SceneError(f"table.{name} must be a positive number")
    if not isinstance(spec.pockets, bool):
        raise SceneError("table.pockets must be true or false")
    return spec, params


def _check_positions(scene: Scene) -> None:
    g, R = scene.geometry, scene.params.R
    w, l = g.spec.w, g.spec.l
    items = list(scene.positions.items())
    for name, (x, y) in items:
        if not (R <= x <= w - R and R <= y <= l - R):
            raise SceneError(f"ball {name} at ({x}, {y}) is off the table or in a cushion")
        for pocket in g.pockets:
            if math.hypot(x - pocket.center[0], y - pocket.center[1]) < pocket.radius:
                raise SceneError(f"ball {name} is inside pocket {pocket.name}")
    for k, (a, (xa, ya)) in enumerate(items):
        for b, (xb, yb) in items[k + 1 :]:
            if math.hypot(xb - xa, yb - ya) < 2 * R - OVERLAP_TOLERANCE:
                raise SceneError(f"balls {a} and {b} overlap")


def parse_scene(data: dict[str, Any]) -> Scene:
    """Validate a scene dictionary (the JSON format of the physics issue)."""
    if not isinstance(data, dict):
        raise SceneError("a scene is a JSON object")
    try:
        raw = SceneIn.model_validate(data)
    except ValidationError as exc:
        first = exc.errors()[0]
        where = ".".join(str(x) for x in first["loc"]) or "scene"
        raise SceneError(f"{where}: {first['msg']}") from None
    spec, params = _table(raw.table)
    overrides: dict[str, float | int] = dict(raw.params)
    if "mathavan_steps" in overrides:
        steps = overrides["mathavan_steps"]
        if steps != int(steps):
            raise SceneError("params.mathavan_steps must be a whole number")
        overrides["mathavan_steps"] = int(steps)
    try:
        params = params.with_overrides(overrides)
    except ValueError as exc:
        raise SceneError(str(exc)) from None
    _check_params(params)
    scene = Scene(
        geometry=spec.geometry(),
        params=params,
        models=raw.models,
        positions={k: (float(x), float(y)) for k, (x, y) in raw.balls.items()},
        initial=raw.initial,
        strike=raw.strike,
    )
    if not -1.0 < scene.sin_theta < 1.0:
        raise SceneError("table.cushion_height must be between 0 and 2R")
    _check_positions(scene)
    unknown = sorted(set(raw.initial) - set(raw.balls))
    if raw.strike is not None and raw.strike.ball not in raw.balls:
        unknown.append(raw.strike.ball)
    if unknown:
        raise SceneError(f"unknown ball ids: {', '.join(unknown)}")
    if raw.strike is not None and raw.strike.ball in raw.initial:
        raise SceneError(f"ball {raw.strike.ball} has both a strike and an initial motion")
    if raw.strike is not None:
        s = raw.strike
        try:
            v, w = cue_strike(s.speed, s.heading, s.elevation, s.a, s.b, params)
        except ValueError as exc:
            raise SceneError(f"strike: {exc}") from None
        scene = replace(scene, strike_motion=Motion(v=v, w=w))
    for name, motion in raw.initial.items():
        if math.hypot(*motion.v) > MAX_BALL_SPEED:
            raise SceneError(f"ball {name}: speed above {MAX_BALL_SPEED} m/s")
        if math.hypot(*motion.w) > MAX_SPIN:
            raise SceneError(f"ball {name}: spin above {MAX_SPIN} rad/s")
    return scene

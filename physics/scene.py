"""The scene format: what `billiards simulate` reads and `physics.simulate_scene` takes.

Parsing and validation live here so that the engine only ever sees a consistent scene: balls on
the table or in a pocket's mouth, not overlapping, not in a pocket, every number finite and
within a bound that keeps the worst shot cheap (each bound and its reason is in the docstring of
the model that holds it). Anything else, from any input (`scene_from_json` takes raw bytes), is a
`SceneError` whose one-line message says what is wrong.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, replace
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    Strict,
    StringConstraints,
    Tag,
    ValidationError,
    model_validator,
)

from physics.cue import strike as cue_strike
from physics.params import Params
from physics.tables import PRESETS, Geometry, TableSpec, position_problem, table_problem

BallId = Annotated[str, StringConstraints(pattern=r"^[A-Za-z0-9_-]{1,16}$")]
#: A JSON number: no strings, booleans, NaN or infinities.
Finite = Annotated[float, Strict(), Field(allow_inf_nan=False)]


def _within(low: float, high: float, *, above: bool = False) -> Any:
    """A finite number in [low, high], or in (low, high] when it must be above low."""
    if above:
        return Annotated[float, Strict(), Field(allow_inf_nan=False, gt=low, le=high)]
    return Annotated[float, Strict(), Field(allow_inf_nan=False, ge=low, le=high)]


#: The fastest ball a scene may set directly in `initial` (m/s): harder than any break shot.
#: (A strike is bounded by the cue's speed instead, physics.cue.MAX_SPEED.)
MAX_BALL_SPEED = 12.0
#: The largest spin a scene may set directly (rad/s): a 12 m/s ball rolling, on the smallest ball.
MAX_SPIN = 500.0
#: How far (m) a ball may press into another ball, a cushion or a jaw and still count as touching
#: it: the most the engine lets a contact sink in (physics.engine), so the positions a shot ends
#: with are always a valid scene for the next.
CONTACT_TOLERANCE = 1e-9
#: The longest scene document `scene_from_json` reads (bytes): 32 balls take about 3 kB.
MAX_SCENE_BYTES = 64 * 1024


class SceneError(ValueError):
    """An invalid scene; the message says why."""


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Motion(_Strict):
    v: tuple[Finite, Finite] = (0.0, 0.0)
    w: tuple[Finite, Finite, Finite] = (0.0, 0.0, 0.0)


class Strike(_Strict):
    """A cue strike (physics.cue.strike bounds speed, elevation and tip offset). The heading is
    held to one turn either way: beyond that its sine and cosine lose digits for nothing."""

    ball: BallId
    speed: Finite
    heading: _within(-360.0, 360.0)
    elevation: Finite = 0.0
    a: Finite = 0.0
    b: Finite = 0.0


class _Overrides(_Strict):
    """Fields left out take the preset's value; null is not a value."""

    @model_validator(mode="before")
    @classmethod
    def _no_nulls(cls, data: Any) -> Any:
        if isinstance(data, dict) and None in data.values():
            nulls = ", ".join(sorted(_plain(k) for k, v in data.items() if v is None))
            raise ValueError(f"null is not a value ({nulls})")
        return data


class Models(_Strict):
    ball_ball: Literal["alciatore", "frictionless"] = "alciatore"
    cushion: Literal["mathavan", "han"] = "mathavan"
    spin: Annotated[bool, Strict()] = True


#: The preset tables by name.
PresetName = Literal[tuple(PRESETS)]  # type: ignore[valid-type]


class TableIn(_Overrides):
    """Overrides of a preset table's numbers (physics.tables.TableSpec says what each is).

    Every length is in metres and bounded so that no table is degenerate or dear to simulate:
    - w, l in [0.5, 200]: a narrower table would multiply the cushion contacts per metre a ball
      travels; a longer one only saves contacts (the accuracy tests use a 150 m table to keep
      cushions out of reach), and its coordinates stay far above rounding at the 1e-9 m the
      engine resolves contacts to.
    - cushion_height in (0, 0.1]; check_table then holds it to [R, 1.8 R].
    - corner_mouth, side_mouth in (0, 0.3]: wider than any real pocket (pool corners 0.12 m);
      check_table then makes a ball fit and leaves every rail some length.
    - corner_depth, side_depth in [0, 0.2]: the capture circle sits behind the mouth's middle
      (a negative depth would swallow balls resting on the cloth).
    - corner_radius, side_radius in (0, 0.2], jaw_radius in (0, 0.1]; check_table then makes
      every pocket close its mouth.
    """

    preset: PresetName = "nineball"
    w: _within(0.5, 200.0) | None = None
    l: _within(0.5, 200.0) | None = None
    pockets: Annotated[bool, Strict()] | None = None
    cushion_height: _within(0.0, 0.1, above=True) | None = None
    corner_mouth: _within(0.0, 0.3, above=True) | None = None
    corner_depth: _within(0.0, 0.2) | None = None
    corner_radius: _within(0.0, 0.2, above=True) | None = None
    side_mouth: _within(0.0, 0.3, above=True) | None = None
    side_depth: _within(0.0, 0.2) | None = None
    side_radius: _within(0.0, 0.2, above=True) | None = None
    jaw_radius: _within(0.0, 0.1, above=True) | None = None


class ParamsIn(_Overrides):
    """Overrides of the preset's balls and cloth (physics.params.Params says what each is).

    Each bound holds every real game's value with room, and keeps the worst shot cheap:
    - R in [0.02, 0.04] m, m in [0.05, 0.5] kg: the balls of every game (snooker 26.25 mm to
      carom 30.75 mm) with room.
    - u_s in [0.05, 1], u_r in [0.005, 0.05], u_sp in [0.002, 0.1]: real cloth has u_s about
      0.2, u_r 0.005-0.015, u_sp about 0.01; the lower bounds keep a ball from running (and
      hitting cushions) for minutes.
    - e_b in [0, 1]; e_c in [0, 0.98]: a perfectly elastic cushion would keep a ball bouncing
      until rolling resistance alone stops it, hundreds of contacts.
    - f_c in [0, 0.5]: real cushions are 0.1-0.3; far beyond that Mathavan's integration wedges
      the ball into the cushion and takes its longest path (physics.cushion).
    - g in [9.5, 10] m/s^2: the Earth's, anywhere on it.
    - throw_a in [0, 0.1], throw_b in [0, 0.5], throw_c in [0, 10]: Alciatore's fit is
      9.951e-3, 0.108, 1.088; friction between balls stays below 0.6.
    - m_cue in [0.3, 1] kg: cues weigh 0.45-0.7 kg; with a heavier cue the ball would leave
      faster than twice the cue's speed bound allows for.
    - mathavan_steps in [1, 32] (an integer): 4 is the default and already within 1e-4 of the
      converged rebound; each step of an impact costs a few microseconds.
    """

    R: _within(0.02, 0.04) | None = None
    m: _within(0.05, 0.5) | None = None
    u_s: _within(0.05, 1.0) | None = None
    u_r: _within(0.005, 0.05) | None = None
    u_sp: _within(0.002, 0.1) | None = None
    e_b: _within(0.0, 1.0) | None = None
    e_c: _within(0.0, 0.98) | None = None
    f_c: _within(0.0, 0.5) | None = None
    g: _within(9.5, 10.0) | None = None
    throw_a: _within(0.0, 0.1) | None = None
    throw_b: _within(0.0, 0.5) | None = None
    throw_c: _within(0.0, 10.0) | None = None
    m_cue: _within(0.3, 1.0) | None = None
    mathavan_steps: Annotated[int, Strict(), Field(ge=1, le=32)] | None = None


#: A table is a preset's name or an object of overrides; the tags only route the validation
#: (and are left out of error messages).
_TAGS = ("by_name", "by_fields")
TableChoice = Annotated[
    Annotated[PresetName, Tag("by_name")] | Annotated[TableIn, Tag("by_fields")],
    Discriminator(lambda v: "by_name" if isinstance(v, str) else "by_fields"),
]


class SceneIn(_Strict):
    table: TableChoice = "nineball"
    params: ParamsIn = ParamsIn()
    balls: dict[BallId, tuple[Finite, Finite]] = Field(min_length=1, max_length=32)
    initial: dict[BallId, Motion] = Field(default_factory=dict, max_length=32)
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


def _set(model: BaseModel) -> dict[str, Any]:
    """The fields a scene gave (not None), without `preset`."""
    return {k: v for k, v in model if v is not None and k != "preset"}


def _table(table: str | TableIn) -> tuple[TableSpec, Params]:
    if isinstance(table, str):
        return PRESETS[table]
    spec, params = PRESETS[table.preset]
    return replace(spec, name="custom", **_set(table)), params


def _check_positions(scene: Scene) -> None:
    g, R = scene.geometry, scene.params.R
    items = list(scene.positions.items())
    for name, (x, y) in items:
        problem = position_problem(g, R, x, y, CONTACT_TOLERANCE)
        if problem:
            raise SceneError(f"ball {name} at ({x}, {y}) is {problem}")
    for k, (a, (xa, ya)) in enumerate(items):
        for b, (xb, yb) in items[k + 1 :]:
            if math.hypot(xb - xa, yb - ya) < 2 * R - CONTACT_TOLERANCE:
                raise SceneError(f"balls {a} and {b} overlap")


def _plain(text: object, limit: int = 40) -> str:
    """Text from a document made safe for a one-line message: escaped, and cut at `limit`."""
    out = str(text).encode("unicode_escape").decode("ascii")
    return out if len(out) <= limit else out[: limit - 3] + "..."


def _one_line(exc: ValidationError) -> str:
    first = exc.errors(include_input=False)[0]
    where = ".".join(_plain(x) for x in first["loc"] if x not in _TAGS) or "scene"
    return f"{where}: {_plain(first['msg'], 200)}"


def unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """An object's members (`json.loads`' `object_pairs_hook`); ValueError for a key given
    twice. JSON leaves duplicates undefined and Python keeps the last silently, so a document
    could say two things and be read as one: every JSON the project reads refuses them."""
    members: dict[str, Any] = {}
    for key, value in pairs:
        if key in members:
            raise ValueError(f"duplicate key {key!r}")
        members[key] = value
    return members


def scene_from_json(document: bytes | str) -> dict[str, Any]:
    """Decode a scene document: at most MAX_SCENE_BYTES of UTF-8 JSON holding an object.

    Whatever the bytes (not UTF-8, not JSON, a key twice in an object, nested past the
    parser's recursion limit, integers too long to convert, too long a document), the failure
    is a SceneError.
    """
    if len(document) > MAX_SCENE_BYTES:
        raise SceneError(f"a scene document is at most {MAX_SCENE_BYTES} bytes")
    try:
        text = document.decode("utf-8") if isinstance(document, bytes) else document
        data = json.loads(text, object_pairs_hook=unique_keys)
    except UnicodeDecodeError:
        raise SceneError("a scene document is UTF-8 text") from None
    except RecursionError:
        raise SceneError("the scene document is nested too deeply") from None
    except ValueError as exc:  # JSONDecodeError, and integers past Python's digit limit
        raise SceneError(f"not JSON: {str(exc).splitlines()[0]}") from None
    if not isinstance(data, dict):
        raise SceneError("a scene is a JSON object")
    return data


def parse_scene(data: dict[str, Any]) -> Scene:
    """Validate a scene dictionary (the format README.md documents)."""
    if not isinstance(data, dict):
        raise SceneError("a scene is a JSON object")
    try:
        raw = SceneIn.model_validate(data)
    except ValidationError as exc:
        raise SceneError(_one_line(exc)) from None
    except RecursionError:
        raise SceneError("the scene is nested too deeply") from None
    spec, params = _table(raw.table)
    overrides = _set(raw.params)
    if overrides:  # else the preset's own: a batch's scenes then share it (physics.batch)
        params = replace(params, **overrides)
    problem = table_problem(spec, params.R)
    if problem:
        raise SceneError(problem)
    scene = Scene(
        geometry=spec.geometry(),
        params=params,
        models=raw.models,
        positions={k: (float(x), float(y)) for k, (x, y) in raw.balls.items()},
        initial=raw.initial,
        strike=raw.strike,
    )
    unknown = sorted(set(raw.initial) - set(raw.balls))
    if raw.strike is not None and raw.strike.ball not in raw.balls:
        unknown.append(raw.strike.ball)
    if unknown:
        raise SceneError(f"unknown ball ids: {', '.join(unknown)}")
    _check_positions(scene)
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

"""What a player sends: a shot (with its pre-shot choices) or a choice after an opponent's shot.

Inputs are canonical from the moment they exist. Numbers are parsed strictly (a number, never a
string such as "3.0" or a boolean), must be finite, and are quantised on validation to the
fixed-point steps below, which are also what the compact record stores (rules.compact): the
shot the engine plays is exactly the shot a record holds, so a record, its JSON and its share
link replay bit for bit. The heading is normalised to [0, 360). The strike bounds are the
engine's own (physics.cue), so an input accepted here is never refused by the engine.

`accept` is the one entry point for input from outside: it turns JSON or a decoded message
into an input or a `RuleError` with a code.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Discriminator,
    Field,
    Tag,
    TypeAdapter,
    ValidationError,
    field_validator,
    model_validator,
)

from physics.cue import MAX_ELEVATION, MAX_SPEED, MISCUE_LIMIT
from physics.scene import BallId
from rules.codes import Refusal, RuleError

#: Fixed-point steps per unit: heading 1e-4 degree, speed 1 mm/s, tip offsets 1e-3 R,
#: elevation 0.01 degree, placements 0.1 mm.
HEADING_STEPS = 10_000
SPEED_STEPS = 1_000
TIP_STEPS = 1_000
ELEVATION_STEPS = 100
PLACE_STEPS = 10_000

#: A full turn in heading steps: canonical headings are integers in [0, FULL_TURN).
FULL_TURN = 360 * HEADING_STEPS
#: Farthest a placement may be from the origin before quantising (m); the table check that
#: follows is much tighter, this only keeps the fixed-point integers small.
MAX_PLACE = 100.0

Number = Annotated[float, Field(strict=True, allow_inf_nan=False)]
#: A ball or pocket name: what the engine takes as a ball id, and nothing else.
Name = Annotated[BallId, Field(strict=True)]


def fixed(value: float, steps: int) -> int:
    """`value` in units of 1/steps, rounded to the nearest (half to even): the stored integer.

    For a canonical value (one that came out of `fixed(...) / steps`) this is exact.
    """
    return round(value * steps)


def quantise(value: float, steps: int) -> float:
    return fixed(value, steps) / steps


def heading_steps(heading: float) -> int:
    """A heading in degrees as canonical steps in [0, FULL_TURN)."""
    return fixed(math.fmod(heading, 360.0), HEADING_STEPS) % FULL_TURN


class Strike(BaseModel):
    """The cue's stroke, exactly as the physics scene's `strike` takes it, quantised.

    The bounds are the engine's (physics.cue) and stand in the JSON schema too, so a client
    reading the schema sends only what is accepted; any value within them stays within them
    when quantised. A miscue (|(a, b)| over the limit) is a well-formed stroke the rules
    refuse (a `value_error`), not a malformed number.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    ball: Name
    speed: Annotated[Number, Field(ge=1 / SPEED_STEPS, le=MAX_SPEED)]
    heading: Number
    elevation: Annotated[Number, Field(ge=0.0, le=MAX_ELEVATION)] = 0.0
    a: Annotated[Number, Field(ge=-MISCUE_LIMIT, le=MISCUE_LIMIT)] = 0.0
    b: Annotated[Number, Field(ge=-MISCUE_LIMIT, le=MISCUE_LIMIT)] = 0.0

    @field_validator("heading")
    @classmethod
    def _heading(cls, v: float) -> float:
        return heading_steps(v) / HEADING_STEPS

    @field_validator("speed")
    @classmethod
    def _speed(cls, v: float) -> float:
        return quantise(v, SPEED_STEPS)

    @field_validator("elevation")
    @classmethod
    def _elevation(cls, v: float) -> float:
        return quantise(v, ELEVATION_STEPS)

    @field_validator("a", "b")
    @classmethod
    def _tip(cls, v: float) -> float:
        return quantise(v, TIP_STEPS)

    @model_validator(mode="after")
    def _no_miscue(self) -> Strike:
        if math.hypot(self.a, self.b) > MISCUE_LIMIT:
            raise ValueError(f"tip offset |(a, b)| must be at most {MISCUE_LIMIT} (miscue)")
        return self


#: A placement coordinate (m): bounded only to keep the fixed-point integers small.
Coordinate = Annotated[Number, Field(ge=-MAX_PLACE, le=MAX_PLACE)]


class Shot(BaseModel):
    """A stroke and the choices a player states before it.

    place: where the cue ball goes when the player has ball in hand (required when the cue
        ball is off the table, optional otherwise).
    push_out: nine-ball, the shot after the break only.
    call: eight-ball, the pocket called for the 8 (only when shooting at the 8).
    nominate: snooker, the ball nominated as the free ball, or the colour nominated after a
        red (if no colour is nominated, the colour the cue ball hits first is taken as it).
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    strike: Strike
    place: tuple[Coordinate, Coordinate] | None = None
    push_out: Annotated[bool, Field(strict=True)] = False
    call: Name | None = None
    nominate: Name | None = None

    @field_validator("place")
    @classmethod
    def _quantise_place(cls, v: tuple[float, float] | None) -> tuple[float, float] | None:
        return None if v is None else (quantise(v[0], PLACE_STEPS), quantise(v[1], PLACE_STEPS))


class ShotOptions(BaseModel):
    """The declarations a shot may carry in the present state (each referee says which).

    push_out: a push-out may be declared. call: when not empty, a pocket must be called and
    must be one of these; when empty, no call is allowed. nominate: the balls that may be
    nominated (none: no nomination allowed).
    """

    model_config = ConfigDict(frozen=True)

    push_out: bool = False
    call: tuple[str, ...] = ()
    nominate: frozenset[str] = frozenset()


Option = Literal["play_on", "play_again", "replace"]
OPTIONS: tuple[Option, ...] = ("play_on", "play_again", "replace")


class Choice(BaseModel):
    """A decision offered after the opponent's shot.

    play_on: take the table as it lies. play_again: make the opponent shoot again from here
    (snooker after a foul; nine-ball after a push-out). replace: snooker after a foul and a
    miss: the balls go back where they were and the offender plays again.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    option: Option


def _kind(value: Any) -> str:
    """Tell a shot from a choice by its fields, so records need no type tag."""
    if isinstance(value, dict):
        return "choice" if "option" in value else "shot"
    return "choice" if isinstance(value, Choice) else "shot"


PlayerInput = Annotated[
    Annotated[Shot, Tag("shot")] | Annotated[Choice, Tag("choice")], Discriminator(_kind)
]

_INPUT = TypeAdapter(PlayerInput)


def _malformed(exc: ValidationError) -> RuleError:
    first = exc.errors()[0]
    where = ".".join(str(x) for x in first["loc"] if x not in ("shot", "choice"))
    return RuleError(Refusal.MALFORMED, f"{where or 'input'}: {first['msg']}")


def accept(data: str | bytes | dict[str, Any]) -> Shot | Choice:
    """An input from outside (JSON text, or a decoded JSON/msgpack object), canonical.

    Raises RuleError (code MALFORMED) naming the first problem. The game service calls this
    once, when an input arrives, and stores and plays exactly what it returns.
    """
    if not isinstance(data, str | bytes | dict):
        raise RuleError(Refusal.MALFORMED, "an input is a JSON object")
    try:
        if isinstance(data, dict):
            return _INPUT.validate_python(data)
        return _INPUT.validate_json(data)
    except ValidationError as exc:
        raise _malformed(exc) from None


def check_canonical(action: Shot | Choice) -> None:
    """Refuse an input that bypassed validation (`model_construct`) or is not canonical:
    validating its fields again must give the same input."""
    try:
        again = _INPUT.validate_python(action.model_dump())
    except ValidationError as exc:
        raise _malformed(exc) from None
    if again != action:
        raise RuleError(Refusal.MALFORMED, "the input is not in canonical (quantised) form")

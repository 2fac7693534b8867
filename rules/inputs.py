"""What a player sends: a shot (with its pre-shot choices) or a choice after an opponent's shot.

These models are the whole of a game record besides its setup, so they stay small: fields at
their defaults are left out when serialised. Numbers are checked here (finite, in range) so that
bad input fails before anything is simulated and changes nothing.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Discriminator, Field, Tag, model_validator

Finite = Annotated[float, Field(allow_inf_nan=False)]

#: Tip offsets farther than this from the ball's centre (as a fraction of R) miscue.
MISCUE_LIMIT = 0.5


class Strike(BaseModel):
    """The cue's stroke, exactly as the physics scene's `strike` takes it."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    ball: str
    speed: Annotated[float, Field(gt=0.0, le=12.0, allow_inf_nan=False)]
    heading: Finite
    elevation: Annotated[float, Field(ge=0.0, le=90.0, allow_inf_nan=False)] = 0.0
    a: Finite = 0.0
    b: Finite = 0.0

    @model_validator(mode="after")
    def _no_miscue(self) -> Strike:
        if math.hypot(self.a, self.b) > MISCUE_LIMIT:
            raise ValueError(f"tip offset |(a, b)| must be at most {MISCUE_LIMIT} (miscue)")
        return self


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
    place: tuple[Finite, Finite] | None = None
    push_out: bool = False
    call: str | None = None
    nominate: str | None = None


Option = Literal["play_on", "play_again", "replace"]


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

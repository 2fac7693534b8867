"""The wire models of the recorded real shots (`/api/real-shots`, docs/protocol.md).

A shot's tracks are in the engine's frame of the three-cushion table (x across, y along its
length, metres, origin at a corner) and the recording's time (seconds): each ball's track is
rows [t, x, y]. The recorded rows are the tracker's samples; the simulated rows are the
engine's shot of the strike, sampled for drawing.
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from physics.cue import MAX_SPEED, MISCUE_LIMIT

#: Simulations one refit may run at most (its last one draws the answer): about half a second
#: of a worker's CPU.
MAX_REFIT_SIMULATIONS = 2000
#: CPU seconds one refit may take at most (checked before each simulation).
MAX_REFIT_SECONDS = 2.0

Track = list[tuple[float, float, float]]


class _Model(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")


class RealStrike(_Model):
    """A strike on a recorded shot's cue ball: heading (degrees from +x, the engine's frame),
    cue speed (m/s), tip offsets a (right) and b (up) as fractions of R, and t0, the moment
    of the strike in the recording (s). The elevation is 0, as in the fit."""

    heading: float = Field(ge=-360.0, le=360.0, allow_inf_nan=False)
    speed: float = Field(gt=0.0, le=MAX_SPEED, allow_inf_nan=False)
    a: float = Field(ge=-MISCUE_LIMIT, le=MISCUE_LIMIT, allow_inf_nan=False)
    b: float = Field(ge=-MISCUE_LIMIT, le=MISCUE_LIMIT, allow_inf_nan=False)
    t0: float = Field(ge=0.0, le=1.0, allow_inf_nan=False)


class RealModels(_Model):
    """The engine's model choices a refit may make (docs/physics.md)."""

    cushion: Literal["mathavan", "han"] = "mathavan"
    ball_ball: Literal["alciatore", "frictionless"] = "alciatore"


class RealShotFitRequest(_Model):
    """A refit: from `strike` (absent: the shipped fit's), with `models`, refined by least
    squares in at most `simulations` simulations (1: the strike is only simulated) and
    `MAX_REFIT_SECONDS` of CPU."""

    strike: RealStrike | None = None
    models: RealModels = RealModels()
    simulations: int = Field(default=MAX_REFIT_SIMULATIONS, ge=1, le=MAX_REFIT_SIMULATIONS)


class RealShotFit(_Model):
    """A strike's fit to a recorded shot: its cue-ball and all-balls RMSE (cm, the recording's
    units, the simulated position at each recorded sample), the simulations and CPU seconds
    this answer took, why it stopped ("evaluated", "converged", "simulations", "time"), and
    each ball's recorded and simulated track."""

    id: int
    cue: str
    strike: RealStrike
    models: RealModels
    rmse_cm: float
    rmse_all_cm: float
    simulations: int
    seconds: float
    stopped: Literal["evaluated", "converged", "simulations", "time"]
    recorded: dict[str, Track]
    simulated: dict[str, Track]


class RealShotEntry(_Model):
    """One recorded shot as the list shows it, with the shipped fit's figures."""

    id: int
    cue: str
    duration: float
    rmse_cm: float
    rmse_all_cm: float


class RealShotList(_Model):
    """The recorded shots shipped with the server, the figures of their shipped fits, and
    what those fits were made with."""

    shots: list[RealShotEntry]
    median_rmse_cm: float
    engine_version: str
    source: str
    max_simulations: int = MAX_REFIT_SIMULATIONS
    max_seconds: float = MAX_REFIT_SECONDS

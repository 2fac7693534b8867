"""One interface over the four referees: start a game, check an input, play it.

Each referee module (nineball, eightball, snooker, three_cushion) provides `TABLE`,
`new_game`, `cue_ball`, `check_shot` and `judge`; everything common to all four lives here:
whose turn it is, ball-in-hand placement, choices after a shot, and building the physics scene.
An input is checked completely before the engine runs, so a rejected input changes nothing.
"""

from __future__ import annotations

from collections.abc import Callable
from types import ModuleType
from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field

from physics import ENGINE_VERSION
from rules import eightball, nineball, snooker, three_cushion
from rules.inputs import Choice, PlayerInput, Shot
from rules.racks import GameName
from rules.spots import Point, in_region, is_free
from rules.state import Decision, RuleError, State, other

REFEREES: dict[str, ModuleType] = {
    "nineball": nineball,
    "eightball": eightball,
    "snooker": snooker,
    "three_cushion": three_cushion,
}

REGION_WORDS = {
    "anywhere": "anywhere on the table",
    "kitchen": "behind the head string",
    "D": "in the D",
}

Simulate = Callable[[dict], dict]


class Setup(BaseModel):
    """What fixes a game before the first shot: the rule set, the rack seed and options.

    gap: the largest extra space between rack balls (m), see `rules.racks`.
    target: three-cushion points to win (0 = the default of 15); ignored by the other games.
    engine: the physics engine version the game is played with (physics.ENGINE_VERSION).
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    game: GameName
    seed: Annotated[int, Field(ge=0, lt=2**63)]
    gap: Annotated[float, Field(ge=0.0, le=0.005, allow_inf_nan=False)] = 0.0
    target: Annotated[int, Field(ge=0, le=1000)] = 0
    engine: str = ENGINE_VERSION


def start(setup: Setup) -> State:
    return REFEREES[setup.game].new_game(setup.seed, setup.gap, setup.target)


def shot_position(state: State, shot: Shot) -> dict[str, Point]:
    """The balls as they stand when the cue strikes: the table plus any cue-ball placement.

    Raises RuleError for a shot the player may not play now.
    """
    ref = REFEREES[state.game]
    if state.over:
        raise RuleError("the game is over")
    if state.pending:
        raise RuleError(f"P{state.turn + 1} must first choose: {' / '.join(state.pending)}")
    cue = ref.cue_ball(state)
    if shot.strike.ball != cue:
        raise RuleError(f"P{state.turn + 1} must strike the {cue} ball, not {shot.strike.ball!r}")
    balls = dict(state.balls)
    if shot.place is not None:
        region = state.ball_in_hand
        if region is None:
            raise RuleError("no ball in hand: the cue ball cannot be moved")
        place = (float(shot.place[0]), float(shot.place[1]))
        if not in_region(place, region, ref.TABLE):
            raise RuleError(f"the cue ball must be placed {REGION_WORDS[region]}")
        others = {b: p for b, p in balls.items() if b != cue}
        if not is_free(place, others, ref.TABLE.R):
            raise RuleError("the cue ball cannot be placed on or against another ball")
        balls[cue] = place
    elif cue not in balls:
        raise RuleError("the cue ball is in hand: give a place for it")
    ref.check_shot(state, shot)
    return balls


def scene(state: State, shot: Shot, balls: dict[str, Point]) -> dict:
    """The physics scene of a shot (the engine's input format)."""
    return {
        "table": REFEREES[state.game].TABLE.preset,
        "balls": {b: [p[0], p[1]] for b, p in balls.items()},
        "strike": shot.strike.model_dump(),
    }


def choose(state: State, choice: Choice) -> State:
    """Apply a choice offered after the opponent's shot."""
    if state.over:
        raise RuleError("the game is over")
    if choice.option not in state.pending:
        offered = " / ".join(state.pending) or "nothing"
        raise RuleError(f"{choice.option!r} is not an option now (offered: {offered})")
    if choice.option == "play_on":
        return state.model_copy(update={"pending": (), "retake": None})
    if choice.option == "play_again":
        update = {"pending": (), "turn": other(state.turn), "free_ball": False, "retake": None}
        return state.model_copy(update=update)
    restored = {"scores": state.scores, "best": state.best, "shots": state.shots}
    return state.retake.model_copy(update=restored)


def default_simulate(scene_: dict) -> dict:
    import physics

    return physics.simulate_scene(scene_)


def play(
    state: State, action: PlayerInput, simulate: Simulate = default_simulate
) -> tuple[State, Decision | None]:
    """The state after a player's input and, for a shot, the referee's decision."""
    if isinstance(action, Choice):
        return choose(state, action), None
    balls = shot_position(state, action)
    result = simulate(scene(state, action, balls))
    return REFEREES[state.game].judge(state, action, balls, result)

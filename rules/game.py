"""The seam the game service stands on: start a game, check an input, play it.

Everything common to the four referees lives here: whose turn it is, ball-in-hand placement,
a shot's declarations, choices after a shot, and building the physics scene. The game-specific
parts come from the game's `Referee` (rules.referee). An input is checked completely before
the engine runs (`check` is that check alone), so a refused input changes nothing, and `play`
returns the engine's typed result beside the new state so that nothing is simulated twice.
States, inputs and outcomes pickle, so `play` can run in a worker process.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

import physics
from rules.codes import Refusal, RuleError
from rules.inputs import Choice, PlayerInput, Shot, check_canonical, quantise
from rules.positions import check_start, opening
from rules.racks import POOL_GAMES, REDS_FULL, Game
from rules.referee import allowed, referee, table_of
from rules.spots import STANDARD_SIZE, Point, Size, in_region, is_free
from rules.state import Decision, State, other

REGION_WORDS = {
    "anywhere": "anywhere on the table",
    "kitchen": "behind the head string",
    "D": "in the D",
}

#: Rack gaps are in steps of 1e-7 m.
GAP_STEPS = 10_000_000

#: The engine as the referees use it: a validated scene in, the typed shot out.
Simulate = Callable[[physics.Scene], physics.Shot]


class Setup(BaseModel):
    """What fixes a game before the first shot: the rule set, the rack seed and options.

    gap: the largest extra space between rack balls (m), see `rules.racks`; quantised to
        1e-7 m (GAP_STEPS) so that the compact record stores it as an integer.
    target: three-cushion points to win (0 = the default of 15); ignored by the other games.
    reds: snooker's reds, 6, 10 or 15 (the full game); the other games keep 15, unused.
    size: pool's table in feet, 7, 8 or 9 (the standard); the other games keep 9, unused.
    position: a set-up position the rack starts from instead of the seeded rack (practice,
        `rules.positions.check_start`: the game's balls, each where the engine lets a ball
        rest, to the bit); None for the game's own rack.
    breaker: the player (0 or 1) who breaks, so that a match's racks, whose break alternates,
        are each a record of their own with the players as seated. Three-cushion's rack
        places the breaker's ball as the white, so its breaker is always player 0.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    game: Game
    seed: Annotated[int, Field(strict=True, ge=0, lt=2**63)]
    gap: Annotated[float, Field(strict=True, ge=0.0, le=0.005, allow_inf_nan=False)] = 0.0
    target: Annotated[int, Field(strict=True, ge=0, le=1000)] = 0
    breaker: Annotated[int, Field(strict=True, ge=0, le=1)] = 0
    reds: Literal[6, 10, 15] = REDS_FULL
    size: Size = STANDARD_SIZE
    position: dict[str, Point] | None = None

    @field_validator("gap")
    @classmethod
    def _quantise_gap(cls, v: float) -> float:
        return quantise(v, GAP_STEPS)

    @model_validator(mode="after")
    def _white_breaks(self) -> Setup:
        if self.game is Game.THREE_CUSHION and self.breaker != 0:
            raise ValueError("in three-cushion player 0 breaks (the rack's white is theirs)")
        if self.game is not Game.SNOOKER and self.reds != REDS_FULL:
            raise ValueError("only snooker is played with fewer reds")
        if self.game not in POOL_GAMES and self.size != STANDARD_SIZE:
            raise ValueError("only pool is played on tables of other sizes")
        if self.position is not None:
            try:
                check_start(self.game, self.position, self.size, self.reds)
            except RuleError as error:
                raise ValueError(error.reason) from None
        return self

    @property
    def set_up(self) -> bool:
        """The rack starts from a position a player set up, not from the game's rack."""
        return self.position is not None


@dataclass(frozen=True, slots=True)
class Outcome:
    """What one input led to: the new state, and for a shot the referee's decision and the
    engine's result (events and trajectories, to publish as they are); None for a choice."""

    state: State
    decision: Decision | None
    shot: physics.Shot | None


def start(setup: Setup) -> State:
    ref = referee(setup.game)
    first = ref.new_game(setup.seed, setup.gap, setup.target, setup.reds, setup.size)
    if setup.position is not None:
        first = opening(first, setup.position)
    return first.evolve(turn=setup.breaker) if setup.breaker else first


def _check_turn(state: State) -> None:
    if state.over:
        raise RuleError(Refusal.GAME_OVER, "the game is over")


def _check_declarations(state: State, shot: Shot) -> None:
    """Push-out, called pocket and nomination against what the referee allows now."""
    may = referee(state.game).options(state)
    if shot.push_out and not may.push_out:
        raise RuleError(Refusal.NO_PUSH_OUT, "a push-out is not allowed on this shot")
    if may.call and shot.call not in may.call:
        raise RuleError(Refusal.CALL_REQUIRED, f"call a pocket, one of: {', '.join(may.call)}")
    if not may.call and shot.call is not None:
        raise RuleError(Refusal.NO_CALL, "no pocket is called on this shot")
    if shot.nominate is not None and shot.nominate not in may.nominate:
        offered = ", ".join(sorted(may.nominate)) or "none now"
        raise RuleError(
            Refusal.BAD_NOMINATION, f"cannot nominate {shot.nominate!r} (nominate: {offered})"
        )


def shot_position(state: State, shot: Shot) -> dict[str, Point]:
    """The balls as they stand when the cue strikes: the table plus any cue-ball placement.

    Raises RuleError for a shot the player may not play now.
    """
    _check_turn(state)
    now = allowed(state)
    if now.choices:
        raise RuleError(
            Refusal.CHOICE_PENDING,
            f"P{state.turn + 1} must first choose: {' / '.join(now.choices)}",
        )
    check_canonical(shot)
    if shot.strike.ball != now.cue:
        why = f"P{state.turn + 1} must strike the {now.cue} ball, not {shot.strike.ball!r}"
        raise RuleError(Refusal.WRONG_CUE_BALL, why)
    table = table_of(state)
    balls = dict(state.balls)
    if shot.place is not None:
        if now.ball_in_hand is None:
            raise RuleError(Refusal.NOT_IN_HAND, "no ball in hand: the cue ball cannot be moved")
        if not in_region(shot.place, now.ball_in_hand, table):
            why = f"the cue ball must be placed {REGION_WORDS[now.ball_in_hand]}"
            raise RuleError(Refusal.OUTSIDE_REGION, why)
        others = {b: p for b, p in balls.items() if b != now.cue}
        if not is_free(shot.place, others, table.R):
            why = "the cue ball cannot be placed on or against another ball"
            raise RuleError(Refusal.PLACE_BLOCKED, why)
        balls[now.cue] = shot.place
    elif now.cue not in balls:
        raise RuleError(Refusal.PLACE_REQUIRED, "the cue ball is in hand: give a place for it")
    _check_declarations(state, shot)
    return balls


def check_choice(state: State, choice: Choice) -> None:
    _check_turn(state)
    check_canonical(choice)
    if choice.option not in state.pending:
        offered = " / ".join(state.pending) or "nothing"
        why = f"{choice.option!r} is not an option now (offered: {offered})"
        raise RuleError(Refusal.NOT_AN_OPTION, why)


def check(state: State, action: PlayerInput) -> None:
    """Every rule check of an input in `state`, without simulating anything: turn, phase,
    bounds, placement, declarations, pending choices. Raises RuleError (with its code)."""
    if isinstance(action, Choice):
        check_choice(state, action)
    else:
        shot_position(state, action)


def scene(state: State, shot: Shot, balls: dict[str, Point]) -> physics.Scene:
    """The physics scene of a shot, validated by the engine's own parser."""
    return physics.parse_scene(
        {
            "table": table_of(state).preset,
            "balls": {b: [p[0], p[1]] for b, p in balls.items()},
            "strike": shot.strike.model_dump(),
        }
    )


def choose(state: State, choice: Choice) -> State:
    """Apply a choice offered after the opponent's shot."""
    check_choice(state, choice)
    if choice.option == "play_on":
        return state.evolve(pending=(), retake=None)
    if choice.option == "play_again":
        return state.evolve(pending=(), turn=other(state.turn), free_ball=False, retake=None)
    return state.retake.evolve(scores=state.scores, best=state.best, shots=state.shots)


def play(state: State, action: PlayerInput, simulate: Simulate = physics.simulate) -> Outcome:
    """The outcome of a player's input: the new state, and for a shot the referee's decision
    and the engine's result. Raises RuleError (nothing simulated) for an input refused."""
    if isinstance(action, Choice):
        return Outcome(state=choose(state, action), decision=None, shot=None)
    balls = shot_position(state, action)
    result = simulate(scene(state, action, balls))
    new, decision = referee(state.game).judge(state, action, balls, result)
    return Outcome(state=new, decision=decision, shot=result)

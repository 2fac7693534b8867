"""Every call the game service makes into `rules`, in one place: the seam to the referees.

The match owner checks an input here on the event loop (cheap: no physics), and the worker
processes run `referee` and `bot_input` (the engine runs there, never on the event loop). What
they return is picklable and already in wire form, so the event loop only stores and publishes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import physics
from physics.trajectory import Shot as EngineShot
from rules.game import REFEREES, Setup, choose, play, shot_position, start
from rules.inputs import Choice, PlayerInput, Shot, Strike
from rules.pickers import pick
from rules.racks import GameName
from rules.spots import in_region, is_free
from rules.state import Decision, RuleError, State
from server.api_models import InputKind, Trajectory, WireSegment

#: Cue speed (m/s) of the stroke played when the shot clock runs out: it rolls about 1 cm.
TIMEOUT_SPEED = 0.05
#: Significant digits kept in a published trajectory (animation only; rest positions are exact).
TRAJECTORY_DIGITS = 7

__all__ = [
    "Refereed",
    "RuleError",
    "bot_input",
    "check",
    "constraints",
    "new_rack",
    "referee",
    "rule_code",
    "timeout_input",
]


@dataclass(frozen=True, slots=True)
class Refereed:
    """The result of playing one input: the new state, the decision and the motion (shots).

    void: why an accepted input could not be played (the engine refused its scene); the state
    is then unchanged.
    """

    state: State
    decision: Decision | None
    trajectory: Trajectory | None
    void: str | None = None


def new_rack(game: GameName, seed: int, breaker: int) -> State:
    """The opening position of a rack, with `breaker` (a seat) to play the break."""
    return start(Setup(game=game, seed=seed)).model_copy(update={"turn": breaker})


def canonical(action: PlayerInput) -> PlayerInput:
    """The input as the server will play and record it (the rules' canonical form)."""
    return action


def check(state: State, action: PlayerInput) -> None:
    """RuleError if the player to act may not send `action` now (nothing is simulated)."""
    if isinstance(action, Choice):
        choose(state, action)
    else:
        shot_position(state, action)


def rule_code(error: RuleError) -> str | None:
    """The referee's code for a refusal, once the rules give one (None before)."""
    code = getattr(error, "code", None)
    return None if code is None else str(getattr(code, "value", code))


def constraints(state: State) -> tuple[list[InputKind], str, str | None, list[str]]:
    """(kinds, cue ball, ball-in-hand region, options) for the player to act in `state`."""
    cue = REFEREES[state.game].cue_ball(state)
    if state.pending:
        return [InputKind.CHOICE], cue, None, list(state.pending)
    return [InputKind.SHOT], cue, state.ball_in_hand, []


def _round(x: float) -> float:
    return float(f"{x:.{TRAJECTORY_DIGITS}g}")


def wire_trajectory(shot: EngineShot) -> Trajectory:
    """The engine's segments as compact arrays (see docs/protocol.md, the outcome message)."""
    balls: dict[str, list[WireSegment]] = {}
    for ball, segments in shot.trajectories.items():
        balls[ball] = [
            (_round(s.t), s.state, *map(_round, (*s.r, *s.v, *s.a, *s.w, *s.dw))) for s in segments
        ]
    return Trajectory(duration=shot.duration, events=shot.events, balls=balls)


def referee(state: State, action: PlayerInput) -> Refereed:
    """Simulate and judge one checked input (run in a worker process)."""
    shots: list[EngineShot] = []

    def simulate(scene: dict) -> dict:
        shots.append(physics.simulate(scene))
        return shots[-1].summary()

    try:
        new_state, decision = play(state, action, simulate)
    except (RuleError, physics.SceneError, physics.SimulationError) as error:
        return Refereed(state=state, decision=None, trajectory=None, void=str(error))
    trajectory = wire_trajectory(shots[0]) if shots else None
    return Refereed(state=new_state, decision=decision, trajectory=trajectory)


def timeout_input(state: State) -> PlayerInput:
    """What the server plays for a player whose shot clock ran out (see server/clock.py).

    A pending choice takes the first option offered; otherwise a dead-slow stroke of the cue
    ball straight away from the nearest ball (placed first, on the first free point of a grid
    over the region, if it is in hand off the table), which the referee rules as a shot that
    hit no ball: a foul in pool and snooker, no point and the turn over in three-cushion.
    """
    if state.pending:
        return Choice(option=state.pending[0])
    referee_ = REFEREES[state.game]
    table, cue = referee_.TABLE, referee_.cue_ball(state)
    others = {ball: p for ball, p in state.balls.items() if ball != cue}
    at, place = state.balls.get(cue), None
    if at is None:
        grid = [
            (table.width * i / 8, table.length * j / 32) for j in range(1, 32) for i in range(1, 8)
        ]
        region = state.ball_in_hand or "anywhere"
        at = place = next(
            p for p in grid if in_region(p, region, table) and is_free(p, others, table.R)
        )
    nearest = min(others.values(), key=lambda p: math.dist(p, at))
    heading = math.degrees(math.atan2(at[1] - nearest[1], at[0] - nearest[0])) % 360.0
    strike = Strike(ball=cue, speed=TIMEOUT_SPEED, heading=round(heading, 4))
    return Shot(strike=strike, place=place)


def bot_input(state: State) -> PlayerInput:
    """The shot pickers' input for the player to act (run in a worker process)."""
    return pick(state)

"""Three-cushion billiards referee (UMB rules), one game to `target` points.

- Each player has his own cue ball: the first player (the breaker) white, the second yellow;
  the red is shared.
- A point: the cue ball contacts both object balls and, before it contacts the second one, has
  touched cushions at least three times (cushion contacts before the first ball count too).
- The break: the cue ball must contact the red first; otherwise no point.
- The player continues after a point; otherwise the inning passes to the opponent. The run
  (points in one inning) is tracked, and `best` holds each player's highest run.
- The first to reach `target` points wins (the equalising inning of some tournaments is left
  out: the rule set is the plain "race to N" of most leagues and online play).

Left out: frozen balls (the cue ball touching a ball, where UMB lets the player have the balls
spotted) and fouls that the engine cannot produce (jumping off the table, push shots, touching
a ball with the hand or cue).
"""

from __future__ import annotations

from collections.abc import Mapping

import physics
from physics.trajectory import Event
from rules.codes import FoulCode, NoteCode
from rules.events import CUSHION_EVENTS, read_shot
from rules.inputs import Shot, ShotOptions
from rules.racks import REDS_FULL, Game, rack
from rules.spots import CAROM_TABLE, Point
from rules.state import Decision, Foul, State, award, conclude, foul, note, other

GAME = Game.THREE_CUSHION
TABLE = CAROM_TABLE
CUE_BALLS = ("white", "yellow")
CUSHIONS_NEEDED = 3
DEFAULT_TARGET = 15


def new_game(
    seed: int, gap: float = 0.0, target: int = 0, reds: int = REDS_FULL, size: int = 9
) -> State:
    return State(
        game=GAME,
        balls=rack(GAME, seed, gap),
        target=target or DEFAULT_TARGET,
    )


def cue_ball(state: State) -> str:
    return CUE_BALLS[state.turn]


def targets(state: State, balls: Mapping[str, Point]) -> frozenset[str]:
    """The red on the break, either object ball afterwards."""
    if state.shots == 0:
        return frozenset({"red"} & set(balls))
    return frozenset(balls) - {cue_ball(state)}


def options(state: State) -> ShotOptions:
    return ShotOptions()


def count_point(events: list[Event], cue: str) -> tuple[bool, list[str], int]:
    """Whether `cue` scored, the object balls it touched in order, and its cushions before
    the second object ball (or in all, if it never reached it)."""
    touched: list[str] = []
    cushions = 0
    for ev in events:
        if cue not in ev.balls:
            continue
        if ev.type in CUSHION_EVENTS:
            cushions += 1
        elif ev.type == "ball_ball":
            hit = next(b for b in ev.balls if b != cue)
            if hit not in touched:
                touched.append(hit)
                if len(touched) == 2:
                    return cushions >= CUSHIONS_NEEDED, touched, cushions
    return False, touched, cushions


def judge(
    state: State, shot: Shot, before: dict[str, Point], result: physics.Shot
) -> tuple[State, Decision]:
    me, opp = state.turn, other(state.turn)
    cue = cue_ball(state)
    scored, touched, cushions = count_point(result.events, cue)
    fouls: list[Foul] = []
    if state.shots == 0 and touched and touched[0] != "red":
        why = f"on the break the cue ball must hit the red first (hit the {touched[0]})"
        fouls.append(foul(FoulCode.BREAK_NOT_RED, why, touched[0]))
        scored = False
    if scored:
        said = note(NoteCode.POINT, f"point ({cushions} cushions before the second ball)")
    elif len(touched) == 2:
        why = f"no point: only {cushions} cushions before the second ball"
        said = note(NoteCode.NO_POINT_CUSHIONS, why)
    else:
        why = f"no point: the cue ball touched {len(touched)} object ball(s)"
        said = note(NoteCode.NO_POINT_CONTACT, why)
    notes = [said]
    positions = read_shot(result, cue, before).positions
    visit = state.visit + int(scored)
    best = list(state.best)
    best[me] = max(best[me], visit)
    points = award(me, int(scored))
    won = state.scores[me] + points[me] >= state.target
    return conclude(
        state,
        balls=positions,
        next_player=me if scored else opp,
        fouls=fouls,
        points=points,
        notes=notes,
        winner=me if won else None,
        visit=visit if scored else 0,
        best=tuple(best),
    )

"""Nine-ball referee (WPA world standardized rules), one rack.

- The break: the cue ball (in hand behind the head string) must hit the 1 first; the break is
  legal when a ball is pocketed or four object balls reach a cushion.
- Every later shot: the lowest-numbered ball first, then a ball pocketed or any ball to a
  cushion. A scratch, a miss, the wrong ball first or no rail is a foul.
- Push-out: the player shooting the shot right after the break may declare one; it need not
  hit any ball or cushion (a scratch is still a foul), and the opponent then chooses to play
  on or to make the pusher play again.
- After a foul the opponent has ball in hand anywhere (also after a foul on the break).
- The 9 pocketed on any legal shot wins, the break included, and in combination; pocketed on
  a foul or a push-out it is respotted on the foot spot.
- Three fouls in a row by the same player lose the rack. WPA asks the referee to warn the
  player after the second; the warning is shown as a note, and the rule applies regardless.
- A player continues after legally pocketing any ball.

Left out: jump and masse fouls, balls off the table (the engine keeps every ball on the table
or in a pocket) and the re-rack options, which a one-rack game has no use for.
"""

from __future__ import annotations

from collections.abc import Mapping

import physics
from rules import pool
from rules.codes import NoteCode
from rules.events import read_shot
from rules.inputs import Shot, ShotOptions
from rules.racks import REDS_FULL, Game, rack
from rules.spots import POOL_TABLE, STANDARD_SIZE, Point, Size
from rules.state import Decision, State, note, other

GAME = Game.NINEBALL
TABLE = POOL_TABLE
FOULS_TO_LOSE = 3
#: The shot right after the break, the only one that may be a push-out.
PUSH_OUT_SHOT = 1


def new_game(
    seed: int, gap: float = 0.0, target: int = 0, reds: int = REDS_FULL, size: Size = STANDARD_SIZE
) -> State:
    balls = rack(GAME, seed, gap, size=size)
    return State(game=GAME, balls=balls, ball_in_hand="kitchen", size=size)


def cue_ball(state: State) -> str:
    return "cue"


def lowest(balls: Mapping[str, Point]) -> str:
    return min(pool.object_balls(balls), key=int)


def targets(state: State, balls: Mapping[str, Point]) -> frozenset[str]:
    """The lowest-numbered ball (none once the table is empty, after the game)."""
    return frozenset({lowest(balls)}) if pool.object_balls(balls) else frozenset()


def options(state: State) -> ShotOptions:
    return ShotOptions(push_out=True) if state.shots == PUSH_OUT_SHOT else pool.PLAIN


def judge(
    state: State, shot: Shot, before: dict[str, Point], result: physics.Shot
) -> tuple[State, Decision]:
    me, opp = state.turn, other(state.turn)
    facts = read_shot(result, "cue", before)
    on = lowest(before)
    breaking = state.shots == 0
    if shot.push_out:
        fouls = [pool.SCRATCH] if facts.cue_pocketed else []
    else:
        fouls = pool.contact_fouls(facts, frozenset({on}), f"the {on}", rail=not breaking)
        if breaking:
            fouls += pool.break_fouls(facts)
    positions = dict(facts.positions)
    respotted: dict[str, Point] = {}
    notes = [note(NoteCode.PUSH_OUT, "push-out")] if shot.push_out else []
    nine_down = "9" in facts.pocketed
    if nine_down and (fouls or shot.push_out):
        respotted["9"] = positions["9"] = pool.respot_on_foot_spot(positions, state.size)

    fouls_now = list(state.foul_streak)
    fouls_now[me] = fouls_now[me] + 1 if fouls else 0
    winner = None
    if fouls and fouls_now[me] >= FOULS_TO_LOSE:
        winner = opp
        notes.append(note(NoteCode.THREE_FOULS, f"{FOULS_TO_LOSE} fouls in a row lose the rack"))
    elif nine_down and not fouls and not shot.push_out:
        winner = me
    elif fouls and fouls_now[me] == FOULS_TO_LOSE - 1:
        notes.append(note(NoteCode.FOUL_WARNING, f"P{me + 1} is on {FOULS_TO_LOSE - 1} fouls"))

    if winner is not None:
        nxt, bih, pending = winner, None, ()
    elif fouls:
        nxt, bih, pending = opp, "anywhere", ()
    elif shot.push_out:
        nxt, bih, pending = opp, None, ("play_on", "play_again")
    else:
        nxt, bih, pending = (me if facts.pocketed else opp), None, ()
    verdict = (nxt, bih, winner)
    return pool.conclude_rack(
        state,
        facts,
        positions,
        verdict,
        fouls,
        respotted,
        notes,
        options=pending,
        foul_streak=tuple(fouls_now),
    )

"""Eight-ball referee (WPA world standardized rules, as online players expect them), one rack.

- The break: cue ball in hand behind the head string; legal when a ball is pocketed or four
  object balls reach a cushion. An illegal break or a scratch on the break is a foul: the
  opponent gets ball in hand behind the head string. The breaker continues after pocketing a
  ball on a legal break. The table is open after the break whatever was pocketed.
- The 8 pocketed on the break is respotted on the foot spot; the breaker plays on (or, if he
  also scratched, the opponent gets ball in hand behind the head string). WPA also lets the
  player re-rack instead; left out, as a record replays one rack.
- Open table: any solid or stripe may be hit first, never the 8. The first ball legally
  pocketed decides the groups: its group goes to the shooter (if both groups fall on that
  shot, the first to drop decides).
- Later shots: own group first (the 8 once the group is cleared), then a ball pocketed or any
  ball to a cushion; otherwise a foul, and the opponent has ball in hand anywhere.
- The shooter continues after pocketing a ball of his own group (any ball on an open table).
- The 8: only it is called (the common online form of "call shot"); the player on the 8
  names a pocket. Pocketing it legally in the called pocket wins. Pocketing it before the group
  is cleared, in another pocket, or on a foul (a scratch included) loses the rack.

Left out: calling every shot (obvious balls need no call in WPA and the engine's result says
where each ball went), jump and masse fouls, balls off the table, and the "cue ball behind
the head string must first cross it" detail of a kitchen ball in hand.
"""

from __future__ import annotations

from collections.abc import Mapping

import physics
from rules import pool
from rules.codes import NoteCode
from rules.events import ShotFacts, read_shot
from rules.inputs import Shot, ShotOptions
from rules.racks import REDS_FULL, SOLIDS, STRIPES, Game, rack
from rules.spots import POOL_TABLE, STANDARD_SIZE, Point, Size
from rules.state import Decision, Foul, Group, Note, State, note, other

GAME = Game.EIGHTBALL
TABLE = POOL_TABLE
#: On the 8, a pocket must be called.
CALL_THE_EIGHT = ShotOptions(call=pool.POCKETS)


def new_game(
    seed: int, gap: float = 0.0, target: int = 0, reds: int = REDS_FULL, size: Size = STANDARD_SIZE
) -> State:
    balls = rack(GAME, seed, gap, size=size)
    return State(game=GAME, balls=balls, ball_in_hand="kitchen", size=size)


def cue_ball(state: State) -> str:
    return "cue"


def group_of(ball: str) -> Group | None:
    if ball in SOLIDS:
        return "solids"
    if ball in STRIPES:
        return "stripes"
    return None


def wanted(state: State, balls: Mapping[str, Point]) -> tuple[frozenset[str], str]:
    """The balls the player to shoot may hit first, and how to name them in a foul."""
    mine = state.groups[state.turn]
    objects = [b for b in pool.object_balls(balls) if b != "8"]
    eight = (frozenset({"8"} & set(balls)), "the 8")
    if mine is None:
        return (frozenset(objects), "a solid or a stripe") if objects else eight
    own = frozenset(b for b in objects if group_of(b) == mine)
    return (own, f"one of the {mine}") if own else eight


def targets(state: State, balls: Mapping[str, Point]) -> frozenset[str]:
    return wanted(state, balls)[0]


def on_eight(state: State, balls: Mapping[str, Point]) -> bool:
    return state.shots > 0 and targets(state, balls) == {"8"}


def options(state: State) -> ShotOptions:
    return CALL_THE_EIGHT if on_eight(state, state.balls) else pool.PLAIN


def _eight_verdict(
    state: State, shot: Shot, facts: ShotFacts, on_eight: bool, fouls: list[Foul]
) -> tuple[int, Note]:
    """Who wins when the 8 drops after the break, and why."""
    me, opp = state.turn, other(state.turn)
    pocket = facts.pocketed["8"]
    if not on_eight:
        why = "8 pocketed before the group was cleared: loss of rack"
        return opp, note(NoteCode.EIGHT_EARLY, why)
    if fouls:
        return opp, note(NoteCode.EIGHT_ON_FOUL, "8 pocketed on a foul: loss of rack")
    if pocket != shot.call:
        why = f"8 pocketed in {pocket}, not the called {shot.call}: loss of rack"
        return opp, note(NoteCode.EIGHT_WRONG_POCKET, why)
    return me, note(NoteCode.EIGHT_CALLED, "8 pocketed in the called pocket")


def judge(
    state: State, shot: Shot, before: dict[str, Point], result: physics.Shot
) -> tuple[State, Decision]:
    me, opp = state.turn, other(state.turn)
    facts = read_shot(result, "cue", before)
    positions = dict(facts.positions)
    respotted: dict[str, Point] = {}
    notes: list[Note] = []
    groups = state.groups
    winner = None
    breaking = state.shots == 0
    legal, words = wanted(state, before)
    if breaking:
        fouls = pool.contact_fouls(facts, legal | {"8"}, "a ball", rail=False)
        fouls += pool.break_fouls(facts)
        if "8" in facts.pocketed:
            respotted["8"] = positions["8"] = pool.respot_on_foot_spot(positions, state.size)
            notes.append(note(NoteCode.EIGHT_ON_BREAK, "8 pocketed on the break: respotted"))
    else:
        fouls = pool.contact_fouls(facts, legal, words, rail=True)
        if "8" in facts.pocketed:
            winner, why = _eight_verdict(state, shot, facts, legal == {"8"}, fouls)
            notes.append(why)
    dropped = [b for b in facts.pocketed if b != "8"]
    if not fouls and not breaking and groups[me] is None and dropped:
        first = group_of(dropped[0])
        rest = "stripes" if first == "solids" else "solids"
        groups = (first, rest) if me == 0 else (rest, first)
        notes.append(note(NoteCode.GROUP_TAKEN, f"P{me + 1} takes the {first}"))
    if winner is not None:
        nxt, bih = winner, None
    elif fouls:
        nxt, bih = opp, ("kitchen" if breaking else "anywhere")
    else:
        own = [b for b in dropped if groups[me] is None or group_of(b) == groups[me]]
        scored = facts.pocketed if breaking else own
        nxt, bih = (me if scored else opp), None
    verdict = (nxt, bih, winner)
    return pool.conclude_rack(
        state, facts, positions, verdict, fouls, respotted, notes, groups=groups
    )

"""Why a game was lost: the loser's last act before the winner's final visit, in one word.

The arena keeps every input of a game as a `Turn` (who acted, what they sent, the kind of shot
the bot's search chose when the chooser reports one, and the referee's decision). `classify`
reads a lost game back from its end:

- the loser's own shot ended the game: `THREE_FOULS` when the referee says so, else `FOUL`
  (the 8 down early, in the wrong pocket or with a foul);
- the loser never came to the table (the winner broke and ran out): `BREAK_AND_RUN`, which
  no choice of the loser's answers; the last input was the loser's own break (it pocketed
  nothing or fouled, and the winner ran out from there): `BREAK`, which a better break does;
- otherwise the input that ended the loser's last visit: `PUSH_OUT` (a push-out), `CHOICE`
  (taking the table, or handing it back, after the winner's push-out or foul), `FOUL` (it
  fouled: ball in hand for the winner), `MISSED_POT` (a pot, bank or combination that did not
  drop), `POSITION` (a safety or kick played after the same visit had potted: the pot before
  left no shot), `SAFETY` (a safety or kick that opened the visit and still handed the winner
  a run), `OTHER` (a chooser that does not say what it meant, such as the pickers).

The loser's last act is not always the mistake that mattered, but it is the one the winner's
final visit started from, which is what a change to the bot has to answer; the counts are per
lost game, so they add up to the games lost.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum

from rules.bot.candidates import Kind
from rules.codes import NoteCode
from rules.inputs import Choice, PlayerInput, Shot
from rules.state import Decision

#: The kinds of candidate that try to pocket a ball.
POTS = frozenset({Kind.POT, Kind.BANK, Kind.COMBO})


class Loss(StrEnum):
    BREAK_AND_RUN = "break and run"
    BREAK = "break"
    MISSED_POT = "missed pot"
    FOUL = "foul"
    SAFETY = "safety failed"
    POSITION = "position left"
    THREE_FOULS = "three fouls"
    PUSH_OUT = "push-out"
    CHOICE = "choice"
    OTHER = "other"


@dataclass(frozen=True, slots=True)
class Turn:
    """One input of a game. kind: what the bot's search chose it as (None: not reported)."""

    seat: int
    action: PlayerInput
    kind: Kind | None
    decision: Decision | None


def _potted(decision: Decision | None) -> bool:
    return decision is not None and not decision.fouls and bool(decision.pocketed)


def _ended_own_game(turn: Turn) -> Loss:
    notes = {n.code for n in turn.decision.notes} if turn.decision else set()
    return Loss.THREE_FOULS if NoteCode.THREE_FOULS in notes else Loss.FOUL


def _visit_potted(turns: Sequence[Turn], last: int) -> bool:
    """Whether the visit that `turns[last]` ends potted a ball before it."""
    seat = turns[last].seat
    for turn in reversed(turns[:last]):
        if turn.seat != seat:
            return False
        if _potted(turn.decision):
            return True
    return False


def classify(turns: Sequence[Turn], loser: int) -> Loss:
    """Why seat `loser` lost the game whose inputs were `turns` (in order, the last one ended
    the game)."""
    if turns and turns[-1].seat == loser:
        return _ended_own_game(turns[-1])
    mine = [i for i, t in enumerate(turns) if t.seat == loser]
    if not mine:
        return Loss.BREAK_AND_RUN
    if mine[-1] == 0:
        return Loss.BREAK
    last = mine[-1]
    turn = turns[last]
    if isinstance(turn.action, Choice):
        return Loss.CHOICE
    if isinstance(turn.action, Shot) and turn.action.push_out:
        return Loss.PUSH_OUT
    if turn.decision is not None and turn.decision.fouls:
        return Loss.FOUL
    if turn.kind is None:
        return Loss.OTHER
    if turn.kind == Kind.BREAK:
        return Loss.BREAK
    if turn.kind in POTS:
        return Loss.MISSED_POT
    if turn.kind == Kind.PUSH_OUT:
        return Loss.PUSH_OUT
    return Loss.POSITION if _visit_potted(turns, last) else Loss.SAFETY

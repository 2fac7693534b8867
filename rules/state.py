"""The table and score before a shot, and the referee's decision about a shot.

One `State` model serves all four games: the common fields (balls, turn, scores, ball in hand,
consecutive fouls, the current visit) plus a few that only one game uses, each defaulted so
that the others never see them. States are immutable; a referee returns a new one.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from rules.codes import FoulCode, NoteCode, RuleError
from rules.inputs import Option
from rules.racks import Game
from rules.spots import STANDARD_SIZE, Point, Size

__all__ = ["Decision", "Foul", "Group", "Note", "Region", "RuleError", "State"]

Region = Literal["anywhere", "kitchen", "D"]
Group = Literal["solids", "stripes"]


class Foul(BaseModel):
    """A foul: its code (what clients test and translate), its reason in words, and the ball
    it concerns when there is one (hit first in error, pocketed in error, the free ball)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    code: FoulCode
    reason: str
    ball: str | None = None


class Note(BaseModel):
    """Anything else a referee says about a shot (a push-out, a group taken, a point made)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    code: NoteCode
    text: str


class State(BaseModel):
    """Everything the referee needs to judge the next input.

    balls: the balls on the table and where they lie (a pocketed cue ball is absent until
        placed). turn: the player (0 or 1) who acts next, shooting or choosing. scores: frames
        or racks won in pool, points in snooker and three-cushion. ball_in_hand: the region the
        player to shoot may place the cue ball in, if any. foul_streak: consecutive fouls per
        player (nine-ball's three-foul rule). shots: strokes played so far (0 = the break). visit:
        what the player at the table has made in the current visit (snooker's break in points,
        three-cushion's run in points, nine-ball's and eight-ball's balls pocketed without a
        foul). best: the highest visit of each player (the leaderboard's break). pending:
        options the player to act must choose from before anyone shoots. over / winner: the
        end of the game.

    Game-specific: groups (eight-ball, per player); on (snooker's ball on: "red", "colour" or
    a colour's name); free_ball (snooker: the player to shoot may nominate a free ball);
    retake (snooker: the state before a foul-and-miss, restored on "replace");
    target (three-cushion: points to win); size (pool: the table's size in feet, which
    places its spots, lines and ball-in-hand regions).
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    game: Annotated[Game, Field(strict=False)]  # the name is the game, even in evolve
    balls: dict[str, Point]
    turn: int = 0
    scores: tuple[int, int] = (0, 0)
    ball_in_hand: Region | None = None
    foul_streak: tuple[int, int] = (0, 0)
    shots: int = 0
    visit: int = 0
    best: tuple[int, int] = (0, 0)
    pending: tuple[Option, ...] = ()
    over: bool = False
    winner: int | None = None
    groups: tuple[Group | None, Group | None] = (None, None)
    on: str = "red"
    free_ball: bool = False
    retake: State | None = None
    target: int = 0
    size: Size = STANDARD_SIZE

    def evolve(self, **changes: Any) -> State:
        """This state with `changes`, validated (strictly: no "1" for 1, no list for a pair):
        a misspelt field or a wrong type is an error, which pydantic's
        `model_copy(update=...)` would store silently. (A state read from the wire or storage
        is validated as pydantic does by default, where a JSON array is a pair.)"""
        return State.model_validate({**dict(self), **changes}, strict=True)


class Decision(BaseModel):
    """What the referee ruled about one shot, in the order a player reads it.

    fouls: each foul, a code and its reason. points: added to each player's score by this shot
    (penalties go to the opponent). respotted: balls put back and where. note: anything else
    worth saying (a push-out, a group taken, a point made), each a code and its words.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    player: int
    fouls: tuple[Foul, ...] = ()
    points: tuple[int, int] = (0, 0)
    pocketed: tuple[str, ...] = ()
    respotted: dict[str, Point] = {}
    notes: tuple[Note, ...] = ()
    next_player: int
    ball_in_hand: Region | None = None
    options: tuple[Option, ...] = ()
    over: bool = False
    winner: int | None = None

    def line(self) -> str:
        """One human-readable line: who shot, what happened, who is next."""
        parts = [f"P{self.player + 1}"]
        if self.pocketed:
            parts.append("pocketed " + ", ".join(self.pocketed))
        parts += [f"FOUL: {f.reason}" for f in self.fouls]
        parts += [n.text for n in self.notes]
        if any(self.points):
            parts.append(f"points {self.points[0]}-{self.points[1]}")
        if self.respotted:
            parts.append("respotted " + ", ".join(self.respotted))
        if self.over:
            parts.append(f"game over, winner P{self.winner + 1}")
        else:
            nxt = f"next P{self.next_player + 1}"
            if self.ball_in_hand:
                nxt += f" with ball in hand ({self.ball_in_hand})"
            if self.options:
                nxt += " to choose " + " / ".join(self.options)
            parts.append(nxt)
        return "; ".join(parts)


def foul(code: FoulCode, reason: str, ball: str | None = None) -> Foul:
    return Foul(code=code, reason=reason, ball=ball)


def note(code: NoteCode, text: str) -> Note:
    return Note(code=code, text=text)


def other(player: int) -> int:
    return 1 - player


def add_points(scores: tuple[int, int], points: tuple[int, int]) -> tuple[int, int]:
    return (scores[0] + points[0], scores[1] + points[1])


def award(player: int, n: int) -> tuple[int, int]:
    """Points (n) for `player` as a per-player pair."""
    return (n, 0) if player == 0 else (0, n)


def conclude(
    state: State,
    *,
    balls: dict[str, Point],
    next_player: int,
    fouls: list[Foul] | tuple[Foul, ...] = (),
    points: tuple[int, int] = (0, 0),
    pocketed: tuple[str, ...] = (),
    respotted: dict[str, Point] | None = None,
    notes: list[Note] | tuple[Note, ...] = (),
    ball_in_hand: Region | None = None,
    options: tuple[Option, ...] = (),
    winner: int | None = None,
    **game_fields,
) -> tuple[State, Decision]:
    """The state after a shot and the decision that explains it, built from one set of facts.

    Every referee ends its judgement here, so a state and its decision can never disagree.
    `game_fields` are the game-specific State fields the shot changed.
    """
    over = winner is not None
    new = state.evolve(
        balls=balls,
        turn=next_player,
        scores=add_points(state.scores, points),
        ball_in_hand=None if over else ball_in_hand,
        shots=state.shots + 1,
        pending=() if over else options,
        over=over,
        winner=winner,
        **game_fields,
    )
    decision = Decision(
        player=state.turn,
        fouls=tuple(fouls),
        points=points,
        pocketed=pocketed,
        respotted=respotted or {},
        notes=tuple(notes),
        next_player=next_player,
        ball_in_hand=new.ball_in_hand,
        options=new.pending,
        over=over,
        winner=winner,
    )
    return new, decision

"""The interface every referee module offers, and the one lookup from a game to its referee.

The four referee modules (nineball, eightball, snooker, three_cushion) each satisfy `Referee`:
the game service, the shot pickers and the bot ask a referee what the player to act may do now
(`allowed`) instead of testing the game's name.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import physics
from rules import eightball, nineball, snooker, three_cushion
from rules.inputs import Option, Shot, ShotOptions
from rules.racks import REDS_FULL, Game, table
from rules.spots import Point, Table
from rules.state import Decision, Region, State


@runtime_checkable
class Referee(Protocol):
    """One game's rules.

    GAME, TABLE: the game refereed and its standard table (`table_of` gives a state's own).
    new_game: the state before the break (`target`: three-cushion's points to win; `reds`:
    snooker's reds, 6, 10 or 15; `size`: pool's table in feet; each game ignores the others').
    cue_ball: the ball the player to shoot must strike. targets: the balls that player may
    legally hit first from `balls`. options: the
    declarations the next shot may carry. judge: the state after a shot (already checked) and
    the decision explaining it, from the position `before` the stroke and the engine's result.
    """

    GAME: Game
    TABLE: Table

    def new_game(
        self, seed: int, gap: float = 0.0, target: int = 0, reds: int = REDS_FULL, size: int = 9
    ) -> State: ...

    def cue_ball(self, state: State) -> str: ...

    def targets(self, state: State, balls: Mapping[str, Point]) -> frozenset[str]: ...

    def options(self, state: State) -> ShotOptions: ...

    def judge(
        self, state: State, shot: Shot, before: dict[str, Point], result: physics.Shot
    ) -> tuple[State, Decision]: ...


REFEREES: Mapping[Game, Referee] = {
    Game.NINEBALL: nineball,
    Game.EIGHTBALL: eightball,
    Game.SNOOKER: snooker,
    Game.THREE_CUSHION: three_cushion,
}


def referee(game: Game) -> Referee:
    return REFEREES[Game(game)]


def table_of(state: State) -> Table:
    """The table a state is played on: its game's, at the state's size (pool)."""
    return table(state.game, state.size)


@dataclass(frozen=True, slots=True)
class Allowed:
    """What the player to act (`player`) may do in a state.

    choices: when not empty, the player must choose one of these before anyone shoots.
    cue: the ball to strike. ball_in_hand: the region the cue ball may be placed in, if any.
    targets: the legal first contacts from the balls as they lie. options: a shot's declarations.
    """

    player: int
    choices: tuple[Option, ...]
    cue: str
    ball_in_hand: Region | None
    targets: frozenset[str]
    options: ShotOptions


def allowed(state: State) -> Allowed:
    ref = referee(state.game)
    return Allowed(
        player=state.turn,
        choices=state.pending,
        cue=ref.cue_ball(state),
        ball_in_hand=state.ball_in_hand,
        targets=ref.targets(state, state.balls),
        options=ref.options(state),
    )

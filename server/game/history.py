"""Players' match histories: each decided match, kept once, as its players' profiles show it.

A match is recorded when it is rated (server/game/actor.py): the replica whose rating landed
records it, once per table (storage invariant 13), with both players' ratings before and
after, how it ended and its racks' replays. Bots are rated like anyone, so a bot level's
rating says how strong it plays against the people here.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from server.game.ratings import Rating
from server.game.refereeing import GameName
from server.protocol.models import Ending, PlayerInfo


class MatchResult(BaseModel):
    """A decided match (seats as at the table)."""

    model_config = ConfigDict(frozen=True)

    table: str
    game: GameName
    at: float
    seats: tuple[PlayerInfo, PlayerInfo]
    winner: int
    ended: Ending
    racks_won: tuple[int, int]
    before: tuple[Rating, Rating]
    after: tuple[Rating, Rating]
    replays: tuple[str, ...] = ()
    #: Played at a private table: its profiles' entries lead to neither it nor its replays.
    private: bool = False

    def seat_of(self, player_id: str) -> int:
        return 0 if self.seats[0].id == player_id else 1

"""Every command a table's actor takes (server/game/actor.py), as frozen typed values.

A command names who sends it and what it asks; the HTTP handlers (server/http/api.py) only parse a
request into one of these and hand it to the table's actor, and the server makes its own
(`ClockExpiry`, `BotMove`) the same way. The actor decides and answers; nothing here
does I/O or knows HTTP.

Server-made inputs are stored and published under input ids no client can send: a client's
shot id matches `ids.SHOT_ID_PATTERN` (letters, digits, `_` and `-`), the server's own carry a
`:` (`clock:<version>`, `bot:<version>`), so a client can never pre-empt one by reusing its id.
"""

from __future__ import annotations

from dataclasses import dataclass

from server.game.refereeing import Position
from server.protocol.ids import QuickText
from server.protocol.models import AimRequest, Intent, PlayerInfo


@dataclass(frozen=True)
class Play:
    """A seated player's shot or choice."""

    player: PlayerInfo
    intent: Intent


@dataclass(frozen=True)
class Join:
    """Take the free seat of an open match table."""

    player: PlayerInfo


@dataclass(frozen=True)
class Leave:
    """Cancel an open table (its creator, before anyone joined)."""

    player: PlayerInfo


@dataclass(frozen=True)
class Resign:
    """Give up the match (practice: end the session)."""

    player: PlayerInfo


@dataclass(frozen=True)
class Claim:
    """Claim the win from an opponent absent past the grace period."""

    player: PlayerInfo


@dataclass(frozen=True)
class Rematch:
    """Offer a rematch of a finished match, or accept the opponent's offer."""

    player: PlayerInfo


@dataclass(frozen=True)
class Rerack:
    """Practice: start the next rack, from a set-up position or (None) the game's own rack."""

    player: PlayerInfo
    position: Position | None = None


@dataclass(frozen=True)
class Retake:
    """Practice: re-rack from the balls as they stood when the last shot struck."""

    player: PlayerInfo


@dataclass(frozen=True)
class Heartbeat:
    """A seated player is still here."""

    player: PlayerInfo


@dataclass(frozen=True)
class QuickMessage:
    """One of the fixed quick messages, from a player or a spectator."""

    player: PlayerInfo
    message: QuickText


@dataclass(frozen=True)
class Aim:
    """How the player to act is lining up, for the table's readers (never played)."""

    player: PlayerInfo
    aim: AimRequest


@dataclass(frozen=True)
class ClockExpiry:
    """The shot clock may have run out: play the timeout input if the deadline has passed."""


@dataclass(frozen=True)
class BotMove:
    """Finish an input a dead replica left pending; then, if a bot seat is to act, search its
    move (at most once per table version in a process) and play it."""


#: What the players and spectators may send (each through an HTTP handler).
ClientCommand = (
    Play
    | Join
    | Leave
    | Resign
    | Claim
    | Rematch
    | Rerack
    | Retake
    | Heartbeat
    | QuickMessage
    | Aim
)
#: The client commands that change nothing of the versioned table (a heartbeat is kept beside
#: it, a quick message and an aim are only published): the actor answers them at once rather
#: than behind the queue, where a job may wait out a dead replica's lease (15 s), so that a
#: player's heartbeats are kept and nobody looks gone meanwhile.
Beside = Heartbeat | QuickMessage | Aim
#: What the server makes itself.
ServerCommand = ClockExpiry | BotMove
Command = ClientCommand | ServerCommand

"""Every request, answer and channel message of the game service, as pydantic models.

docs/protocol.md describes them for client authors; the OpenAPI description served at
`/api/openapi.json` is generated from these classes. Requests forbid unknown fields and
non-finite numbers, so a malformed request fails here, before anything is looked up.
"""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated, Literal

from annotated_types import Interval
from pydantic import BaseModel, ConfigDict, Field, StringConstraints

from server.errors import ErrorCode
from server.refereeing import Decision, GameName, GameRecord, Option, PlayerInput, Region, State
from server.trajectories import Trajectory

#: The format version of channel messages; bumped when a client must change to read them.
PROTOCOL = 1
#: Seconds between the heartbeats a seated player's client sends (docs/protocol.md, Match
#: life): a player is shown disconnected after tables.PRESENCE_TIMEOUT (10 s) without one, so
#: two may be lost before that happens.
HEARTBEAT_INTERVAL = 3.0


def json_int(low: int, high: int | None = None) -> object:
    """An integer of a request in [low, high] (as JSON Schema bounds it)."""
    return Annotated[int, Interval(ge=low, le=high)]


#: Seconds per shot: 0 for no clock, else 10 to 300.
ShotClock = json_int(0, 0) | json_int(10, 300)
RaceTo = json_int(1, 15)

_REQUEST = ConfigDict(frozen=True, extra="forbid")
_ANSWER = ConfigDict(frozen=True)

#: Letters, digits, `_`, `-`, `.` and inner spaces: nothing a page could take for markup.
NAME_PATTERN = r"^[A-Za-z0-9_.\-](?:[A-Za-z0-9_. \-]*[A-Za-z0-9_.\-])?$"
DisplayName = Annotated[str, StringConstraints(min_length=1, max_length=24, pattern=NAME_PATTERN)]
ShotId = Annotated[str, StringConstraints(pattern=r"^[A-Za-z0-9_-]{8,64}$")]
TableId = Annotated[str, StringConstraints(pattern=r"^[0-9a-f]{20}$")]
Seat = Annotated[int, Field(ge=0, le=1)]


class Mode(StrEnum):
    MATCH = "match"
    PRACTICE = "practice"
    BOT = "bot"


class Status(StrEnum):
    OPEN = "open"
    PLAYING = "playing"
    OVER = "over"
    CANCELLED = "cancelled"


class InputKind(StrEnum):
    SHOT = "shot"
    CHOICE = "choice"


class BotName(StrEnum):
    """The server's opponents: the rules' simple shot picker, or the searching bot at a level
    from 1 (a beginner) to 5 (the strongest), as `rules.bot.chooser` names them."""

    PICKER = "picker"
    LEVEL_1 = "bot:1"
    LEVEL_2 = "bot:2"
    LEVEL_3 = "bot:3"
    LEVEL_4 = "bot:4"
    LEVEL_5 = "bot:5"


class QuickText(StrEnum):
    """The fixed set of quick messages: nothing else can be said, so nothing to moderate."""

    GOOD_SHOT = "good_shot"
    GOOD_GAME = "good_game"
    NICE_TRY = "nice_try"
    WELL_PLAYED = "well_played"
    THANKS = "thanks"
    OOPS = "oops"
    HELLO = "hello"
    BYE = "bye"


# ----- errors ---------------------------------------------------------------------------------
class ApiError(BaseModel):
    """The body of every refusal (the request changed nothing)."""

    model_config = _ANSWER

    code: ErrorCode
    reason: str
    rule: str | None = Field(default=None, description="the referee's own code, if any")


# ----- identity -------------------------------------------------------------------------------
class PlayerCreate(BaseModel):
    model_config = _REQUEST

    name: DisplayName


class PlayerInfo(BaseModel):
    model_config = _ANSWER

    id: str
    name: str


class PlayerToken(BaseModel):
    model_config = _ANSWER

    player: PlayerInfo
    token: str
    expires_at: int = Field(description="unix time after which the token is refused")


class RatingView(BaseModel):
    """A Glicko-2 rating (server/ratings.py), provisional while its deviation exceeds 110."""

    model_config = _ANSWER

    rating: float
    deviation: float
    volatility: float
    games: int
    provisional: bool


class PlayerRatings(BaseModel):
    model_config = _ANSWER

    player: PlayerInfo
    ratings: dict[str, RatingView] = Field(description="by game; a game never played is absent")


# ----- tables ---------------------------------------------------------------------------------
class TableOptions(BaseModel):
    model_config = _REQUEST

    race_to: RaceTo = 1
    shot_clock: ShotClock = Field(default=0, description="seconds per shot, 0: no clock")
    private: bool = False


class TableCreate(BaseModel):
    model_config = _REQUEST

    game: GameName
    mode: Mode = Mode.MATCH
    race_to: RaceTo = 1
    shot_clock: ShotClock = 0
    private: bool = False
    bot: BotName = BotName.LEVEL_3

    def options(self) -> TableOptions:
        return TableOptions(race_to=self.race_to, shot_clock=self.shot_clock, private=self.private)


class ShotRules(BaseModel):
    """What a shot sent now must or may carry, as the game's referee allows it in this state
    (a shot that breaks one of these is refused with `illegal_input` and its rule code)."""

    model_config = _ANSWER

    place: Region | None = Field(
        default=None,
        description="ball in hand: the region the shot's `place` may put the cue ball in "
        "(kitchen: behind the head string; D: snooker's D); null: `place` is refused",
    )
    place_required: bool = Field(
        default=False, description="the cue ball is off the table: `place` is required"
    )
    targets: list[str] = Field(
        default=[], description="the balls the cue ball may legally hit first, as they lie"
    )
    push_out: bool = Field(
        default=False,
        description="`push_out: true` may be declared (nine-ball, the shot after the break)",
    )
    call: list[str] = Field(
        default=[],
        description="when not empty, `call` is required and must name one of these pockets "
        "(eight-ball, shooting at the 8); when empty, `call` must be absent",
    )
    nominate: list[str] = Field(
        default=[],
        description="the balls `nominate` may name (snooker: the free ball after a foul, or "
        "the colour after a red; optional); empty: no nomination",
    )


class Constraints(BaseModel):
    """What the seat to act may send now: a choice of `options` (when not empty), otherwise a
    shot of `cue_ball` carrying what `shot` says."""

    model_config = _ANSWER

    seat: Seat
    player: str | None = Field(description="the id of the player in that seat")
    kinds: list[InputKind]
    cue_ball: str
    ball_in_hand: Region | None = None
    options: list[Option] = Field(
        default=[],
        description="choices pending (play_on, play_again, replace): the input must be "
        "`{option}` with one of them",
    )
    deadline: float | None = Field(default=None, description="unix time the shot clock ends")
    shot: ShotRules | None = Field(
        default=None, description="what a shot must or may carry (null while a choice is pending)"
    )


class TableSummary(BaseModel):
    model_config = _ANSWER

    id: TableId
    game: GameName
    mode: Mode
    status: Status
    seats: list[PlayerInfo | None]
    options: TableOptions
    spectators: int = 0


class TableList(BaseModel):
    model_config = _ANSWER

    tables: list[TableSummary]


class TableView(BaseModel):
    """The full state of a table: what a client starts from and resyncs to."""

    model_config = _ANSWER

    id: TableId
    channel: str
    game: GameName
    mode: Mode
    options: TableOptions
    status: Status
    seats: list[PlayerInfo | None]
    version: int
    rack: int
    racks_won: tuple[int, int]
    state: State
    next: Constraints | None
    last_outcome: OutcomeMessage | None = None
    presence: tuple[bool, bool] = (True, True)
    spectators: int = 0
    winner: Seat | None = None
    rematch: tuple[bool, bool] = (False, False)
    rematch_table: TableId | None = None


class QuickRequest(BaseModel):
    model_config = _REQUEST

    game: GameName


class QuickStatus(BaseModel):
    model_config = _ANSWER

    status: Literal["waiting", "paired", "cancelled", "idle"]
    table: TableId | None = None


# ----- intents --------------------------------------------------------------------------------
class Intent(BaseModel):
    model_config = _REQUEST

    version: json_int(0)
    shot_id: ShotId
    input: PlayerInput


class IntentAccepted(BaseModel):
    model_config = _ANSWER

    status: Literal["accepted"] = "accepted"
    version: int = Field(description="the version the outcome will carry")


class IntentDuplicate(BaseModel):
    model_config = _ANSWER

    status: Literal["duplicate"] = "duplicate"
    version: int
    outcome: OutcomeMessage | None = Field(description="None while it is still being played")


class QuickMessageRequest(BaseModel):
    model_config = _REQUEST

    message: QuickText


#: An aim's numbers: finite, and no wider than a shot's (rules.inputs).
_Unit = Annotated[float, Field(ge=0.0, le=1.0, allow_inf_nan=False)]
_Tip = Annotated[float, Field(ge=-0.5, le=0.5, allow_inf_nan=False)]
_Metres = Annotated[float, Field(ge=0.0, le=4.0, allow_inf_nan=False)]


class AimRequest(BaseModel):
    """How the player to act is lining up: shown to the opponent and spectators as it is,
    never played or checked against the rules (the shot is the intent)."""

    model_config = _REQUEST

    heading: float = Field(ge=-360.0, le=720.0, allow_inf_nan=False, description="degrees")
    power: _Unit = Field(description="the power control, 0 to 1")
    elevation: float = Field(ge=0.0, lt=90.0, allow_inf_nan=False, description="degrees")
    a: _Tip = 0.0
    b: _Tip = 0.0
    place: tuple[_Metres, _Metres] | None = Field(
        default=None, description="where the cue ball in hand is placed for now"
    )


# ----- replays and the leaderboard ------------------------------------------------------------
ReplayId = Annotated[str, StringConstraints(pattern=r"^[0-9a-f]{24}$")]


class Source(StrEnum):
    MATCH = "match"
    PRACTICE = "practice"
    CLAIM = "claim"


class ReplayView(BaseModel):
    """One finished rack (or frame, or game) as a record anyone can replay."""

    model_config = _ANSWER

    id: ReplayId
    url: str = Field(description="the replay's page")
    table: TableId | None
    rack: int
    game: GameName
    players: list[PlayerInfo | None] = Field(description="the seats 0 and 1")
    best: tuple[int, int] = Field(description="each player's best break in it")
    record: GameRecord
    created: float


class ReplayShot(BaseModel):
    """One input of a replay played again: `input`, `decision`, `trajectory` and `state` as the
    outcome message carries them."""

    model_config = _ANSWER

    player: Seat = Field(
        description="the record's player who played it (its seat, but in practice one person"
        " plays both)"
    )
    input: PlayerInput
    decision: Decision | None
    trajectory: Trajectory | None
    state: State


class ReplayShots(BaseModel):
    """Every input of a replay with its outcome, computed by replaying the record."""

    model_config = _ANSWER

    id: ReplayId
    shots: list[ReplayShot] = Field(description="one per input of the record, in order")


class BreakEntry(BaseModel):
    """One break on the leaderboard."""

    model_config = _ANSWER

    game: GameName
    score: int
    name: str
    player: str | None = Field(default=None, description="the player's id (online breaks)")
    replay: ReplayId | None = None
    source: Source
    at: float


class Leaderboard(BaseModel):
    model_config = _ANSWER

    game: GameName
    breaks: list[BreakEntry]


class LeaderboardMessage(BaseModel):
    """On `public-leaderboard`: a game's top breaks after a new entry."""

    model_config = _ANSWER

    kind: Literal["leaderboard"] = "leaderboard"
    protocol: int = PROTOCOL
    game: GameName
    breaks: list[BreakEntry]


class ClaimRequest(BaseModel):
    """A break claimed from a game record (as `billiards selfplay --record` writes one)."""

    model_config = _REQUEST

    game: GameName = Field(description="the leaderboard the break is claimed on")
    record: GameRecord
    name: DisplayName
    score: json_int(1, 10_000)


class ClaimVerdict(BaseModel):
    model_config = _ANSWER

    accepted: bool
    entry: BreakEntry
    replay: ReplayView


# ----- channel messages -----------------------------------------------------------------------
class OutcomeMessage(BaseModel):
    """One input played: published once on the table channel, after it was stored."""

    model_config = _ANSWER

    kind: Literal["outcome"] = "outcome"
    protocol: int = PROTOCOL
    table: TableId
    version: int
    shot_id: ShotId
    seat: Seat
    input: PlayerInput
    decision: Decision | None
    trajectory: Trajectory | None
    state: State
    next: Constraints | None
    rack: int
    racks_won: tuple[int, int]
    status: Status
    winner: Seat | None = None
    void: str | None = Field(
        default=None, description="why the accepted input could not be played (state unchanged)"
    )
    replay: str | None = Field(default=None, description="the replay of the rack it ended")


class TableMessage(BaseModel):
    model_config = _ANSWER

    kind: Literal["table"] = "table"
    protocol: int = PROTOCOL
    version: int
    view: TableView


class PresenceMessage(BaseModel):
    model_config = _ANSWER

    kind: Literal["presence"] = "presence"
    protocol: int = PROTOCOL
    version: int
    presence: tuple[bool, bool]
    grace_until: tuple[float | None, float | None]


class ChatMessage(BaseModel):
    model_config = _ANSWER

    kind: Literal["chat"] = "chat"
    protocol: int = PROTOCOL
    version: int
    from_name: str
    seat: Seat | None
    message: QuickText


class AimMessage(AimRequest):
    """The aim of the player in `seat`, as sent (AimRequest), on the table channel."""

    model_config = _ANSWER

    kind: Literal["aim"] = "aim"
    protocol: int = PROTOCOL
    version: int
    seat: Seat


class LobbyMessage(BaseModel):
    model_config = _ANSWER

    kind: Literal["lobby"] = "lobby"
    protocol: int = PROTOCOL
    tables: list[TableSummary]
    players_online: int


class PairedMessage(BaseModel):
    model_config = _ANSWER

    kind: Literal["paired"] = "paired"
    protocol: int = PROTOCOL
    table: TableId


TableView.model_rebuild()

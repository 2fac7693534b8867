"""Every request, answer and channel message of the game service, as pydantic models.

docs/protocol.md describes them for client authors; the OpenAPI description served at
`/api/openapi.json` is generated from these classes. Requests forbid unknown fields and
non-finite numbers, so a malformed request fails here, before anything is looked up.
"""

from __future__ import annotations

from enum import StrEnum
from typing import Annotated, Literal

from annotated_types import Interval
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    StringConstraints,
    ValidationInfo,
    field_validator,
    model_validator,
)

from rules.inputs import Option, PlayerInput
from rules.racks import Game as GameName
from rules.record import GameRecord
from rules.state import Decision, Region, State
from server.protocol import ids
from server.protocol.errors import ErrorCode
from server.protocol.ids import PROTOCOL, BotName, MessageKind, QuickText
from server.protocol.trajectories import Trajectory


def json_int(low: int, high: int | None = None) -> object:
    """An integer of a request in [low, high] (as JSON Schema bounds it)."""
    return Annotated[int, Interval(ge=low, le=high)]


#: Seconds per shot: 0 for no clock, else 10 to 300.
ShotClock = json_int(0, 0) | json_int(ids.SHOT_CLOCK_MIN, ids.SHOT_CLOCK_MAX)
RaceTo = json_int(1, ids.RACE_TO_MAX)
Reds = Literal[6, 10, 15]
TableSize = Literal[tuple(ids.TABLE_SIZES)]  # type: ignore[valid-type]
Target = json_int(0, ids.TARGET_MAX)

_REQUEST = ConfigDict(frozen=True, extra="forbid")
_ANSWER = ConfigDict(frozen=True)

DisplayName = Annotated[
    str, StringConstraints(min_length=1, max_length=ids.NAME_MAX, pattern=ids.NAME_PATTERN)
]
ShotId = Annotated[str, StringConstraints(pattern=ids.SHOT_ID_PATTERN)]
InputId = Annotated[str, StringConstraints(pattern=ids.INPUT_ID_PATTERN)]
TableId = Annotated[str, StringConstraints(pattern=ids.TABLE_ID_PATTERN)]
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


class Ending(StrEnum):
    """How a match ended: its racks decided it, a player resigned, or the win was claimed from
    an absent player."""

    RACKS = "racks"
    RESIGNED = "resigned"
    CLAIMED = "claimed"


class InputKind(StrEnum):
    SHOT = "shot"
    CHOICE = "choice"


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
    """A Glicko-2 rating (server/game/ratings.py), provisional while its deviation exceeds 110."""

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


class ProfileMatch(BaseModel):
    """One decided match in a player's history, from that player's side."""

    model_config = _ANSWER

    table: TableId | None = Field(description="None for a private table's match")
    game: GameName
    at: float = Field(description="unix time it was decided")
    opponent: PlayerInfo
    won: bool
    ended: Ending
    score: tuple[int, int] = Field(description="racks won: this player's, the opponent's")
    rating_before: float
    rating_after: float
    replays: list[ReplayId] = Field(description="each finished rack's replay (none: private)")


class RatingPoint(BaseModel):
    """A player's rating in a game after one rated match: a point of its rating graph."""

    model_config = _ANSWER

    game: GameName
    at: float = Field(description="unix time of the match")
    rating: float
    deviation: float


class PlayerProfile(BaseModel):
    """Who a player is here: ratings and their history, recent matches, best breaks, when
    last seen."""

    model_config = _ANSWER

    player: PlayerInfo
    ratings: dict[str, RatingView] = Field(description="by game; a game never played is absent")
    matches: list[ProfileMatch] = Field(description="the most recent first")
    best_breaks: dict[str, BreakEntry] = Field(
        description="by game, the best break under the player's name if the player made it"
    )
    history: list[RatingPoint] = Field(
        default=[],
        description=f"the rating after each of the player's last {ids.PROFILE_HISTORY} rated"
        " matches (of every game), oldest first",
    )
    online: bool = Field(default=False, description="the player holds its name now")
    last_seen: float | None = Field(
        default=None, description="unix time of the player's last sign of life, if known"
    )


class BotInfo(BaseModel):
    """One of the server's bots: what to send as `bot` to play it, and how it has done."""

    model_config = _ANSWER

    id: BotName
    level: int = Field(description="0: the shot picker (never searches), 1 (weakest) to 5")
    name: str = Field(description="the level in words")
    ratings: dict[str, RatingView] = Field(description="by game, once it has played rated games")


class BotList(BaseModel):
    model_config = _ANSWER

    bots: list[BotInfo] = Field(description="weakest first")


# ----- tables ---------------------------------------------------------------------------------
class TableOptions(BaseModel):
    model_config = _REQUEST

    race_to: RaceTo = 1
    shot_clock: ShotClock = Field(default=0, description="seconds per shot, 0: no clock")
    private: bool = False
    reds: Reds = Field(default=15, description="snooker's reds: 6, 10 or 15")
    target: Target = Field(default=0, description="three-cushion's points to win, 0: 15")
    size: TableSize = Field(default=ids.TABLE_SIZE, description="pool's table size in feet")


class GameChoice(BaseModel):
    """A game and the options that change how it is played (a quick match pairs players who
    chose the same)."""

    model_config = _REQUEST

    game: GameName
    race_to: RaceTo = 1
    reds: Reds = Field(default=15, description="snooker only: 6, 10 or 15 reds")
    target: Target = Field(default=0, description="three-cushion only: points to win (0: 15)")
    size: TableSize = Field(
        default=ids.TABLE_SIZE, description="nine-ball and eight-ball only: the table in feet"
    )

    @field_validator("target")
    @classmethod
    def _default_target_is_zero(cls, target: int, info: ValidationInfo) -> int:
        """Three-cushion's default target asked for by its number is the default: one game,
        one quick-match pool (`target: 15` and no target are paired)."""
        default = info.data.get("game") == "three_cushion" and target == ids.THREE_CUSHION_TARGET
        return 0 if default else target

    @model_validator(mode="after")
    def _options_of_the_game(self) -> GameChoice:
        return options_of_the_game(self)


def options_of_the_game(choice: GameChoice | PositionShare) -> GameChoice | PositionShare:
    """`choice`, once its options are found to be its game's (ValueError otherwise)."""
    if choice.reds != 15 and choice.game != "snooker":
        raise ValueError("only snooker is played with fewer reds")
    if getattr(choice, "target", 0) and choice.game != "three_cushion":
        raise ValueError("only three-cushion has a target of points")
    if choice.size != ids.TABLE_SIZE and choice.game not in ids.SIZED_GAMES:
        raise ValueError("only nine-ball and eight-ball are played on other table sizes")
    return choice


Coordinate = Annotated[float, Field(allow_inf_nan=False)]
#: A set-up position: ball id -> [x, y] in the table's coordinates (m), checked by the rules
#: (`rules.positions`) against the game, its reds and its table size.
Position = Annotated[
    dict[
        Annotated[str, StringConstraints(min_length=1, max_length=8)],
        tuple[Coordinate, Coordinate],
    ],
    Field(max_length=22),
]


class TableCreate(GameChoice):
    mode: Mode = Mode.MATCH
    shot_clock: ShotClock = 0
    private: bool = False
    bot: BotName = BotName.LEVEL_3
    position: Position | None = Field(
        default=None,
        description="practice only: the position the table's racks start from instead of the "
        "game's rack (the game's own balls, each on the bed, none overlapping; without the cue "
        "ball, it is in hand). Its breaks are not ranked.",
    )

    @model_validator(mode="after")
    def _position_in_practice(self) -> TableCreate:
        if self.position is not None and self.mode is not Mode.PRACTICE:
            raise ValueError("only a practice table starts from a set-up position")
        return self

    def options(self) -> TableOptions:
        return TableOptions(
            race_to=self.race_to,
            shot_clock=self.shot_clock,
            private=self.private,
            reds=self.reds,
            target=self.target,
            size=self.size,
        )


class RackRequest(BaseModel):
    """A practice table's next rack: from `position` (a set-up position, as `TableCreate`
    takes one), or the game's own rack when it is absent."""

    model_config = _REQUEST

    position: Position | None = None


class PositionShare(BaseModel):
    """A position to share: the game, its options and the balls."""

    model_config = _REQUEST

    game: GameName
    size: TableSize = ids.TABLE_SIZE
    reds: Reds = 15
    position: Position

    @model_validator(mode="after")
    def _options_of_the_game(self) -> PositionShare:
        options_of_the_game(self)
        return self


class SharedPosition(BaseModel):
    """A shared position, checked: its link code (`/practice/{game}?position=code`) and what
    it sets up."""

    model_config = _ANSWER

    code: str
    url: str
    game: GameName
    size: int
    reds: int
    position: dict[str, tuple[float, float]]


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
    last_outcome: OutcomeMessage | None = Field(
        default=None,
        description="the last input played, without its motion (trajectory null): the channel "
        "carried that once",
    )
    presence: tuple[bool, bool] = (True, True)
    spectators: int = 0
    winner: Seat | None = None
    ended: Ending | None = Field(default=None, description="how the match ended, once over")
    replays: list[ReplayId] = Field(
        default=[],
        description="each rack's replay, rack 1 first: every finished rack, and the rack being"
        " played when the match ended by a resignation or a claim if an input was played in it",
    )
    rematch: tuple[bool, bool] = (False, False)
    rematch_table: TableId | None = None
    position: dict[str, tuple[float, float]] | None = Field(
        default=None,
        description="practice: the set-up position this rack started from (null: the game's "
        "rack); its breaks are not ranked",
    )
    retake: bool = Field(
        default=False, description="practice: the last shot can be taken again (`/retake`)"
    )
    ball_set: list[str] = Field(
        default=[],
        description="practice: the game's balls at this table's options (what a set-up "
        "position may hold)",
    )
    presets: dict[str, dict[str, tuple[float, float]]] = Field(
        default={},
        description="practice: named positions of this game and table size to set up "
        "(`combination`, `long_pot`, three-cushion's `standard`); the break is a re-rack",
    )


class QuickRequest(GameChoice):
    pass


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
ReplayId = Annotated[str, StringConstraints(pattern=ids.REPLAY_ID_PATTERN)]


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
    """A page of a replay's inputs with their outcomes, computed by replaying the record."""

    model_config = _ANSWER

    id: ReplayId
    page: int = Field(default=0, description="this page's number (from 0)")
    shots: list[ReplayShot] = Field(
        description="one per input of the record, in order: at most REPLAY_SHOTS_PAGE, those"
        " from page * REPLAY_SHOTS_PAGE on"
    )
    next: int | None = Field(default=None, description="the next page's number; null: the last")


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


class RankedOptions(BaseModel):
    """The options a board ranks (null: the game has no such option); breaks at others, and
    from set-up practice positions, keep their replays but are not ranked."""

    model_config = _ANSWER

    reds: int | None = None
    target: int | None = None
    size: int | None = None


class Leaderboard(BaseModel):
    model_config = _ANSWER

    game: GameName
    ranks: RankedOptions = Field(description="the options this board ranks")
    breaks: list[BreakEntry]


class LeaderboardMessage(BaseModel):
    """On the leaderboard channel (`ids.LEADERBOARD`): a game's top breaks after a new entry."""

    model_config = _ANSWER

    kind: Literal[MessageKind.LEADERBOARD] = MessageKind.LEADERBOARD
    protocol: int = PROTOCOL
    game: GameName
    breaks: list[BreakEntry]


class ClaimRequest(BaseModel):
    """A break claimed from a game record (as `billiards selfplay --record` writes one), by
    the player whose token comes with it: the entry carries that player's name."""

    model_config = _REQUEST

    game: GameName = Field(description="the leaderboard the break is claimed on")
    record: GameRecord
    name: DisplayName | None = Field(
        default=None, description="optional: the claiming player's own name (else refused)"
    )
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

    kind: Literal[MessageKind.OUTCOME] = MessageKind.OUTCOME
    protocol: int = PROTOCOL
    table: TableId
    version: int
    shot_id: InputId
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

    kind: Literal[MessageKind.TABLE] = MessageKind.TABLE
    protocol: int = PROTOCOL
    version: int
    view: TableView


class PresenceMessage(BaseModel):
    model_config = _ANSWER

    kind: Literal[MessageKind.PRESENCE] = MessageKind.PRESENCE
    protocol: int = PROTOCOL
    version: int
    presence: tuple[bool, bool]
    grace_until: tuple[float | None, float | None]


class ChatMessage(BaseModel):
    model_config = _ANSWER

    kind: Literal[MessageKind.CHAT] = MessageKind.CHAT
    protocol: int = PROTOCOL
    version: int
    from_name: str
    seat: Seat | None
    message: QuickText


class Doing(StrEnum):
    PLAYING = "playing"
    WAITING = "waiting"
    ONLINE = "online"


class OnlinePlayer(BaseModel):
    """A player online, and what it is doing: playing at a listed table, waiting for a quick
    match, or neither (on a page: in the lobby, practising in private, watching)."""

    model_config = _ANSWER

    player: PlayerInfo
    doing: Doing
    table: TableId | None = Field(default=None, description="where it plays, if listed")


class ChallengeStatus(StrEnum):
    PENDING = "pending"
    ACCEPTED = "accepted"
    DECLINED = "declined"
    CANCELLED = "cancelled"
    LAPSED = "lapsed"


class ChallengeCreate(GameChoice):
    """Challenge a player to a game with these options."""

    to: Annotated[str, StringConstraints(pattern=ids.PLAYER_ID_PATTERN)]
    shot_clock: ShotClock = 0


class Challenge(BaseModel):
    """A challenge and where it stands; `table` once accepted."""

    model_config = _ANSWER

    id: str
    challenger: PlayerInfo
    challenged: PlayerInfo
    choice: GameChoice
    shot_clock: int
    status: ChallengeStatus
    table: TableId | None = None
    created: float


class ChallengeList(BaseModel):
    model_config = _ANSWER

    challenges: list[Challenge] = Field(description="pending, made by or to this player")


class ChallengeMessage(BaseModel):
    """On both players' channels whenever a challenge is made or settled."""

    model_config = _ANSWER

    kind: Literal[MessageKind.CHALLENGE] = MessageKind.CHALLENGE
    protocol: int = PROTOCOL
    challenge: Challenge


class AimMessage(AimRequest):
    """The aim of the player in `seat`, as sent (AimRequest), on the table channel."""

    model_config = _ANSWER

    kind: Literal[MessageKind.AIM] = MessageKind.AIM
    protocol: int = PROTOCOL
    version: int
    seat: Seat


class LobbyMessage(BaseModel):
    model_config = _ANSWER

    kind: Literal[MessageKind.LOBBY] = MessageKind.LOBBY
    protocol: int = PROTOCOL
    tables: list[TableSummary]
    players_online: int
    online: list[OnlinePlayer] = Field(
        default=[], description="the players online, most recently active first (at most 100)"
    )


class PairedMessage(BaseModel):
    model_config = _ANSWER

    kind: Literal[MessageKind.PAIRED] = MessageKind.PAIRED
    protocol: int = PROTOCOL
    table: TableId


TableView.model_rebuild()

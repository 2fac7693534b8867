"""A table as the server stores it (`TableRecord`), and the pure transitions of its life.

Nothing here does I/O: the table actor (server/game/actor.py) loads a record, applies one of
these transitions and stores the result with a compare-and-set on `version` (server/storage). Seats
and the referee's players coincide: seat 0 is the referee's player 0, and each rack's break
goes to `breaker` by starting the rack with `turn = breaker` (alternating rack by rack).
"""

from __future__ import annotations

import time

from pydantic import BaseModel, ConfigDict, Field

from server.game import refereeing
from server.game.refereeing import GameName, PlayerInput, Position, State
from server.protocol.encoding import with_encoded
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import (
    BOT_LEVELS,
    CLOCK_PREFIX,
    PRESENCE_TIMEOUT,
    REMATCH_LAPSE,
    TURN_LIMIT,
    BotName,
    derived_table_id,
    table_channel,
)
from server.protocol.models import (
    Constraints,
    Ending,
    InputKind,
    Mode,
    OutcomeMessage,
    PlayerInfo,
    ShotRules,
    Status,
    TableCreate,
    TableOptions,
    TableSummary,
    TableView,
)

#: How long a disconnected player may stay away before the opponent may claim the win (s).
GRACE = 60.0
#: How long the live store keeps a finished table (over or cancelled) after its last change
#: (s): its state, inputs and rematch link stay readable that long. Its racks' replays and
#: breaks are in the replay store (storage: replays, breaks), which keeps them for good.
KEEP_FINISHED = 24 * 3600.0
#: How long the live store keeps an unfinished table that nobody changes (s): an open table
#: nobody joins, a match both players left (a shot clock's timeouts count as changes).
KEEP_IDLE = 7 * 24 * 3600.0


class InputEntry(BaseModel):
    """One accepted input: stored before it is played, completed with its outcome after."""

    model_config = ConfigDict(frozen=True)

    shot_id: str
    seat: int
    input: PlayerInput
    version: int = Field(description="the table version the input was accepted at")
    rack: int = Field(default=1, description="the rack it was played in")
    accepted_at: float
    replica: str = Field(default="", description="the server process that accepted it")
    outcome: OutcomeMessage | None = None


class TableRecord(BaseModel):
    """Everything the server keeps about one table (one stored document per table)."""

    model_config = ConfigDict(frozen=True)

    id: str
    game: GameName
    mode: Mode
    options: TableOptions
    bot: BotName | None = None
    seats: tuple[PlayerInfo | None, PlayerInfo | None]
    status: Status
    version: int = 0
    seed: int
    rack: int = 1
    racks_won: tuple[int, int] = (0, 0)
    breaker: int = 0
    state: State
    pending: InputEntry | None = Field(default=None, description="accepted, not yet played")
    last_outcome: OutcomeMessage | None = None
    winner: int | None = None
    ended: Ending | None = None
    replays: tuple[str, ...] = Field(default=(), description="the finished racks' replays")
    deadline: float | None = None
    rematch: tuple[bool, bool] = (False, False)
    rematch_table: str | None = None
    created: float
    started: float | None = Field(
        default=None, description="unix time both seats were taken (presence counts from it)"
    )
    updated: float = Field(default=0.0, description="unix time of the last stored change")
    position: Position | None = Field(
        default=None,
        description="practice: the set-up position the racks start from (None: the game's rack)",
    )
    retake: Position | None = Field(
        default=None,
        description="practice: the balls as they stood when the last shot struck (to retake it)",
    )

    @property
    def channel(self) -> str:
        return table_channel(self.id)

    @property
    def finished(self) -> bool:
        return self.status in (Status.OVER, Status.CANCELLED)

    @property
    def expires(self) -> float:
        """When the live store may drop this table (storage invariant 12)."""
        keep = KEEP_FINISHED if self.finished else KEEP_IDLE
        return max(self.created, self.updated) + keep

    @property
    def setup(self) -> refereeing.Setup:
        """The rules' setup of the rack being played (`refereeing.rack_setup`)."""
        return refereeing.rack_setup(
            self.game, self.options, self.seed + self.rack, self.breaker, self.position
        )

    @property
    def listed(self) -> bool:
        """Shown in the lobby: public and not finished."""
        return not self.options.private and self.status in (Status.OPEN, Status.PLAYING)


def bot_player(bot: BotName) -> PlayerInfo:
    return PlayerInfo(id=f"bot:{bot.value}", name=f"{BOT_LEVELS[bot][1]} bot")


def is_bot(player: PlayerInfo) -> bool:
    return player.id.startswith("bot:")


def has_bot(record: TableRecord) -> bool:
    """Whether a bot holds a seat of the table."""
    return any(seat is not None and is_bot(seat) for seat in record.seats)


def people(record: TableRecord) -> list[str]:
    """The ids of the players of flesh seated at the table (not a bot, not an empty seat)."""
    return [seat.id for seat in record.seats if seat is not None and not is_bot(seat)]


def holder(record: TableRecord) -> str:
    """Whom a bot table's work is counted against: its player of flesh (the table itself if
    it has none seated)."""
    seated_people = people(record)
    return seated_people[0] if seated_people else record.id


def chooser_of(bot: PlayerInfo) -> str:
    """The chooser name (`rules.bot.chooser`) of a bot player made by `bot_player`."""
    return bot.id.removeprefix("bot:")


def set_up(
    game: GameName, options: TableOptions, position: Position, left: bool = False
) -> Position:
    """A set-up position checked for a table of `game` at `options` (`left`: by a shot, as
    `refereeing.checked_position` says); BAD_POSITION saying what is wrong otherwise (nothing
    is stored)."""
    try:
        return refereeing.checked_position(game, position, options, left)
    except refereeing.RuleError as error:
        raise ServiceError(ErrorCode.BAD_POSITION, error.reason) from None


def new_table(table_id: str, create: TableCreate, creator: PlayerInfo, seed: int) -> TableRecord:
    """A table as created: practice and bot tables play at once, a match waits for a player.
    A practice table may start from a set-up position (BAD_POSITION when it cannot)."""
    second = bot_player(create.bot) if create.mode is Mode.BOT else None
    status = Status.OPEN if create.mode is Mode.MATCH else Status.PLAYING
    options = create.options()
    position = None if create.position is None else set_up(create.game, options, create.position)
    now = time.time()
    first = refereeing.rack_setup(create.game, options, seed + 1, 0, position)
    record = TableRecord(
        id=table_id,
        game=create.game,
        mode=create.mode,
        options=options,
        bot=create.bot if create.mode is Mode.BOT else None,
        seats=(creator, second),
        status=status,
        seed=seed,
        state=refereeing.start(first),
        position=position,
        created=now,
        started=now if status is Status.PLAYING else None,
    )
    return record.model_copy(update={"deadline": next_deadline(record)})


def seat_of(record: TableRecord, player_id: str) -> int | None:
    for seat, occupant in enumerate(record.seats):
        if occupant is not None and occupant.id == player_id:
            return seat
    return None


def played_by_both(inputs: list[InputEntry]) -> bool:
    """Whether each seat has played an input of its own in a match (`inputs`, its log): the
    clock's for a seat does not count. A match ended off the table before that (a
    resignation, a claim) is neither rated nor recorded, one its racks decided is (though
    the loser never came to the table). Before, two accounts farmed a rating by creating,
    joining and resigning (300 points in six loops), and guests pushed a bot's up by
    resigning to it before its first shot."""
    return {e.seat for e in inputs if not e.shot_id.startswith(CLOCK_PREFIX)} == {0, 1}


def join_waiting(record: TableRecord, player: PlayerInfo, seen: Seen, now: float) -> TableRecord:
    """`join` an open table whose player is still there (`waiting`; `seen` its heartbeats)."""
    if (
        seat_of(record, player.id) is None
        and record.status is Status.OPEN
        and not waiting(record, seen, now)
    ):
        raise ServiceError(
            ErrorCode.WRONG_PHASE, "the player who opened this table has left: it waits for them"
        )
    return join(record, player)


def join(record: TableRecord, player: PlayerInfo) -> TableRecord:
    """The table with `player` in its free seat, started; ServiceError if it cannot be."""
    if seat_of(record, player.id) is not None:
        raise ServiceError(ErrorCode.ALREADY_SEATED, "you already sit at this table")
    if record.status is not Status.OPEN or record.mode is not Mode.MATCH:
        raise ServiceError(ErrorCode.TABLE_FULL, "this table takes no more players")
    seats = (record.seats[0], player)
    return bump(record, seats=seats, status=Status.PLAYING, started=time.time())


def seated(record: TableRecord, player: PlayerInfo) -> int:
    """The seat of `player`; FORBIDDEN if it has none at this table."""
    seat = seat_of(record, player.id)
    if seat is None:
        raise ServiceError(ErrorCode.FORBIDDEN, "you do not sit at this table")
    return seat


def leave(record: TableRecord, player: PlayerInfo) -> TableRecord:
    """The open table cancelled by its player."""
    seated(record, player)
    if record.status is not Status.OPEN:
        raise ServiceError(ErrorCode.WRONG_PHASE, "the table has started: resign instead")
    return bump(record, status=Status.CANCELLED)


def resign(record: TableRecord, player: PlayerInfo) -> TableRecord:
    """The match given up by `player` (practice: over, with no winner)."""
    seat = seated(record, player)
    if record.status is not Status.PLAYING:
        raise ServiceError(ErrorCode.WRONG_PHASE, f"the table is {record.status.value}")
    winner = None if record.mode is Mode.PRACTICE else 1 - seat
    return bump(record, status=Status.OVER, winner=winner, ended=Ending.RESIGNED)


def claim(
    record: TableRecord, player: PlayerInfo, seen: Seen, now: float, grace: float = GRACE
) -> TableRecord:
    """The match won by `player` because the opponent is absent past its grace period."""
    seat = seated(record, player)
    if record.status is not Status.PLAYING or record.mode is not Mode.MATCH:
        raise ServiceError(ErrorCode.WRONG_PHASE, "there is no match to claim")
    until = grace_until(record, seen, now, grace)[1 - seat]
    if until is None or now < until:
        raise ServiceError(ErrorCode.WRONG_PHASE, "your opponent is here or within grace")
    return bump(record, status=Status.OVER, winner=seat, ended=Ending.CLAIMED)


def rematch_id(table_id: str) -> str:
    """The id of a finished match's rematch table: one per match, whoever creates it."""
    return derived_table_id("rematch", table_id)


def offer_rematch(record: TableRecord, player: PlayerInfo, now: float) -> TableRecord:
    """The finished match with `player`'s rematch offer; once both offered, linked to its
    rematch table (`rematch_id`). Unchanged (the same object) if there is nothing new. Offers
    lapse when the table has not changed for `REMATCH_LAPSE` seconds (its last change was the
    last offer, or came after it): this one is then a new offer, not an accept."""
    seat = seated(record, player)
    if record.status is not Status.OVER or record.mode is not Mode.MATCH:
        raise ServiceError(ErrorCode.WRONG_PHASE, "a rematch follows a finished match")
    if record.rematch_table is not None:
        return record
    lapsed = now - record.updated > REMATCH_LAPSE
    offers = [False, False] if lapsed else list(record.rematch)
    offers[seat] = True
    if not lapsed and (offers[0], offers[1]) == record.rematch:
        return record
    link = rematch_id(record.id) if all(offers) else None
    return bump(record, rematch=(offers[0], offers[1]), rematch_table=link)


def rematch_table(record: TableRecord, seed: int) -> TableRecord:
    """The rematch of a finished match: the same game and options, the seats swapped so that
    the break alternates (seat 0 breaks a table's first rack)."""
    assert record.rematch_table is not None
    first, second = record.seats[1], record.seats[0]
    assert first is not None and second is not None
    create = TableCreate(game=record.game, **record.options.model_dump())
    return join(new_table(record.rematch_table, create, first, seed), second)


def practising(record: TableRecord, player: PlayerInfo) -> None:
    """FORBIDDEN unless `player` sits here, WRONG_PHASE unless this is a practice table under
    way (the actor settles a pending input before any change, so none is being played)."""
    seated(record, player)
    if record.mode is not Mode.PRACTICE or record.status is not Status.PLAYING:
        raise ServiceError(ErrorCode.WRONG_PHASE, "only a practice table under way is re-racked")


def rerack(
    record: TableRecord, player: PlayerInfo, position: Position | None = None, left: bool = False
) -> TableRecord:
    """The practice table's next rack, from a set-up `position` (checked, BAD_POSITION; `left`:
    by the last shot) or, without one, the game's own rack; the rack under way is dropped
    unrecorded."""
    practising(record, player)
    if position is not None:
        position = set_up(record.game, record.options, position, left)
    rack = record.rack + 1
    setup = refereeing.rack_setup(record.game, record.options, record.seed + rack, 0, position)
    return bump(
        record,
        rack=rack,
        breaker=0,
        position=position,
        retake=None,
        state=refereeing.start(setup),
        last_outcome=None,
    )


def retake(record: TableRecord, player: PlayerInfo) -> TableRecord:
    """The practice table re-racked from the balls as they stood when its last shot struck
    (the cue ball where it was placed), so the shot can be taken again; WRONG_PHASE when no
    shot was played since the table was created or re-racked."""
    practising(record, player)
    if record.retake is None:
        raise ServiceError(ErrorCode.WRONG_PHASE, "no shot to take again yet")
    after = rerack(record, player, record.retake, left=True)
    return after.model_copy(update={"retake": record.retake})  # and again, as often as wanted


def bump(record: TableRecord, **changes: object) -> TableRecord:
    """The record with `changes` and the next version (every stored change goes through here).

    Every new version restarts the shot clock of the seat then to act (server/game/clock.py).
    """
    update = {**changes, "version": record.version + 1, "updated": time.time()}
    after = record.model_copy(update=update)
    return after.model_copy(update={"deadline": next_deadline(after)})


def next_deadline(record: TableRecord) -> float | None:
    """When the shot clock of the seat to act runs out, from now: a match without one has the
    `TURN_LIMIT` (None: practice or bot table without a clock, or no turn)."""
    clock = record.options.shot_clock
    if not clock and record.mode is Mode.MATCH:
        clock = TURN_LIMIT
    return time.time() + clock if clock and acting_seat(record) is not None else None


def acting_seat(record: TableRecord) -> int | None:
    """The seat that may send an input now (practice: always seat 0), None if nobody may."""
    if record.status is not Status.PLAYING or record.state.over:
        return None
    return 0 if record.mode is Mode.PRACTICE else record.state.turn


def constraints(record: TableRecord) -> Constraints | None:
    """What the seat to act may send next, from its referee (None: nobody may act)."""
    seat = acting_seat(record)
    if seat is None:
        return None
    now = refereeing.constraints(record.state)
    occupant = record.seats[seat]
    shot = None
    if not now.choices:
        shot = ShotRules(
            place=now.ball_in_hand,
            place_required=now.place_required,
            targets=list(now.targets),
            push_out=now.push_out,
            call=list(now.call),
            nominate=list(now.nominate),
        )
    return Constraints(
        seat=seat,
        player=occupant.id if occupant else None,
        kinds=[InputKind.CHOICE if now.choices else InputKind.SHOT],
        cue_ball=now.cue,
        ball_in_hand=now.ball_in_hand,
        options=list(now.choices),
        deadline=record.deadline,
        shot=shot,
    )


Seen = tuple[float | None, float | None]


def last_seen(record: TableRecord, seen: Seen) -> Seen:
    """When each seat was last known to be here: its last heartbeat, else when the match
    started (a player who never sent one is absent from `PRESENCE_TIMEOUT` after the start,
    so that a seat nobody ever took up can be claimed like one that left)."""
    since = record.started if record.started is not None else record.created
    return (seen[0] or since, seen[1] or since)


def presence(record: TableRecord, seen: Seen, now: float) -> tuple[bool, bool]:
    """Whether each seated human has been here lately (`seen`: the last heartbeat per seat).

    Bots and empty seats count as present; so does everyone before the match has started,
    except the player of an open table who has left it (`waiting`), whom a visitor cannot
    join.
    """
    if record.status is Status.OPEN:
        return waiting(record, seen, now), True
    last = last_seen(record, seen) if record.status is Status.PLAYING else (now, now)
    here = [
        occupant is None or is_bot(occupant) or now - when < PRESENCE_TIMEOUT
        for occupant, when in zip(record.seats, last, strict=True)
    ]
    return here[0], here[1]


def waiting(record: TableRecord, seen: Seen, now: float) -> bool:
    """Whether the player who opened an open table is still there: their last heartbeat, else
    the table's creation, within `PRESENCE_TIMEOUT`. A table its player has left is neither
    joined nor shown (before, whoever joined one that had waited for hours sat at a match the
    other could not know of, and claimed it as soon as the grace ran out)."""
    return now - (seen[0] or record.created) < PRESENCE_TIMEOUT


def attended(record: TableRecord, seen: Seen, now: float) -> bool:
    """Whether any player of flesh is at the table (a bot or an empty seat is nobody): the
    lobby shows a listed table while someone is (an open one while its player waits, a
    started one not all its players have left)."""
    here = presence(record, seen, now)
    return any(
        present and occupant is not None and not is_bot(occupant)
        for occupant, present in zip(record.seats, here, strict=True)
    )


def grace_until(
    record: TableRecord, seen: Seen, now: float, grace: float = GRACE
) -> tuple[float | None, float | None]:
    """For each absent seat, when its opponent may claim the win (None if present): `grace`
    seconds after it was first shown disconnected."""
    here = presence(record, seen, now)
    until = [
        None if present else last + PRESENCE_TIMEOUT + grace
        for present, last in zip(here, last_seen(record, seen), strict=True)
    ]
    return until[0], until[1]


def _listing(record: TableRecord, spectators: int) -> dict[str, object]:
    """What a lobby summary and a full view both say about a table."""
    return {
        "id": record.id,
        "game": record.game,
        "mode": record.mode,
        "status": record.status,
        "seats": list(record.seats),
        "options": record.options,
        "spectators": spectators,
    }


def summary(record: TableRecord, spectators: int = 0) -> TableSummary:
    return TableSummary(**_listing(record, spectators))


def view(
    record: TableRecord, seen: Seen = (None, None), spectators: int = 0, now: float | None = None
) -> TableView:
    """The full state a client starts from (`GET /api/tables/{id}`)."""
    return TableView(
        **_listing(record, spectators),
        channel=record.channel,
        version=record.version,
        rack=record.rack,
        racks_won=record.racks_won,
        state=record.state,
        next=constraints(record),
        last_outcome=record.last_outcome,
        presence=presence(record, seen, time.time() if now is None else now),
        winner=record.winner,
        ended=record.ended,
        replays=list(record.replays),
        rematch=record.rematch,
        rematch_table=record.rematch_table,
        position=record.position,
        retake=record.retake is not None,
        **practice_aids(record),
    )


def practice_aids(record: TableRecord) -> dict[str, object]:
    """What a practice table's view adds for setting up positions: the balls a position may
    hold and the game's named positions at the table's size (nothing at other tables)."""
    if record.mode is not Mode.PRACTICE:
        return {}
    options = record.options
    return {
        "ball_set": list(refereeing.ball_set(record.game, options.reds)),
        "presets": refereeing.presets(record.game, options.size),
    }


def outcome_json(outcome: OutcomeMessage, result: refereeing.Refereed) -> bytes:
    """The JSON of the outcome of `result`, published and stored as it is: its trajectory
    written from the worker's encoding (server.protocol.encoding), the rest encoded here."""
    if result.trajectory_json is None:
        return OutcomeMessage.__pydantic_serializer__.to_json(outcome)
    return with_encoded(outcome, {"trajectory": result.trajectory_json})


def played(
    record: TableRecord,
    entry: InputEntry,
    result: refereeing.Refereed,
    replay: str | None = None,
) -> tuple[TableRecord, OutcomeMessage]:
    """The table after an accepted input was played, and the outcome that announces it,
    without the motion: the table keeps that outcome as its last one (a view carries no
    motion; the channel and the rack's replay do), and `outcome_json` writes the motion in,
    from the worker's JSON, for the input log and the channel.

    A finished rack counts for its winner; the match ends at `race_to` racks, otherwise the
    next rack is racked at once with the break alternating (practice tables rack forever).
    """
    state, rack, breaker = result.state, record.rack, record.breaker
    taken = record.retake
    if record.mode is Mode.PRACTICE and isinstance(entry.input, refereeing.Shot):
        taken = refereeing.shot_position(record.state, entry.input)
    racks_won, status, winner = record.racks_won, record.status, None
    if state.over:
        if record.mode is not Mode.PRACTICE and state.winner is not None:
            won = list(racks_won)
            won[state.winner] += 1
            racks_won = (won[0], won[1])
            if won[state.winner] >= record.options.race_to:
                status, winner = Status.OVER, state.winner
        if status is Status.PLAYING:
            rack = rack + 1
            practice = record.mode is Mode.PRACTICE
            breaker = 0 if practice else refereeing.next_breaker(record.game, breaker)
            setup = refereeing.rack_setup(
                record.game, record.options, record.seed + rack, breaker, record.position
            )
            state = refereeing.start(setup)
    after = bump(
        record,
        state=state,
        rack=rack,
        breaker=breaker,
        racks_won=racks_won,
        status=status,
        winner=winner,
        ended=Ending.RACKS if status is Status.OVER else None,
        replays=record.replays if replay is None else (*record.replays, replay),
        pending=None,
        retake=taken,
    )
    outcome = OutcomeMessage(
        table=record.id,
        version=after.version,
        shot_id=entry.shot_id,
        seat=entry.seat,
        input=entry.input,
        decision=result.decision,
        trajectory=None,  # written from result.trajectory_json (`outcome_json`), kept by no table
        state=after.state,
        next=constraints(after),
        rack=after.rack,
        racks_won=after.racks_won,
        status=after.status,
        winner=after.winner,
        void=result.void,
        replay=replay,
    )
    return after.model_copy(update={"last_outcome": outcome}), outcome

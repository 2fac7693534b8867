"""A table as the server stores it (`TableRecord`), and the pure transitions of its life.

Nothing here does I/O: the match owner (server/match.py) loads a record, applies one of these
transitions and stores the result with a compare-and-set on `version` (server/storage). Seats
and the referee's players coincide: seat 0 is the referee's player 0, and each rack's break
goes to `breaker` by starting the rack with `turn = breaker` (alternating rack by rack).
"""

from __future__ import annotations

import time

from pydantic import BaseModel, ConfigDict, Field

from server import refereeing
from server.api_models import (
    BotName,
    Constraints,
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
from server.errors import ErrorCode, ServiceError
from server.refereeing import GameName, PlayerInput, State

#: A seated player without a heartbeat for this long is shown disconnected (s).
PRESENCE_TIMEOUT = 10.0
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
    deadline: float | None = None
    rematch: tuple[bool, bool] = (False, False)
    rematch_table: str | None = None
    created: float
    updated: float = Field(default=0.0, description="unix time of the last stored change")

    @property
    def channel(self) -> str:
        return channel_of(self.id)

    @property
    def finished(self) -> bool:
        return self.status in (Status.OVER, Status.CANCELLED)

    @property
    def expires(self) -> float:
        """When the live store may drop this table (storage invariant 12)."""
        keep = KEEP_FINISHED if self.finished else KEEP_IDLE
        return max(self.created, self.updated) + keep

    @property
    def listed(self) -> bool:
        """Shown in the lobby: public and not finished."""
        return not self.options.private and self.status in (Status.OPEN, Status.PLAYING)


def channel_of(table_id: str) -> str:
    return f"table-{table_id}"


def bot_player(bot: BotName) -> PlayerInfo:
    return PlayerInfo(id=f"bot:{bot.value}", name=f"Bot ({bot.value})")


def is_bot(player: PlayerInfo) -> bool:
    return player.id.startswith("bot:")


def chooser_of(bot: PlayerInfo) -> str:
    """The chooser name (`rules.bot.chooser`) of a bot player made by `bot_player`."""
    return bot.id.removeprefix("bot:")


def new_table(table_id: str, create: TableCreate, creator: PlayerInfo, seed: int) -> TableRecord:
    """A table as created: practice and bot tables play at once, a match waits for a player."""
    second = bot_player(create.bot) if create.mode is Mode.BOT else None
    status = Status.OPEN if create.mode is Mode.MATCH else Status.PLAYING
    record = TableRecord(
        id=table_id,
        game=create.game,
        mode=create.mode,
        options=create.options(),
        bot=create.bot if create.mode is Mode.BOT else None,
        seats=(creator, second),
        status=status,
        seed=seed,
        state=refereeing.new_rack(create.game, seed + 1, 0),
        created=time.time(),
    )
    return record.model_copy(update={"deadline": next_deadline(record)})


def seat_of(record: TableRecord, player_id: str) -> int | None:
    for seat, occupant in enumerate(record.seats):
        if occupant is not None and occupant.id == player_id:
            return seat
    return None


def join(record: TableRecord, player: PlayerInfo) -> TableRecord:
    """The table with `player` in its free seat, started; ServiceError if it cannot be."""
    if seat_of(record, player.id) is not None:
        raise ServiceError(ErrorCode.ALREADY_SEATED, "you already sit at this table")
    if record.status is not Status.OPEN or record.mode is not Mode.MATCH:
        raise ServiceError(ErrorCode.TABLE_FULL, "this table takes no more players")
    seats = (record.seats[0], player)
    return bump(record, seats=seats, status=Status.PLAYING)


def bump(record: TableRecord, **changes: object) -> TableRecord:
    """The record with `changes` and the next version (every stored change goes through here).

    Every new version restarts the shot clock of the seat then to act (server/clock.py).
    """
    update = {**changes, "version": record.version + 1, "updated": time.time()}
    after = record.model_copy(update=update)
    return after.model_copy(update={"deadline": next_deadline(after)})


def next_deadline(record: TableRecord) -> float | None:
    """When the shot clock of the seat to act runs out, from now (None: no clock, no turn)."""
    clock = record.options.shot_clock
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


def presence(record: TableRecord, seen: Seen, now: float) -> tuple[bool, bool]:
    """Whether each seated human has sent a heartbeat lately (`seen`: the last one per seat).

    Bots, empty seats and players who never sent one count as present.
    """
    here = [
        occupant is None or is_bot(occupant) or last is None or now - last < PRESENCE_TIMEOUT
        for occupant, last in zip(record.seats, seen, strict=True)
    ]
    return here[0], here[1]


def grace_until(
    record: TableRecord, seen: Seen, now: float, grace: float = GRACE
) -> tuple[float | None, float | None]:
    """For each absent seat, when its opponent may claim the win (None if present): `grace`
    seconds after it was first shown disconnected."""
    here = presence(record, seen, now)
    until = [
        None if present or last is None else last + PRESENCE_TIMEOUT + grace
        for present, last in zip(here, seen, strict=True)
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
        rematch=record.rematch,
        rematch_table=record.rematch_table,
    )


def played(
    record: TableRecord,
    entry: InputEntry,
    result: refereeing.Refereed,
    replay: str | None = None,
) -> tuple[TableRecord, OutcomeMessage]:
    """The table after an accepted input was played, and the outcome that announces it.

    A finished rack counts for its winner; the match ends at `race_to` racks, otherwise the
    next rack is racked at once with the break alternating (practice tables rack forever).
    """
    state, rack, breaker = result.state, record.rack, record.breaker
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
            state = refereeing.new_rack(record.game, record.seed + rack, breaker)
    after = bump(
        record,
        state=state,
        rack=rack,
        breaker=breaker,
        racks_won=racks_won,
        status=status,
        winner=winner,
        pending=None,
    )
    outcome = OutcomeMessage(
        table=record.id,
        version=after.version,
        shot_id=entry.shot_id,
        seat=entry.seat,
        input=entry.input,
        decision=result.decision,
        trajectory=result.trajectory,
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

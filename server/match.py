"""The owner of each match: takes its inputs strictly one at a time, and referees each once.

In each server process a table has at most one `MatchOwner`, an actor: a queue of jobs and one
task that runs them in order (the task ends when the queue is empty, so idle tables cost
nothing). Every job starts from a fresh read of the stored table, so replicas sharing a Redis
see each other's moves.

The life of an intent (docs/protocol.md, Playing: intents):

1. **validate** against the stored table: seat, turn, phase, version, then the referee's
   check (no physics). A refusal is answered at once and changes nothing.
2. **accept**: store the input as the table's pending input with a compare-and-set on the
   version (server/storage, invariants 2-4). Only now is the client told `accepted`.
3. **play** it in a worker process (server/workers.py), never on the event loop.
4. **resolve**: store the new record (next version) and the outcome with a compare-and-set
   that requires this input still pending, and only if that succeeds **publish** the outcome on
   the table's channel.

Exactly once across replicas: two replicas may both validate intents for version v, but the
compare-and-set lets exactly one accept; the other retries from a fresh read and answers
`stale_version` or `duplicate`. An accepted input is already stored, so if its replica dies
before resolving it, any replica that next touches the table (a heartbeat is enough) plays it
after `LEASE` seconds; the engine is deterministic, so whoever plays it gets the same outcome,
and the resolve compare-and-set lets only one of them store and publish it.
"""

from __future__ import annotations

import asyncio
import logging
import secrets
import time
from collections import deque
from collections.abc import Awaitable, Callable
from dataclasses import dataclass

from server import ratings, refereeing, tables
from server.api_models import (
    Intent,
    IntentAccepted,
    IntentDuplicate,
    Mode,
    PlayerInfo,
    Status,
    TableMessage,
)
from server.channels import Publisher
from server.errors import ErrorCode, ServiceError
from server.leaderboard import Breaks
from server.ratings import Rating
from server.storage import AcceptResult, RateResult, Storage
from server.tables import InputEntry, TableRecord
from server.workers import WorkerPool

log = logging.getLogger(__name__)

#: Seconds after which an input another replica accepted but never resolved is played here.
LEASE = 15.0
#: Seconds between reads while waiting for another replica to resolve its pending input.
PENDING_POLL = 0.02
#: Compare-and-set attempts before a busy table answers `unavailable`.
CAS_TRIES = 5
#: Rating attempts of one match while other matches of its players keep being rated first
#: (each conflict means another rating landed, so this is only reached under a storm).
RATE_TRIES = 20

Job = Callable[[], Awaitable[None]]
Change = Callable[[TableRecord], TableRecord]


@dataclass
class MatchContext:
    """What every match owner of a process shares."""

    storage: Storage
    pool: WorkerPool
    publisher: Publisher
    on_listing_change: Callable[[], None]
    replica: str
    breaks: Breaks


def _answer(request: asyncio.Future, result: object) -> None:
    """Answer the request waiting on `request` (`result` an exception to refuse it), unless
    it has gone: a client that disconnects cancels the wait, and the job carries on anyway
    (an accepted input is stored, and is played and published whether or not anyone asks)."""
    if request.done():
        return
    if isinstance(result, BaseException):
        request.set_exception(result)
    else:
        request.set_result(result)


def duplicate(entry: InputEntry) -> IntentDuplicate:
    return IntentDuplicate(version=entry.version + 1, outcome=entry.outcome)


class MatchOwner:
    """The actor of one table in this process (see the module docstring)."""

    def __init__(self, table_id: str, context: MatchContext, forget: Callable[[], None]) -> None:
        self.table_id = table_id
        self._context = context
        self._jobs: deque[Job] = deque()
        self._task: asyncio.Task[None] | None = None
        self._forget = forget

    # ----- the actor ----------------------------------------------------------------------
    def _enqueue(self, job: Job) -> None:
        self._jobs.append(job)
        if self._task is None:
            self._task = asyncio.create_task(self._drain())

    async def _drain(self) -> None:
        while self._jobs:
            job = self._jobs.popleft()
            try:
                await job()
            except Exception:  # a job reports to its caller; a bug must not stop the table
                log.exception("table %s: job failed", self.table_id)
        self._task = None
        self._forget()

    async def idle(self) -> None:
        """Wait until every job queued so far has run (tests, shutdown)."""
        while self._task is not None:
            await asyncio.shield(self._task)

    # ----- requests -----------------------------------------------------------------------
    async def intent(self, player: PlayerInfo, intent: Intent) -> IntentAccepted | IntentDuplicate:
        """Answer an intent once it is accepted or refused; it is played afterwards."""
        ack: asyncio.Future[IntentAccepted | IntentDuplicate] = (
            asyncio.get_running_loop().create_future()
        )
        self._enqueue(lambda: self._play_intent(player, intent, ack))
        return await ack

    async def change(self, change: Change) -> TableRecord:
        """Apply `change` to the stored table (compare-and-set) and announce the new view.

        `change` raises ServiceError to refuse; returning the record unchanged stores nothing.
        """
        done: asyncio.Future[TableRecord] = asyncio.get_running_loop().create_future()
        self._enqueue(lambda: self._change(change, done))
        return await done

    def expire(self) -> None:
        """Rule on a shot clock that may have run out (server/clock.py)."""
        self._enqueue(self._expire)

    def poke(self) -> None:
        """Look at the table: finish an abandoned input, let a bot play (after a restart)."""
        self._enqueue(self._look)

    # ----- jobs -----------------------------------------------------------------------------
    async def _settled(self) -> TableRecord:
        """The stored table once no input is pending (playing an abandoned one first)."""
        while True:
            record = await self._context.storage.get_table(self.table_id)
            if record is None:
                raise ServiceError(ErrorCode.NOT_FOUND, "no such table")
            pending = record.pending
            if pending is None:
                return record
            mine = pending.replica == self._context.replica  # our jobs resolve before ending
            if mine or time.time() - pending.accepted_at > LEASE:
                await self._resolve(record)
            else:
                await asyncio.sleep(PENDING_POLL)

    async def _play_intent(
        self, player: PlayerInfo, intent: Intent, ack: asyncio.Future, *, on_time: bool = True
    ) -> None:
        """Validate, accept (answering `ack`), play, store and publish one intent.

        on_time: refuse the intent once the shot clock has run out (False for the clock's own).
        """
        try:
            for _ in range(CAS_TRIES):
                record = await self._settled()
                answer = await self._admit(record, player, intent, on_time)
                if answer is not None:
                    break
            else:
                raise ServiceError(ErrorCode.UNAVAILABLE, "the table is busy: try again")
        except ServiceError as error:
            _answer(ack, error)
            return
        if isinstance(answer, IntentDuplicate):
            _answer(ack, answer)
            return
        _answer(ack, IntentAccepted(version=answer.version + 1))
        await self._resolve(answer)
        self._enqueue(self._look)

    async def _admit(
        self, record: TableRecord, player: PlayerInfo, intent: Intent, on_time: bool
    ) -> TableRecord | IntentDuplicate | None:
        """The record with the intent accepted, its first answer if it is a resend, or None
        if another replica changed the table meanwhile. ServiceError for a refusal."""
        storage = self._context.storage
        try:
            entry = validate(record, player, intent)
            if on_time and record.deadline is not None and time.time() > record.deadline:
                raise ServiceError(ErrorCode.WRONG_PHASE, "the shot clock ran out")
        except ServiceError:
            # A resend (its version has passed) is answered with its first outcome; only a
            # refused intent needs the look-up: `accept` itself refuses a shot id played before.
            seen = await storage.find_input(record.id, intent.shot_id)
            if seen is not None:
                return duplicate(seen)
            raise
        entry = entry.model_copy(update={"replica": self._context.replica})
        result = await storage.accept(record.model_copy(update={"pending": entry}))
        if result.result is AcceptResult.DUPLICATE:
            return duplicate(result.entry)
        if result.result is AcceptResult.CONFLICT:
            return None
        return record.model_copy(update={"pending": entry})

    async def _resolve(self, record: TableRecord) -> None:
        """Play the pending input of `record`, store its outcome, then publish it."""
        entry = record.pending
        assert entry is not None
        context = self._context
        try:
            result = await context.pool.referee(record.state, entry.input)
        except Exception as error:  # a bug in the engine or the referee: void, not stuck
            log.exception("table %s: refereeing %s failed", record.id, entry.shot_id)
            result = refereeing.Refereed(record.state, None, None, void=type(error).__name__)
        replay = None
        if result.state.over:  # the rack ended: archive it before anyone hears of it
            replay = await self._archive_rack(record, entry, result)
        after, outcome = tables.played(record, entry, result, replay)
        stored = entry.model_copy(update={"outcome": outcome})
        if await context.storage.resolve(after, stored):
            await context.publisher.publish(record.channel, outcome)
            await self._status_changed(record, after)

    async def _archive_rack(
        self, record: TableRecord, last: InputEntry, result: refereeing.Refereed
    ) -> str:
        """Store the finished rack's replay and breaks; its replay id."""
        earlier = [
            e.outcome
            for e in await self._context.storage.rack_inputs(record.id, record.rack)
            if e.outcome is not None and e.outcome.void is None
        ]
        played = [(o.input, o.state) for o in earlier] + [(last.input, result.state)]
        replay = await self._context.breaks.rack_finished(record, played)
        return replay.id

    async def _status_changed(self, before: TableRecord, after: TableRecord) -> None:
        """Tell the lobby, and rate a match between two people that has just been decided."""
        if after.listed != before.listed or after.status is not before.status:
            self._context.on_listing_change()
        decided = before.status is Status.PLAYING and after.status is Status.OVER
        if not decided or after.mode is not Mode.MATCH or after.winner is None:
            return
        people = [p for p in after.seats if p is not None and not tables.is_bot(p)]
        if len(people) == 2:
            await rate(self._context.storage, after, people)

    async def _change(self, change: Change, done: asyncio.Future) -> None:
        try:
            for _ in range(CAS_TRIES):
                record = await self._settled()
                after = change(record)
                if after is record:
                    _answer(done, record)
                    return
                if await self._context.storage.update(after):
                    break
            else:
                raise ServiceError(ErrorCode.UNAVAILABLE, "the table is busy: try again")
        except ServiceError as error:
            _answer(done, error)
            return
        seen = await self._context.storage.heartbeats(after.id)
        message = TableMessage(version=after.version, view=tables.view(after, seen))
        await self._context.publisher.publish(after.channel, message)
        await self._status_changed(record, after)
        _answer(done, after)
        self._enqueue(self._look)

    async def _expire(self) -> None:
        """Play the timeout input for the seat to act if its deadline has passed."""
        record = await self._settled()
        seat = tables.acting_seat(record)
        if record.deadline is None or record.deadline > time.time() or seat is None:
            return
        occupant = record.seats[seat]
        action = refereeing.timeout_input(record.state)
        shot_id = f"clock-{record.version:08d}"
        intent = Intent(version=record.version, shot_id=shot_id, input=action)
        await self._play_quietly(occupant, intent, on_time=False)

    async def _play_quietly(self, player: PlayerInfo, intent: Intent, *, on_time: bool) -> None:
        """Play an input the server makes (bot, clock); a refusal is a bug, so it is logged."""
        ack: asyncio.Future = asyncio.get_running_loop().create_future()
        await self._play_intent(player, intent, ack, on_time=on_time)
        if ack.exception() is not None:
            log.error("table %s: server input refused: %s", self.table_id, ack.exception())

    async def _look(self) -> None:
        """Let a bot seat play if it is to act (its shot goes through the same path)."""
        record = await self._settled()
        seat = tables.acting_seat(record)
        occupant = record.seats[seat] if seat is not None else None
        if occupant is None or not tables.is_bot(occupant):
            return
        action = await self._context.pool.bot_input(record.state, tables.chooser_of(occupant))
        intent = Intent(version=record.version, shot_id=f"bot-{record.version:08d}", input=action)
        await self._play_quietly(occupant, intent, on_time=True)


async def rate(storage: Storage, record: TableRecord, people: list[PlayerInfo]) -> None:
    """Rate a decided match between two people: read both ratings, compute, store with the
    storage's compare-and-set (invariant 9), and on a conflict (another match of one of them
    was rated meanwhile, perhaps on another replica) read and compute again."""
    winner = record.winner
    assert winner is not None
    for _ in range(RATE_TRIES):
        current = [(await storage.ratings(p.id)).get(record.game, Rating()) for p in people]
        won, lost = ratings.after_match(current[winner], current[1 - winner])
        new = {people[winner].id: won, people[1 - winner].id: lost}
        if await storage.rate(record.id, record.game, new) is not RateResult.CONFLICT:
            return
    log.error("table %s: not rated after %d conflicts", record.id, RATE_TRIES)


def validate(record: TableRecord, player: PlayerInfo, intent: Intent) -> InputEntry:
    """The entry to store for `intent` from `player`; ServiceError if it may not be played."""
    seat = tables.seat_of(record, player.id)
    if seat is None:
        raise ServiceError(ErrorCode.FORBIDDEN, "you do not sit at this table")
    acting = tables.acting_seat(record)
    if acting is None:
        raise ServiceError(ErrorCode.WRONG_PHASE, f"the table is {record.status.value}")
    if seat != acting:
        raise ServiceError(ErrorCode.NOT_YOUR_TURN, f"seat {acting} is to act")
    if intent.version != record.version:
        raise ServiceError(
            ErrorCode.STALE_VERSION,
            f"the table is at version {record.version}, not {intent.version}: resync",
        )
    options = refereeing.constraints(record.state).choices
    if bool(options) != isinstance(intent.input, refereeing.Choice):
        wanted = "a choice of " + " / ".join(options) if options else "a shot"
        raise ServiceError(ErrorCode.WRONG_PHASE, f"send {wanted}")
    action = refereeing.canonical(intent.input)
    try:
        refereeing.check(record.state, action)
    except refereeing.RuleError as error:
        rule = refereeing.rule_code(error)
        raise ServiceError(ErrorCode.ILLEGAL_INPUT, str(error), rule) from None
    return InputEntry(
        shot_id=intent.shot_id,
        seat=seat,
        input=action,
        version=record.version,
        rack=record.rack,
        accepted_at=time.time(),
    )


class Matches:
    """The match owners of this process, created on demand and dropped when idle."""

    def __init__(self, context: MatchContext) -> None:
        self.context = context
        self._owners: dict[str, MatchOwner] = {}

    def owner(self, table_id: str) -> MatchOwner:
        owner = self._owners.get(table_id)
        if owner is None:
            owner = MatchOwner(table_id, self.context, lambda: self._drop(owner))
            self._owners[table_id] = owner
        return owner

    def _drop(self, owner: MatchOwner) -> None:
        if self._owners.get(owner.table_id) is owner:
            del self._owners[owner.table_id]

    async def idle(self) -> None:
        for owner in list(self._owners.values()):
            await owner.idle()


def new_replica_id() -> str:
    return secrets.token_hex(6)

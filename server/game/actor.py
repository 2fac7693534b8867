"""The table actor: every command on a table, in one place, those that change it strictly one at
a time.

In each server process a table has at most one `TableActor`: a queue of jobs and one task that
runs them in order (the task ends when the queue is empty, so idle tables cost nothing). Every
command is a typed value (server/game/commands.py): the players' `Play`, `Join`, `Leave`, `Resign`,
`Claim`, `Rematch`, `Heartbeat`, `QuickMessage` and `Aim`, handed over by the HTTP handlers with
`ask`, and the server's own `ClockExpiry` (server/game/clock.py) and `BotMove`, queued with `tell`.
The three that change nothing of the versioned table (`commands.Beside`: a heartbeat, a quick
message, an aim) are answered at once, not behind a job that may wait out a dead replica's
lease. Every job starts from a fresh read of the stored table, so replicas sharing a Redis see each
other's moves, and every change is stored with a compare-and-set on the table's version.

The life of an input (docs/protocol.md, Playing: intents):

1. **validate** against the stored table: seat, turn, phase, version, then the referee's
   check (no physics). A refusal is answered at once and changes nothing.
2. **accept**: store the input as the table's pending input with a compare-and-set on the
   version (server/storage, invariants 2-4). Only now is the client told `accepted`.
3. **play** it in a worker process (server/game/workers.py), never on the event loop.
4. **resolve**: store the new record (next version) and the outcome with a compare-and-set
   that requires this input still pending, and only if that succeeds **publish** the outcome on
   the table's channel.

Exactly once across replicas: two replicas may both validate inputs for version v, but the
compare-and-set lets exactly one accept; the other retries from a fresh read and answers
`stale_version` or `duplicate`. An accepted input is already stored, so if its replica dies
before resolving it, any replica that next takes a command for the table (a heartbeat is
enough) plays it after `LEASE` seconds; the engine is deterministic, so whoever plays it gets
the same outcome, and the resolve compare-and-set lets only one of them store and publish it.

What a table guarantees (tests/service/test_actor.py drives random command sequences against
these on both storage backends; tests/service/test_stalls.py holds each over real sockets)
-----------------------------------------------------------------------------------------------
1. **The clock acts.** A table whose seat to act has a deadline gets an input for that seat
   at the deadline (`ClockExpiry`, the input `clock:<version>`), whatever any client sent:
   server inputs carry ids no client can send (server/game/commands.py), so a client's shot id
   can never be taken for one of them. Only while someone is at the table: one that all its
   players have left is not played on for ever (its clock waits, and acts as soon as one of
   them is back), so it idles until it expires.
2. **Absence can be claimed.** A seat that left, or never sent a heartbeat at all, is absent
   `PRESENCE_TIMEOUT` after it was last seen (or after the match started) and claimable by
   its opponent `grace` seconds later (server/game/tables.py, `last_seen`). A heartbeat
   counts as no older than the service's present run (`MatchContext.seen`, storage
   invariant 16): an outage of the whole service is nobody's absence, one replica's restart
   changes nothing.
3. **Quick requests lapse.** A quick-match request lapses when its client stops asking or
   polling (server/game/lobby.py, storage invariant 11), and a quick match has a shot clock.
4. **One rematch.** A finished match has at most one rematch table, however many offers and
   accepts arrive on however many replicas: its id is fixed by the match
   (`tables.rematch_id`) and the link is stored with a compare-and-set before it is created.
5. **No silent resume.** A subscriber that resumes after any restart or eviction gets the
   messages it missed or a gap notice (server/relay/backend.py, invariant 4); every message
   on a table's channel carries the table version, so a client can tell it is behind.
6. **Bounded work.** A bot searches at most once per table version in a process, started
   only by a change of the table or a seated player's heartbeat; a read (`GET`) starts no
   work at all. Searches run on workers of their own, so a match's shot never queues
   behind one, and one player's bot tables search one at a time (`Turns`), so a player with
   many holds one of those workers, not all. Inputs are played at most once (storage
   invariants 3-4). A bot whose search fails still moves (the clock's input), so its
   opponent is never held by it.
7. **Every rack played has its replay.** A rack that ends on the table is archived before its
   last outcome is published; a match that ends off it (a resignation, a claim) archives the
   rack being played, its inputs so far, before the ending is stored, and the table lists the
   replay with the others (`replays`, rack by rack). A rack in which no input was played has
   nothing to replay and no replay; nor has one the shot workers failed to archive (a bug,
   logged), which would otherwise hold its table.
8. **Every request is answered.** A client's command gets its answer, its refusal, or the
   error it met: the storage unreachable (503 `unavailable`) or a bug (500, and logged). No
   request waits on a job that has ended.
"""

from __future__ import annotations

import asyncio
import logging
import secrets
import time
from collections import OrderedDict, deque
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass, field

from server.game import commands, ratings, refereeing, tables
from server.game.commands import ClientCommand, Command
from server.game.history import MatchResult
from server.game.leaderboard import Breaks
from server.game.lobby import new_seed
from server.game.publisher import Publisher
from server.game.ratings import Rating
from server.game.refereeing import State
from server.game.tables import GRACE, InputEntry, TableRecord
from server.game.workers import WorkerPool
from server.protocol import ids
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import QuickText
from server.protocol.models import (
    AimMessage,
    AimRequest,
    ChatMessage,
    Ending,
    IntentAccepted,
    IntentDuplicate,
    Mode,
    PlayerInfo,
    PresenceMessage,
    ReplayView,
    Status,
    TableMessage,
)
from server.relay import RateLimiter
from server.storage import AcceptResult, RateResult, Storage

log = logging.getLogger(__name__)

#: Seconds after which an input another replica accepted but never resolved is played here.
LEASE = 15.0
#: Seconds between reads while waiting for another replica to resolve its pending input.
PENDING_POLL = 0.02
#: Compare-and-set attempts before a busy table answers `unavailable`.
CAS_TRIES = 5
#: Seconds between a process's words to the storage that it is up (`MatchContext.keep_run`),
#: and the silence from every process after which the service counts as having been down.
SAY_UP, OUTAGE = 2.0, 10.0
#: Seconds after which a process announces a table's presence again though it has not changed
#: from what it last said: each replica announces the changes it sees, so another's later
#: announcement may stand on the channel, wrong, until one of them speaks (before, for good
#: when the replica that announced a player gone died and the player came back elsewhere).
PRESENCE_REPEAT = 30.0
#: Rating attempts of one match while other matches of its players keep being rated first
#: (each conflict means another rating landed, so this is only reached under a storm).
RATE_TRIES = 20
#: Tables whose last bot search a process remembers (invariant 6: one search per version).
SEARCHES_KEPT = 10_000

Change = Callable[[TableRecord], TableRecord]
AfterStore = Callable[[TableRecord], Awaitable[None]]
BeforeStore = Callable[[TableRecord, TableRecord], Awaitable[TableRecord]]


class Turns:
    """One at a time per holder: `async with turns.of(holder)` waits while another job of the
    same holder is inside (a lock per holder, forgotten when nobody holds or awaits it)."""

    def __init__(self) -> None:
        self._locks: dict[str, tuple[asyncio.Lock, int]] = {}

    @asynccontextmanager
    async def of(self, holder: str) -> AsyncIterator[None]:
        lock, users = self._locks.get(holder, (asyncio.Lock(), 0))
        self._locks[holder] = (lock, users + 1)
        try:
            async with lock:
                yield
        finally:
            lock, users = self._locks[holder]
            if users == 1:
                del self._locks[holder]
            else:
                self._locks[holder] = (lock, users - 1)

    def __len__(self) -> int:
        return len(self._locks)


@dataclass
class MatchContext:
    """What every table actor of a process shares."""

    storage: Storage
    pool: WorkerPool
    #: The bots' own workers: a search never holds a worker a match's shot is waiting for.
    bots: WorkerPool
    publisher: Publisher
    on_listing_change: Callable[[], None]
    replica: str
    breaks: Breaks
    #: Practice shots per player (server/game/service.py, LIMITS): the one table where the
    #: player is always the one to act.
    practice: RateLimiter
    #: Seconds a disconnected player may stay away before the opponent may claim the win.
    grace: float = GRACE
    #: The presence each table last announced from this process, and when (to announce a
    #: change once, and the same again after `PRESENCE_REPEAT`).
    presence: dict[str, tuple[PresenceMessage, float]] = field(default_factory=dict)
    #: The table version each table's bot last searched at in this process (invariant 6).
    searched: OrderedDict[str, int] = field(default_factory=OrderedDict)
    #: One search at a time for the bot tables of one player (invariant 6).
    bot_turns: Turns = field(default_factory=lambda: Turns())
    #: When the service's present run began (`keep_run`): nobody's absence is counted from
    #: before it (invariant 2). Until the storage has said, this process's start.
    up_since: float = field(default_factory=time.time)

    async def seen(self, table_id: str) -> tables.Seen:
        """Each seat's last heartbeat, as presence and claims count it: none earlier than
        `up_since`, so that the time the service was down is nobody's absence (before, the
        first player back after an outage longer than the grace claimed a rated win)."""
        last = await self.storage.heartbeats(table_id)
        return (
            None if last[0] is None else max(last[0], self.up_since),
            None if last[1] is None else max(last[1], self.up_since),
        )

    async def keep_run(self) -> None:
        """Tell the storage every `SAY_UP` seconds that this process is up, and take the
        service's run from it (storage invariant 16): a replica started while others run
        counts absences as they do (before, one restarted replica showed every player who
        had left as present, played the clock at tables they had left and refused the
        claims the others granted), and a run that began anew moves `up_since` to its start."""
        known = self.up_since
        while True:
            try:
                since = await self.storage.service_since(time.time(), OUTAGE)
                if since != known:
                    known = self.up_since = since
            except Exception:  # storage trouble: the next word tries again
                log.exception("telling the storage the service is up failed")
            await asyncio.sleep(SAY_UP)


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


def take(limiter: RateLimiter, key: str) -> None:
    """Take one request of `key` from `limiter`; RATE_LIMITED (with the wait) if it has none."""
    wait = limiter.allow(key)
    if wait > 0:
        raise ServiceError(ErrorCode.RATE_LIMITED, f"too many requests: retry in {wait:.1f} s")


def duplicate(entry: InputEntry) -> IntentDuplicate:
    return IntentDuplicate(version=entry.version + 1, outcome=entry.outcome)


@dataclass(frozen=True)
class Move:
    """An input to play: a client's intent, or one the server makes (`commands`)."""

    player: PlayerInfo
    version: int
    shot_id: str
    input: refereeing.PlayerInput
    on_time: bool = True  # refused once the shot clock has run out (False: the clock's own)


class TableActor:
    """The actor of one table in this process (see the module docstring)."""

    def __init__(self, table_id: str, context: MatchContext, forget: Callable[[], None]) -> None:
        self.table_id = table_id
        self._context = context
        self._jobs: deque[Callable[[], Awaitable[None]]] = deque()
        self._task: asyncio.Task[None] | None = None
        self._beside = 0  # `commands.Beside` being answered outside the queue
        self._forget = forget

    # ----- the actor ----------------------------------------------------------------------
    def _enqueue(self, job: Callable[[], Awaitable[None]]) -> None:
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
        self._forget_if_idle()

    def _forget_if_idle(self) -> None:
        """Let this process forget the actor once nothing runs on it."""
        if self._task is None and not self._jobs and not self._beside:
            self._forget()

    async def idle(self) -> None:
        """Wait until every job queued so far has run (tests, shutdown)."""
        while self._task is not None:
            await asyncio.shield(self._task)

    # ----- commands -------------------------------------------------------------------------
    async def ask(self, command: ClientCommand) -> object:
        """Run a client's command in turn (one of `commands.Beside` at once) and return the
        actor's answer: an `IntentAccepted` or `IntentDuplicate` (`Play`, answered once
        accepted; it is played afterwards), the stored `TableRecord` (seat and match
        commands), a `PresenceMessage` (`Heartbeat`) or the `ChatMessage` sent
        (`QuickMessage`). ServiceError refuses it, changing nothing; any other error the
        command met (the storage unreachable, a bug) is raised here as well as logged, so
        that no request waits for an answer that will never come."""
        if isinstance(command, commands.Beside):  # changes nothing of the table: no queue
            self._beside += 1
            try:
                return await self._run(command, None)
            finally:
                self._beside -= 1
                self._forget_if_idle()
        done: asyncio.Future[object] = asyncio.get_running_loop().create_future()

        async def job() -> None:
            try:
                _answer(done, await self._run(command, done))
            except ServiceError as error:
                _answer(done, error)
            except Exception as error:  # storage down, or a bug: the asker hears of it too
                _answer(done, error)
                raise

        self._enqueue(job)
        return await done

    def tell(self, command: Command) -> None:
        """Queue a command nobody waits for (the server's own: clock, bot)."""

        async def job() -> None:
            try:
                await self._run(command, None)
            except ServiceError as error:
                log.error("table %s: %s refused: %s", self.table_id, command, error)

        self._enqueue(job)

    async def _run(self, command: Command, done: asyncio.Future | None) -> object:
        """Decide one command (the actor's only dispatch, on the command's type)."""
        match command:
            case commands.Play(player, intent):
                move = Move(player, intent.version, intent.shot_id, intent.input)
                return await self._play(move, done)
            case commands.Join(player):
                seen = await self._context.seen(self.table_id)
                return await self._change(
                    lambda r: tables.join_waiting(r, player, seen, time.time())
                )
            case commands.Leave(player):
                return await self._change(lambda r: tables.leave(r, player))
            case commands.Resign(player):
                return await self._end(lambda r: tables.resign(r, player))
            case commands.Claim(player):
                return await self._claim(player)
            case commands.Rematch(player):
                return await self._change(
                    lambda r: tables.offer_rematch(r, player, time.time()), self._ensure_rematch
                )
            case commands.Rerack(player, position):
                return await self._change(lambda r: tables.rerack(r, player, position))
            case commands.Retake(player):
                return await self._change(lambda r: tables.retake(r, player))
            case commands.Heartbeat(player):
                return await self._heartbeat(player)
            case commands.QuickMessage(player, message):
                return await self._quick_message(player, message)
            case commands.Aim(player, aim):
                return await self._aim(player, aim)
            case commands.ClockExpiry():
                return await self._expire()
            case commands.BotMove():
                return await self._bot_move()
        raise AssertionError(f"unknown command {command!r}")

    # ----- reading the table ------------------------------------------------------------------
    async def _stored(self) -> TableRecord:
        """The stored table as it is (NOT_FOUND if there is none), pending input and all."""
        record = await self._context.storage.get_table(self.table_id)
        if record is None:
            raise ServiceError(ErrorCode.NOT_FOUND, "no such table")
        return record

    async def _settled(self) -> TableRecord:
        """The stored table once no input is pending (playing an abandoned one first)."""
        while True:
            record = await self._stored()
            pending = record.pending
            if pending is None:
                return record
            mine = pending.replica == self._context.replica  # our jobs resolve before ending
            if mine or time.time() - pending.accepted_at > LEASE:
                await self._resolve(record)
            else:
                await asyncio.sleep(PENDING_POLL)

    # ----- inputs ---------------------------------------------------------------------------
    async def _play(self, move: Move, ack: asyncio.Future | None) -> IntentDuplicate | None:
        """Validate, accept (answering `ack`), play, store and publish one input.

        The answer goes to `ack` as soon as the input is accepted, before it is played; the
        job then plays it, so the actor's next command sees the table after it."""
        for attempt in range(CAS_TRIES):
            record = await self._settled()
            if attempt == 0 and record.mode is Mode.PRACTICE and move.on_time:
                take(self._context.practice, move.player.id)  # a client's shot, once
            answer = await self._admit(record, move)
            if answer is not None:
                break
        else:
            raise ServiceError(ErrorCode.UNAVAILABLE, "the table is busy: try again")
        if isinstance(answer, IntentDuplicate):
            return answer
        if ack is not None:
            _answer(ack, IntentAccepted(version=answer.version + 1))
        await self._resolve(answer)
        self._let_bot_act(answer)
        return None

    async def _admit(self, record: TableRecord, move: Move) -> TableRecord | IntentDuplicate | None:
        """The record with the input accepted, its first answer if it is a resend, or None
        if another replica changed the table meanwhile. ServiceError for a refusal."""
        storage = self._context.storage
        try:
            entry = validate(record, move, self._context.replica)
            if move.on_time and record.deadline is not None and time.time() > record.deadline:
                raise ServiceError(ErrorCode.WRONG_PHASE, "the shot clock ran out")
        except ServiceError:
            # A resend (its version has passed) is answered with its first outcome; only a
            # refused input needs the look-up: `accept` itself refuses a shot id played before.
            # Only its sender's seat hears it: to anyone else the refusal stands.
            seen = await storage.find_input(record.id, move.shot_id)
            if seen is not None and seen.seat == tables.seat_of(record, move.player.id):
                return duplicate(seen)
            raise
        accepted = record.model_copy(update={"pending": entry})
        result = await storage.accept(accepted)
        if result.result is AcceptResult.DUPLICATE:
            first = result.entry
            assert first is not None
            if first.seat != entry.seat:
                raise ServiceError(
                    ErrorCode.DUPLICATE, "that shot id is the other seat's input: send a new one"
                )
            return duplicate(first)
        if result.result is AcceptResult.CONFLICT:
            return None
        return accepted

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
        encoded = tables.outcome_json(outcome, result)  # the bytes stored and published
        stored = entry.model_copy(update={"outcome": outcome})
        if await context.storage.resolve(after, stored, encoded):
            await context.publisher.publish_json(record.channel, encoded)
            await self._status_changed(record, after)

    async def _archive_rack(
        self, record: TableRecord, last: InputEntry, result: refereeing.Refereed
    ) -> str | None:
        """Store the finished rack's replay and breaks; its replay id (None: see `_archive`)."""
        played = await self._rack_played(record) + [(last.input, result.state)]
        archived = await self._archive(record, played)
        return archived.id if archived is not None else None

    async def _archive(
        self, record: TableRecord, played: list[tuple[refereeing.PlayerInput, State]]
    ) -> ReplayView | None:
        """Store the replay and breaks of the table's current rack, of these inputs played
        (at least one), archived by the shot workers (`refereeing.rack_archive`). None if the
        workers fail to archive it: a bug there must not stop the match (nor be retried by
        every later command), so the rack goes without its replay, and the failure is logged."""
        try:
            archive = await self._context.pool.rack_archive(record.setup, played)
        except Exception:
            log.exception("table %s: archiving rack %d failed", record.id, record.rack)
            return None
        return await self._context.breaks.rack_played(record, archive)

    async def _rack_played(self, record: TableRecord) -> list[tuple[refereeing.PlayerInput, State]]:
        """Each input of the table's current rack played so far (void ones left out), with the
        state it led to: the rack's record as the rules replay it."""
        entries = await self._context.storage.rack_inputs(record.id, record.rack)
        outcomes = [e.outcome for e in entries if e.outcome is not None and e.outcome.void is None]
        return [(o.input, o.state) for o in outcomes]

    async def _status_changed(self, before: TableRecord, after: TableRecord) -> None:
        """Tell the lobby; rate a match that has just been decided (people and bots alike) once
        both have played in it, and record it in both players' histories."""
        if after.listed != before.listed or after.status is not before.status:
            self._context.on_listing_change()
        decided = before.status is Status.PLAYING and after.status is Status.OVER
        if not decided or after.mode is Mode.PRACTICE or after.winner is None:
            return
        first, second = after.seats
        if first is None or second is None:
            return
        storage = self._context.storage
        if after.ended is not Ending.RACKS and not tables.played_by_both(
            await storage.inputs(after.id)
        ):
            return  # resigned or claimed before both had played: it does not count
        rated = await rate(storage, after, (first, second))
        if rated is not None and after.ended is not None:
            result = MatchResult(
                table=after.id,
                game=after.game,
                at=after.updated,
                seats=(first, second),
                winner=after.winner,
                ended=after.ended,
                racks_won=after.racks_won,
                before=rated[0],
                after=rated[1],
                replays=after.replays,
                private=after.options.private,
            )
            await storage.add_result(result)

    # ----- seats and the match --------------------------------------------------------------
    async def _change(
        self,
        change: Change,
        after_store: AfterStore | None = None,
        before_store: BeforeStore | None = None,
    ) -> TableRecord:
        """Apply `change` to the stored table (compare-and-set), run `after_store` on the
        stored record, then announce the new view. `change` raises ServiceError to refuse;
        returning the record unchanged stores and announces nothing. `before_store(record,
        after)` completes a change with what takes I/O to know (the record to store)."""
        for _ in range(CAS_TRIES):
            record = await self._settled()
            after = change(record)
            if after is record:
                if after_store is not None:
                    await after_store(record)
                return record
            if before_store is not None:
                after = await before_store(record, after)
            if await self._context.storage.update(after):
                break
        else:
            raise ServiceError(ErrorCode.UNAVAILABLE, "the table is busy: try again")
        if after_store is not None:
            await after_store(after)
        seen = await self._context.seen(after.id)
        message = TableMessage(version=after.version, view=tables.view(after, seen))
        await self._context.publisher.publish(after.channel, message)
        await self._status_changed(record, after)
        self._let_bot_act(after)
        return after

    async def _claim(self, player: PlayerInfo) -> TableRecord:
        """The win for `player` if the opponent is absent past grace (read fresh, in turn)."""
        seen = await self._context.seen(self.table_id)
        grace = self._context.grace
        return await self._end(lambda r: tables.claim(r, player, seen, time.time(), grace))

    async def _end(self, change: Change) -> TableRecord:
        """A change that ends the match off the table (a resignation, a claim), stored with
        the replay of the rack being played (invariant 7): archived, with its breaks, before
        the ending is stored, so that nobody hears of the ending without it. A retry after
        another replica's change archives again only if that change played an input."""
        archived: dict[tuple[int, int], str | None] = {}

        async def with_replay(before: TableRecord, after: TableRecord) -> TableRecord:
            played = await self._rack_played(before)
            key = (before.rack, len(played))
            if key not in archived:
                replay = await self._archive(before, played) if played else None
                archived[key] = replay.id if replay is not None else None
            if archived[key] is None:
                return after
            return after.model_copy(update={"replays": (*after.replays, archived[key])})

        return await self._change(change, before_store=with_replay)

    async def _ensure_rematch(self, record: TableRecord) -> None:
        """Create the rematch table a finished match links to, unless it exists: its id is
        fixed by the match (`tables.rematch_id`), so concurrent accepts on any replica make
        one table, and a replica that died between linking and creating is made good by the
        next offer or accept."""
        if record.rematch_table is None:
            return
        storage = self._context.storage
        if await storage.get_table(record.rematch_table) is not None:
            return
        try:
            await storage.create_table(tables.rematch_table(record, new_seed()))
        except ValueError:
            return  # created meanwhile by another replica
        self._context.on_listing_change()

    # ----- presence and messages --------------------------------------------------------------
    async def _heartbeat(self, player: PlayerInfo) -> PresenceMessage:
        """Record that `player` is here; announce the table's presence when it changed."""
        context = self._context
        record = await self._stored()
        seat = tables.seated(record, player)
        now = time.time()
        await context.storage.heartbeat(record.id, seat, now)
        seen = await context.seen(record.id)
        message = PresenceMessage(
            version=record.version,
            presence=tables.presence(record, seen, now),
            grace_until=tables.grace_until(record, seen, now, context.grace),
        )
        last, said = context.presence.get(record.id, (None, 0.0))
        if last is None or last.presence != message.presence or now - said > PRESENCE_REPEAT:
            context.presence[record.id] = (message, now)
            await context.publisher.publish(record.channel, message)
        self.tell(commands.BotMove())  # after a restart: finish what was left, let a bot act
        if record.deadline is not None and record.deadline <= now:
            self.tell(commands.ClockExpiry())  # a clock that waited for someone to come back
        return message

    async def _quick_message(self, player: PlayerInfo, text: QuickText) -> ChatMessage:
        record = await self._stored()
        message = ChatMessage(
            version=record.version,
            from_name=player.name,
            seat=tables.seat_of(record, player.id),
            message=text,
        )
        await self._context.publisher.publish(record.channel, message)
        return message

    async def _aim(self, player: PlayerInfo, aim: AimRequest) -> AimMessage:
        """Pass on the aim of the player to act; refused for anyone else."""
        record = await self._stored()
        seat = tables.seated(record, player)
        if tables.acting_seat(record) != seat:
            raise ServiceError(ErrorCode.WRONG_PHASE, "only the player to act has an aim to show")
        message = AimMessage(version=record.version, seat=seat, **aim.model_dump())
        await self._context.publisher.publish(record.channel, message)
        return message

    # ----- the server's own inputs ------------------------------------------------------------
    async def _expire(self) -> None:
        """Play the timeout input for the seat to act if its deadline has passed."""
        record = await self._settled()
        seat, now = tables.acting_seat(record), time.time()
        if record.deadline is None or record.deadline > now or seat is None:
            return
        if not tables.attended(record, await self._context.seen(record.id), now):
            return  # everyone has left: nothing is played on until someone is back
        occupant = record.seats[seat]
        assert occupant is not None
        shot_id = ids.server_input_id(ids.CLOCK_PREFIX, record.version)
        action = refereeing.timeout_input(record.state)
        await self._play_quietly(Move(occupant, record.version, shot_id, action, on_time=False))

    async def _bot_move(self) -> None:
        """Let a bot seat play if it is to act: one search per table version in a process,
        started only by a change of the table or a seated player's heartbeat (never a read)."""
        record = await self._settled()
        seat = tables.acting_seat(record)
        occupant = record.seats[seat] if seat is not None else None
        if occupant is None or not tables.is_bot(occupant):
            return
        searched = self._context.searched
        if searched.get(record.id) == record.version:
            return
        searched[record.id] = record.version
        searched.move_to_end(record.id)
        while len(searched) > SEARCHES_KEPT:
            searched.popitem(last=False)
        try:
            async with self._context.bot_turns.of(tables.holder(record)):
                action = await self._context.bots.bot_input(
                    record.state, tables.chooser_of(occupant)
                )
        except Exception:  # a bug in the bot must not stop the match: it plays the clock's input
            log.exception("table %s: the bot's search failed", record.id)
            action = refereeing.timeout_input(record.state)
        shot_id = ids.server_input_id(ids.BOT_PREFIX, record.version)
        await self._play_quietly(Move(occupant, record.version, shot_id, action))

    def _let_bot_act(self, record: TableRecord) -> None:
        """After a change of a table with a bot seated, let the bot act if it is its turn (a
        table without one skips the job: its next command settles anything left pending)."""
        if tables.has_bot(record):
            self.tell(commands.BotMove())

    async def _play_quietly(self, move: Move) -> None:
        """Play an input the server makes; a refusal is a bug, so it is logged."""
        try:
            await self._play(move, None)
        except ServiceError as error:
            log.error("table %s: server input %s refused: %s", self.table_id, move.shot_id, error)


Ratings = tuple[Rating, Rating]


async def rate(
    storage: Storage, record: TableRecord, seats: tuple[PlayerInfo, PlayerInfo]
) -> tuple[Ratings, Ratings] | None:
    """Rate a decided match: read both ratings, compute, store with the storage's
    compare-and-set (invariant 9), and on a conflict (another match of one of them was rated
    meanwhile, perhaps on another replica) read and compute again. The seats' ratings before
    and after, or None if the match had been rated already (by another replica)."""
    winner = record.winner
    assert winner is not None
    for _ in range(RATE_TRIES):
        current = [(await storage.ratings(p.id)).get(record.game, Rating()) for p in seats]
        won, lost = ratings.after_match(current[winner], current[1 - winner])
        new = {seats[winner].id: won, seats[1 - winner].id: lost}
        result = await storage.rate(record.id, record.game, new)
        if result is RateResult.RATED:
            return (current[0], current[1]), (new[seats[0].id], new[seats[1].id])
        if result is RateResult.ALREADY:
            return None
    log.error("table %s: not rated after %d conflicts", record.id, RATE_TRIES)
    return None


def validate(record: TableRecord, move: Move, replica: str) -> InputEntry:
    """The entry to store for `move`, accepted by `replica`; ServiceError if it may not be
    played."""
    seat = tables.seated(record, move.player)
    acting = tables.acting_seat(record)
    if acting is None:
        raise ServiceError(ErrorCode.WRONG_PHASE, f"the table is {record.status.value}")
    if seat != acting:
        raise ServiceError(ErrorCode.NOT_YOUR_TURN, f"seat {acting} is to act")
    if move.version != record.version:
        raise ServiceError(
            ErrorCode.STALE_VERSION,
            f"the table is at version {record.version}, not {move.version}: resync",
        )
    options = refereeing.choices(record.state)
    if bool(options) != isinstance(move.input, refereeing.Choice):
        wanted = "a choice of " + " / ".join(options) if options else "a shot"
        raise ServiceError(ErrorCode.WRONG_PHASE, f"send {wanted}")
    action = refereeing.canonical(move.input)
    try:
        refereeing.check(record.state, action)
    except refereeing.RuleError as error:
        rule = refereeing.rule_code(error)
        raise ServiceError(ErrorCode.ILLEGAL_INPUT, str(error), rule) from None
    return InputEntry(
        shot_id=move.shot_id,
        seat=seat,
        input=action,
        version=record.version,
        rack=record.rack,
        accepted_at=time.time(),
        replica=replica,
    )


class Matches:
    """The table actors of this process, created on demand and dropped when idle."""

    def __init__(self, context: MatchContext) -> None:
        self.context = context
        self._owners: dict[str, TableActor] = {}

    def owner(self, table_id: str) -> TableActor:
        owner = self._owners.get(table_id)
        if owner is None:
            owner = TableActor(table_id, self.context, lambda: self._drop(owner))
            self._owners[table_id] = owner
        return owner

    def _drop(self, owner: TableActor) -> None:
        if self._owners.get(owner.table_id) is owner:
            del self._owners[owner.table_id]

    async def idle(self) -> None:
        for owner in list(self._owners.values()):
            await owner.idle()


def new_replica_id() -> str:
    return secrets.token_hex(6)

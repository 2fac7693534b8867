"""What the game service keeps, and the guarantees every storage backend must keep.

Players, display-name claims, tables with their accepted inputs, and the quick-match queue.
`SqliteStorage` (server/storage/sqlite.py, aiosqlite, one file: the embedded default) and
`RedisStorage` (server/storage/redis.py, redis-py asyncio, shared by replicas) implement
`Storage` and pass the same tests (tests/service/test_storage.py, run on both).

What a backend must guarantee
-----------------------------
1. **Durable once answered.** A write that returned has been handed to the database (SQLite:
   committed; Redis: the command answered, durable as far as Redis persists). A restarted
   server reads back exactly what was written.
2. **Compare-and-set on the table version.** `accept`, `resolve` and `update` each succeed only
   if the stored table is exactly in the state the caller read (same `version`, same pending
   input), and then write atomically; otherwise they change nothing and say so. Two replicas
   that act on the same version of a table can never both succeed.
3. **One accepted input at a time.** `accept` stores an input as the table's `pending` input
   (with the record) only when no input is pending; `resolve` replaces the pending input by its
   outcome and the table's next version in one atomic write. So every input that was
   acknowledged is stored before its outcome exists, and each input is resolved at most once.
4. **Shot ids are unique per table.** `accept` refuses a shot id the table has already
   accepted and returns the stored entry instead (`Duplicate`), with its outcome once resolved.
5. **Input log.** `inputs` lists the resolved inputs of a table in the order they were played,
   each with its outcome, and `rack_inputs` those of one rack alone, in the same order, their
   outcomes without trajectories (a rack's end reads its own inputs, not the whole match's,
   for their inputs and states: the motion is most of their bytes); `find_input` finds one by
   shot id, pending or resolved, with its whole outcome. A stored table's last outcome
   (`get_table`) is without its trajectory too, whatever the record stored held: the motion
   is kept once, in the log.
6. **Listing.** `listed_tables` returns the tables whose last stored record is `listed` (public,
   open or playing), newest first, at most `limit`; `due_tables` those whose last stored
   record has a `deadline` at or before a time, earliest first.
7. **Name claims.** `claim_name` gives a name key to one player until a time; it succeeds when
   the key is unclaimed, expired, or already the same player's (then it extends the claim).
   `online_players` counts unexpired claims, and `online` lists their players.
   `name_holder` gives the player who made a key's latest successful claim and until when,
   after the claim lapsed too (until another player claims the key): what a name stands for.
8. **Heartbeats** are kept per table and seat, outside the versioned record: a heartbeat
   never conflicts with an input.
9. **Ratings once per match, never lost.** `rate` stores a table's rating changes at most
   once, however many replicas report the same finished match (`ALREADY`), and only if no
   other rating of those players in that game was stored since they were read: each new
   rating must count exactly one game more than the stored one (none stored: 0), checked and
   written atomically, else nothing is stored (`CONFLICT`) and the caller reads and computes
   again. Two replicas rating two matches of one player at once both land, one after the other.
10. **Breaks once.** `add_break` stores an entry at most once per key, atomically with the
    rankings `top_breaks` and `best_break` read.
11. **Atomic pairing.** `pair` either takes one other player waiting in the same pool (a game
   and its options, as the lobby names them) off the
   queue and records both as paired at the given table (returning the partner), or queues the
   caller; a player is in at most one queue once, never paired twice by one call sequence,
   and never paired with itself. A waiting request lapses at the time it was given (`pair`,
   extended by `touch_quick`): a lapsed one is never paired and reads as idle, so a client
   that stopped asking is never matched with a live player. `quick_status` and
   `cancel_quick` read and leave the queue.
   A pairing records its pool and both players in seat order (`pairing`), so that its table
   can be created by whoever finds it missing (the replica that paired them may have died
   before creating it).
12. **Expiry.** `expire_tables(now, limit)` deletes from the live store at most `limit` tables
   whose last stored record's `expires` (server/game/tables.py: a finished table `KEEP_FINISHED`
   after its last change, an unfinished one `KEEP_IDLE`) is at or before `now`, earliest
   first, each with its inputs, heartbeats, listing and deadline, in one atomic step per
   table, and returns their ids; a table changed since keeps its new expiry. Replays, breaks
   and ratings are never expired. So the live store holds the tables of the last
   `KEEP_FINISHED` / `KEEP_IDLE` seconds, not every table ever played.
13. **Match history.** `add_result` stores a decided match's result at most once per table
   (False, nothing stored, when it was stored before), atomically with its place in both
   players' histories; `results(player, limit)` lists a player's results newest first, at
   most `limit`. Results are never expired.
14. **Challenges settle once.** `add_challenge` stores a pending challenge; `settle_challenge`
   stores it settled (accepted, declined, cancelled or lapsed) only if the stored one is still
   pending, atomically, and says whether it did: two answers racing on any replicas settle
   it once. `pending_challenges` lists a player's pending challenges, made or received.
   `touch_lobby` keeps a player present in the lobby until a time; `in_lobby` says whether it
   still is.
15. **Unused guests expire.** A player's last sign of life is its `add_player` or its latest
   successful `claim_name` (registering, every heartbeat and the lobby's and a quick match's
   polls claim its name).
   `expire_players(before, limit)` deletes at most `limit` players whose last sign of life is
   before `before` and who have no rating, earliest first, and returns their ids; a player
   with a rating is never deleted. So players are not kept for ever: a guest who never played
   a rated match is gone some time after it was last seen (server/game/expiry.py).
   `last_seen` gives a player's last sign of life (None: no such player).
16. **The service's run.** `service_since(now, outage)` records atomically that a process of
   the service is up at `now` and returns when the service's present run began: `now` if no
   process had said so within `outage` seconds (or ever), else the run's stored start. One
   replica's restart, while others run, is no new run; the whole service down longer than
   `outage` is (server/game/actor.py, invariant 2: nobody's absence is counted from before
   the run).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from enum import StrEnum

from server.game.challenge_record import ChallengeRecord
from server.game.history import MatchResult
from server.game.ratings import Rating
from server.game.tables import InputEntry, TableRecord
from server.protocol.models import (
    BreakEntry,
    OutcomeMessage,
    PlayerInfo,
    QuickStatus,
    ReplayView,
)


class RateResult(StrEnum):
    RATED = "rated"
    ALREADY = "already"
    CONFLICT = "conflict"


class AcceptResult(StrEnum):
    ACCEPTED = "accepted"
    CONFLICT = "conflict"
    DUPLICATE = "duplicate"


@dataclass(frozen=True, slots=True)
class Accepted:
    """What `accept` did; `entry` is the stored entry for a DUPLICATE."""

    result: AcceptResult
    entry: InputEntry | None = None


class StorageError(RuntimeError):
    """The database could not be reached or answered nonsense (callers answer 503)."""


class Storage(ABC):
    """The service's persistent state (see the module docstring for the guarantees)."""

    # ----- players ----------------------------------------------------------------------
    @abstractmethod
    async def add_player(self, player: PlayerInfo, now: float) -> None:
        """Store a player, last seen `now` (invariant 15)."""

    @abstractmethod
    async def get_player(self, player_id: str) -> PlayerInfo | None: ...

    @abstractmethod
    async def claim_name(self, key: str, player_id: str, until: float, now: float) -> bool: ...

    @abstractmethod
    async def online_players(self, now: float) -> int: ...

    @abstractmethod
    async def online(self, now: float, limit: int) -> list[str]:
        """The ids of players whose name claim is unexpired at `now` (invariant 7), the most
        recently renewed first, at most `limit`."""

    @abstractmethod
    async def name_holder(self, key: str) -> tuple[str, float] | None:
        """The player of a name key's latest successful claim and its end, lapsed or not
        (invariant 7); None if the key was never claimed."""

    @abstractmethod
    async def last_seen(self, player_id: str) -> float | None:
        """The player's last sign of life (invariant 15); None if there is no such player."""

    @abstractmethod
    async def expire_players(self, before: float, limit: int) -> list[str]:
        """Delete up to `limit` unrated players last seen before `before` (invariant 15)."""

    # ----- tables -----------------------------------------------------------------------
    @abstractmethod
    async def create_table(self, record: TableRecord) -> None:
        """Store a new table; ValueError if the id exists."""

    @abstractmethod
    async def get_table(self, table_id: str) -> TableRecord | None: ...

    @abstractmethod
    async def accept(self, record: TableRecord) -> Accepted:
        """Store `record` (same version as stored, with `pending` set) if the stored table has
        that version and no pending input and the shot id is new (invariants 2-4)."""

    @abstractmethod
    async def resolve(
        self, record: TableRecord, entry: InputEntry, outcome_json: bytes | None = None
    ) -> bool:
        """Store `record` (next version, nothing pending) and `entry` (with its outcome) if the
        stored table is at version `record.version - 1` with `entry` pending. `outcome_json`:
        the outcome's JSON when the caller has it (what it publishes), stored as it is rather
        than encoded again."""

    @abstractmethod
    async def update(self, record: TableRecord) -> bool:
        """Store `record` if the stored table is at `record.version - 1`, nothing pending."""

    @abstractmethod
    async def find_input(self, table_id: str, shot_id: str) -> InputEntry | None: ...

    @abstractmethod
    async def inputs(self, table_id: str) -> list[InputEntry]: ...

    @abstractmethod
    async def rack_inputs(self, table_id: str, rack: int) -> list[InputEntry]:
        """The resolved inputs of one rack, in the order played, outcomes without their
        trajectories (invariant 5)."""

    @abstractmethod
    async def expire_tables(self, now: float, limit: int) -> list[str]:
        """Delete up to `limit` tables whose expiry is at or before `now` (invariant 12)."""

    @abstractmethod
    async def heartbeat(self, table_id: str, seat: int, now: float) -> None:
        """Record that the player in `seat` is connected (not part of the versioned record)."""

    @abstractmethod
    async def heartbeats(self, table_id: str) -> tuple[float | None, float | None]:
        """The last heartbeat of each seat (None: never)."""

    @abstractmethod
    async def service_since(self, now: float, outage: float) -> float:
        """That a process is up at `now`; when the service's run began (invariant 16)."""

    @abstractmethod
    async def due_tables(self, now: float, limit: int) -> list[str]:
        """Tables whose stored shot-clock deadline is at or before `now`, earliest first."""

    @abstractmethod
    async def listed_tables(self, limit: int) -> list[TableRecord]: ...

    # ----- ratings ----------------------------------------------------------------------
    @abstractmethod
    async def ratings(self, player_id: str) -> dict[str, Rating]:
        """The player's rating in each game it has a rated match in."""

    @abstractmethod
    async def rate(self, table_id: str, game: str, ratings: dict[str, Rating]) -> RateResult:
        """Store new ratings for `game` once per table, each one game on from the stored one
        (invariant 9); ALREADY or CONFLICT store nothing."""

    # ----- replays and the leaderboard ---------------------------------------------------
    @abstractmethod
    async def add_replay(self, replay: ReplayView) -> None: ...

    @abstractmethod
    async def get_replay(self, replay_id: str) -> ReplayView | None: ...

    @abstractmethod
    async def add_break(self, entry: BreakEntry, key: str) -> bool:
        """Add a break under a unique `key` (a rack's seat, a claimed record's digest); False
        (nothing stored) if the key was used before."""

    @abstractmethod
    async def top_breaks(self, game: str, limit: int) -> list[BreakEntry]:
        """The highest breaks of a game, highest first."""

    @abstractmethod
    async def best_break(self, game: str, name: str) -> BreakEntry | None:
        """The highest break of a game under a name."""

    # ----- match history ----------------------------------------------------------------
    @abstractmethod
    async def add_result(self, result: MatchResult) -> bool:
        """Store a decided match once per table, in both players' histories (invariant 13)."""

    @abstractmethod
    async def results(self, player_id: str, limit: int) -> list[MatchResult]:
        """A player's decided matches, newest first."""

    # ----- challenges -------------------------------------------------------------------
    @abstractmethod
    async def add_challenge(self, challenge: ChallengeRecord) -> None: ...

    @abstractmethod
    async def get_challenge(self, challenge_id: str) -> ChallengeRecord | None: ...

    @abstractmethod
    async def settle_challenge(self, challenge: ChallengeRecord) -> bool:
        """Store `challenge` (settled) if the stored one is pending (invariant 14)."""

    @abstractmethod
    async def pending_challenges(self, player_id: str) -> list[ChallengeRecord]:
        """The pending challenges made by or to a player, oldest first."""

    @abstractmethod
    async def touch_lobby(self, player_id: str, until: float) -> None: ...

    @abstractmethod
    async def in_lobby(self, player_id: str, now: float) -> bool: ...

    # ----- quick match ------------------------------------------------------------------
    @abstractmethod
    async def pair(
        self, pool: str, player_id: str, table_id: str, now: float, until: float
    ) -> str | None:
        """Pair with a player waiting in the same pool whose request has not lapsed by `now`
        (returning its id, both now paired at `table_id`), or wait until `until` (None).
        Asking again while waiting in the same pool only extends the wait."""

    @abstractmethod
    async def touch_quick(self, player_id: str, until: float) -> None:
        """Keep the player's waiting request until `until` (nothing if it is not waiting)."""

    async def quick_status(self, player_id: str) -> QuickStatus:
        return parse_quick(await self._quick_value(player_id))

    async def pairing(self, player_id: str) -> Pairing | None:
        """The player's pairing, if paired: its table, pool and players in seat order."""
        return Pairing.parse(await self._quick_value(player_id))

    @abstractmethod
    async def _quick_value(self, player_id: str) -> str | None:
        """The player's stored quick-match status (`waiting(...)` or `paired(...)`), if any."""

    @abstractmethod
    async def cancel_quick(self, player_id: str) -> bool:
        """Leave the queue; False if the player was not waiting."""

    @abstractmethod
    async def close(self) -> None:
        """Release connections."""


@dataclass(frozen=True)
class Pairing:
    """Two players paired by quick match at a table (ids and names hold no ':')."""

    table: str
    pool: str  # the game and options asked for (server/game/lobby.py, `pool_of`)
    at: float  # unix time of the pairing
    seats: tuple[str, str]  # the player who waited first

    @classmethod
    def parse(cls, value: str | None) -> Pairing | None:
        """The pairing a stored status records (`paired:<table>:<pool>:<at>:<first>:<second>`)."""
        kind, _, rest = (value or "").partition(":")
        if kind != "paired":
            return None
        table, pool, at, first, second = rest.split(":")
        return cls(table, pool, float(at), (first, second))


def parse_quick(value: str | None) -> QuickStatus:
    """A stored quick-match status (`waiting:<pool>` or `paired:...`) as the API model."""
    if value is None:
        return QuickStatus(status="idle")
    pairing = Pairing.parse(value)
    if pairing is not None:
        return QuickStatus(status="paired", table=pairing.table)
    return QuickStatus(status="waiting")


def waiting(pool: str) -> str:
    return f"waiting:{pool}"


def paired(table_id: str, pool: str, at: float) -> str:
    """The start of a paired status; the players follow, `<first>:<second>` (`Pairing`)."""
    return f"paired:{table_id}:{pool}:{at:.3f}:"


def without_motion(entry: InputEntry) -> InputEntry:
    """The entry with its outcome's trajectory left out (`rack_inputs`, invariant 5)."""
    outcome = entry.outcome
    if outcome is None or outcome.trajectory is None:
        return entry
    return entry.model_copy(update={"outcome": _motionless(outcome)})


def last_without_motion(record: TableRecord) -> TableRecord:
    """The table with its last outcome's trajectory left out (`get_table`, invariant 5)."""
    outcome = record.last_outcome
    if outcome is None or outcome.trajectory is None:
        return record
    return record.model_copy(update={"last_outcome": _motionless(outcome)})


def _motionless(outcome: OutcomeMessage) -> OutcomeMessage:
    return outcome.model_copy(update={"trajectory": None})

"""The embedded storage: one SQLite file (the default of `billiards serve`).

Every multi-statement operation is one `BEGIN IMMEDIATE` transaction under an asyncio lock
(the lock keeps two coroutines' statements out of each other's transactions). The journal is
WAL with `synchronous=NORMAL`: a committed write survives the process being killed (the server
restart the tests do); surviving power loss too would need `synchronous=FULL`. One process
owns the file.

Two connections, one per kind of work, both under that lock:

- **aiosqlite's thread** runs the rest, what may take long among it: transactions over many
  rows (expiry) and the quick-match queue's, reads of rows no index bounds (a rack's inputs
  with their outcomes, a match's whole log, the names online), a player's history and
  challenges, the schema's set-up, and the WAL's checkpoints (the only step that waits on the
  disk: it syncs the log and the file).
- **The event loop's own connection** runs the statements that touch a row or a few by their
  key: the table's compare-and-set (accepting an input, playing it, any other change of a
  table: one statement each), a read by key or of an index's first few (the lobby's listed
  tables, the clock's due ones, a leaderboard's top), a single-row insert, and the short
  transactions of such statements (a name's claim, a match's rating and its result), each
  without an await inside, so one step of the loop. A round trip to aiosqlite's thread
  (a queue, a thread wake-up, a wake-up of the event loop) cost the event loop more than such
  a statement costs run in place: in bench/match_load.py moving them here cut the server's CPU
  per refereed shot by 13-19% (docs/operations.md). Nothing on this connection waits on the
  disk: it commits into the WAL without syncing and never checkpoints (`wal_autocheckpoint=0`);
  every `CHECKPOINT_EVERY` of its writes, a checkpoint runs in the thread, holding the lock
  as a transaction does. Nor does it wait for SQLite's write lock: only this process writes,
  and its transactions hold the asyncio lock that every statement here takes first.

The hot path keeps statements few: a compare-and-set is one `UPDATE ... WHERE version = ? AND
pending = ?` whose row count says whether it held; accepting an input is that one statement
alone (the pending input lives in the table's document until it is played, and the `inputs`
table holds the played ones with their outcomes); playing it is that statement and the
input's INSERT into the log, one transaction without an await (a trigger of the UPDATE
that logged the input saved round trips to the thread when these ran there; on the loop's
connection it only wrote the input's document into the table's row and out again). And since
one process owns the file, the last
committed record of the `CACHED_TABLES` most recently used tables is kept in memory
(write-through, after each commit): a table actor reads its table before every job. So are
the inputs logged in each table's rack under way (server/storage/rack_log.py), which a rack's
end reads back.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import shutil
import sqlite3
import tempfile
import time
from collections import OrderedDict
from collections.abc import AsyncIterator, Iterable
from contextlib import asynccontextmanager
from pathlib import Path

import aiosqlite

from server.game.challenge_record import ChallengeRecord
from server.game.history import MatchResult
from server.game.ratings import Rating
from server.game.tables import KEEP_IDLE, InputEntry, TableRecord
from server.protocol.models import BreakEntry, OutcomeMessage, PlayerInfo, ReplayView
from server.storage import (
    Accepted,
    AcceptResult,
    RateResult,
    Storage,
    last_without_motion,
    paired,
    waiting,
    without_motion,
)
from server.storage.rack_log import RackLog
from server.storage.records import dump, load

#: Tables whose last stored record is kept in memory (least recently used dropped first).
CACHED_TABLES = 1024
#: Played inputs of the racks under way kept in memory, over all tables (server/storage/rack_log).
CACHED_INPUTS = 10_000
#: Writes on the event loop's connection between two checkpoints of the WAL in the thread (a
#: refereed shot's two writes add 14 pages to the WAL, a break's up to 25, measured on picker
#: racks: some 1,400 pages a checkpoint, where SQLite's own automatic one comes at 1,000).
CHECKPOINT_EVERY = 200
#: Seconds the event loop's connection would wait for SQLite's write lock: never, while this
#: process is the file's only writer (module docstring); bounded in case it is not.
LOOP_BUSY_TIMEOUT = 0.5
#: A table's document leaves out its last outcome, which is kept apart (see `_write`): the
#: outcome (its trajectory is most of a record's bytes) changes once per shot, the document twice.
_DOC = {"last_outcome"}
SCHEMA = """
CREATE TABLE IF NOT EXISTS players (id TEXT PRIMARY KEY, doc TEXT NOT NULL, seen REAL);
CREATE TABLE IF NOT EXISTS names (key TEXT PRIMARY KEY, player TEXT NOT NULL, until REAL NOT NULL);
CREATE TABLE IF NOT EXISTS tables (
    id TEXT PRIMARY KEY, version INTEGER NOT NULL, pending TEXT NOT NULL,
    listed INTEGER NOT NULL, created REAL NOT NULL, deadline REAL, doc TEXT NOT NULL,
    expires REAL,
    outcome TEXT,
    last_shot TEXT);
CREATE INDEX IF NOT EXISTS tables_listed ON tables (listed, created);
CREATE INDEX IF NOT EXISTS tables_deadline ON tables (deadline);
CREATE TABLE IF NOT EXISTS inputs (
    table_id TEXT NOT NULL, shot_id TEXT NOT NULL, seq INTEGER, doc TEXT NOT NULL,
    rack INTEGER,
    PRIMARY KEY (table_id, shot_id));
CREATE TABLE IF NOT EXISTS heartbeats (
    table_id TEXT NOT NULL, seat INTEGER NOT NULL, seen REAL NOT NULL,
    PRIMARY KEY (table_id, seat));
CREATE TABLE IF NOT EXISTS ratings (
    player TEXT NOT NULL, game TEXT NOT NULL, doc TEXT NOT NULL, PRIMARY KEY (player, game));
CREATE TABLE IF NOT EXISTS rated (table_id TEXT PRIMARY KEY);
CREATE TABLE IF NOT EXISTS replays (id TEXT PRIMARY KEY, doc TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS breaks (
    key TEXT PRIMARY KEY, game TEXT NOT NULL, score INTEGER NOT NULL, name TEXT NOT NULL,
    at REAL NOT NULL, doc TEXT NOT NULL);
CREATE INDEX IF NOT EXISTS breaks_rank ON breaks (game, score DESC, at);
CREATE TABLE IF NOT EXISTS results (table_id TEXT PRIMARY KEY, doc TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS history (
    player TEXT NOT NULL, at REAL NOT NULL, table_id TEXT NOT NULL,
    PRIMARY KEY (player, table_id));
CREATE INDEX IF NOT EXISTS history_recent ON history (player, at DESC);
CREATE TABLE IF NOT EXISTS challenges (
    id TEXT PRIMARY KEY, challenger TEXT NOT NULL, challenged TEXT NOT NULL,
    status TEXT NOT NULL, created REAL NOT NULL, doc TEXT NOT NULL);
CREATE INDEX IF NOT EXISTS challenges_made ON challenges (challenger, status);
CREATE INDEX IF NOT EXISTS challenges_received ON challenges (challenged, status);
CREATE TABLE IF NOT EXISTS lobby (player TEXT PRIMARY KEY, until REAL NOT NULL);
CREATE TABLE IF NOT EXISTS service (
    id INTEGER PRIMARY KEY CHECK (id = 0), since REAL NOT NULL, alive REAL NOT NULL);
CREATE TABLE IF NOT EXISTS quick (
    player TEXT PRIMARY KEY, status TEXT NOT NULL, queued INTEGER NOT NULL,
    alive REAL NOT NULL DEFAULT 0);
"""


#: Logs a played input under the shot id the table had pending, at the table's new version,
#: in the transaction of `resolve` that stores its table.
LOG_INPUT = (
    "INSERT OR REPLACE INTO inputs (table_id, shot_id, seq, doc, rack) VALUES (?, ?, ?, ?, ?)"
)
#: A compare-and-set's check that the table has played no input of a shot id.
_UNPLAYED = " AND NOT EXISTS (SELECT 1 FROM inputs WHERE table_id = ? AND shot_id = ?)"
#: Accepting an input into a table whose stored document is the record but for it (`accept`):
#: the pending input is set into the document by SQLite's JSON function, the other columns
#: (and the indexes over them) are left as they are.
ACCEPT_INTO = (
    "UPDATE tables SET pending = ?, doc = json_set(doc, '$.pending', json(?)) "
    "WHERE id = ? AND version = ? AND pending = ''" + _UNPLAYED
)


def _adds_pending(stored: TableRecord | None, record: TableRecord) -> bool:
    """Whether `record` is `stored` with a pending input and nothing else: every other field
    the very same value (the table actor accepts a copy of the record it read)."""
    if stored is None or stored.pending is not None:
        return False
    theirs = stored.__dict__
    changed = (name for name, value in record.__dict__.items() if value is not theirs[name])
    return all(name == "pending" for name in changed)


def take_legacy_token_key(path: str | Path) -> str | None:
    """The token signing key an older server kept in the database's `secrets` table, removed
    from it (server/storage/signing_key.py keeps it now, in a file only its user reads); None
    if the database or the table is not there. Plain `sqlite3`: it runs once, at start-up."""
    if not Path(path).exists():
        return None
    with contextlib.closing(sqlite3.connect(str(path))) as db, db:
        found = db.execute("SELECT name FROM sqlite_master WHERE name = 'secrets'").fetchone()
        if found is None:
            return None
        row = db.execute("SELECT value FROM secrets WHERE name = 'tokens'").fetchone()
        db.execute("DROP TABLE secrets")
    with contextlib.closing(sqlite3.connect(str(path))) as db:
        db.execute("VACUUM")  # the dropped key's pages are rewritten, not left in the file
    return None if row is None else row[0]


async def _columns(db: aiosqlite.Connection, table: str) -> set[str]:
    async with db.execute(f"PRAGMA table_info({table})") as cursor:
        return {row[1] for row in await cursor.fetchall()}


async def _add_columns(db: aiosqlite.Connection) -> None:
    """Bring a database from an older server up to `SCHEMA`.

    Tables made before expiry get their `expires` column (invariant 12): they expire
    `KEEP_IDLE` after creation, or as their next change says. Those from before the `outcome`
    column have their last outcomes moved out of the documents into it (they stay there, read
    as before: `last_shot` refers to a logged input's outcome instead). Logged inputs get the
    `rack` column, read once from their documents, and the index over it; the quick-match queue
    its `alive` column. The trigger an older server logged played inputs with is dropped (its
    `played_doc` column stays, unused)."""
    columns = await _columns(db, "tables")
    if "expires" not in columns:
        await db.execute("ALTER TABLE tables ADD COLUMN expires REAL")
        await db.execute("UPDATE tables SET expires = created + ?", (KEEP_IDLE,))
    await db.execute("CREATE INDEX IF NOT EXISTS tables_expires ON tables (expires)")
    if "outcome" not in columns:
        await db.execute("ALTER TABLE tables ADD COLUMN outcome TEXT")
        for table_id, doc in await db.execute_fetchall("SELECT id, doc FROM tables"):
            record = load(TableRecord, doc)
            outcome = record.last_outcome and dump(record.last_outcome)
            moved = (dump(record, exclude=_DOC), outcome, table_id)
            await db.execute("UPDATE tables SET doc = ?, outcome = ? WHERE id = ?", moved)
    if "last_shot" not in columns:
        await db.execute("ALTER TABLE tables ADD COLUMN last_shot TEXT")
    if "rack" not in await _columns(db, "inputs"):
        await db.execute("ALTER TABLE inputs ADD COLUMN rack INTEGER")
        await db.execute("UPDATE inputs SET rack = json_extract(doc, '$.rack')")
        await db.execute("DROP INDEX IF EXISTS inputs_rack")  # over json_extract(doc)
    await db.execute("CREATE INDEX IF NOT EXISTS inputs_by_rack ON inputs (table_id, rack, seq)")
    await db.execute("DROP TRIGGER IF EXISTS tables_log_played")  # an older server's log
    if "seen" not in await _columns(db, "players"):
        # Players from before invariant 15 are seen now: they expire as if new.
        await db.execute("ALTER TABLE players ADD COLUMN seen REAL")
        await db.execute("UPDATE players SET seen = unixepoch()")
    await db.execute("CREATE INDEX IF NOT EXISTS players_seen ON players (seen)")
    if "alive" not in await _columns(db, "quick"):
        # Requests queued before they could lapse lapse at once (invariant 11).
        await db.execute("ALTER TABLE quick ADD COLUMN alive REAL NOT NULL DEFAULT 0")


def _last_outcome(by_value: str | None, logged: str | None) -> OutcomeMessage | None:
    """A table's last outcome from its row (read without its motion): stored by value
    (`outcome`), or as the outcome of the logged input its `last_shot` names."""
    if by_value is not None:
        return load(OutcomeMessage, by_value)
    return None if logged is None else load(InputEntry, logged).outcome


def _loop_connection(path: str | Path) -> sqlite3.Connection:
    """The event loop's connection (module docstring): commits without syncing, never
    checkpoints, and would wait at most `LOOP_BUSY_TIMEOUT` for SQLite's write lock, which no
    statement of this process holds when it runs (the asyncio lock)."""
    now = sqlite3.connect(str(path), isolation_level=None, timeout=LOOP_BUSY_TIMEOUT)
    now.execute("PRAGMA synchronous=NORMAL")
    now.execute("PRAGMA wal_autocheckpoint=0")
    return now


class SqliteStorage(Storage):
    def __init__(
        self, db: aiosqlite.Connection, now: sqlite3.Connection, scratch: Path | None = None
    ) -> None:
        self._db = db
        self._now = now
        self._scratch = scratch  # the folder of a `:memory:` database's file, removed on close
        self._writes = 0
        self._checkpoint: asyncio.Task[None] | None = None
        self._lock = asyncio.Lock()
        self._queued = itertools.count()
        self._tables: OrderedDict[str, TableRecord] = OrderedDict()
        self._racks = RackLog(CACHED_INPUTS)

    @classmethod
    async def open(cls, path: str | Path) -> SqliteStorage:
        """The storage on the file `path`; `":memory:"` is a database of this storage alone,
        gone when it closes: a file in a folder of its own, removed on close. (SQLite's own
        memory databases are one per connection, and this storage has two connections on one
        database.)"""
        scratch = None
        if str(path) == ":memory:":
            scratch = Path(tempfile.mkdtemp(prefix="billiards-"))
            path = scratch / "game.sqlite"
        db = await aiosqlite.connect(str(path), isolation_level=None)
        await db.execute("PRAGMA journal_mode=WAL")
        await db.execute("PRAGMA synchronous=NORMAL")
        await db.executescript(SCHEMA)
        await _add_columns(db)
        storage = cls(db, _loop_connection(path), scratch)
        async with db.execute("SELECT COALESCE(MAX(queued), 0) + 1 FROM quick") as cursor:
            (start,) = await cursor.fetchone()
        storage._queued = itertools.count(start)
        return storage

    async def close(self) -> None:
        """Close both connections, once the checkpoint under way (if any) has ended; one that
        failed is raised after they are closed, not instead of closing them."""
        try:
            if self._checkpoint is not None:
                await self._checkpoint
        finally:
            self._now.close()
            await self._db.close()
            if self._scratch is not None:
                shutil.rmtree(self._scratch, ignore_errors=True)

    @asynccontextmanager
    async def _transaction(self) -> AsyncIterator[aiosqlite.Connection]:
        async with self._lock:
            await self._db.execute("BEGIN IMMEDIATE")
            try:
                yield self._db
            except BaseException:
                await self._db.execute("ROLLBACK")
                raise
            await self._db.execute("COMMIT")

    @asynccontextmanager
    async def _transaction_here(self) -> AsyncIterator[sqlite3.Connection]:
        """A transaction of statements on rows their keys name, on the event loop's
        connection: its body runs them without awaiting anything, so the whole transaction is
        one step of the loop (module docstring)."""
        async with self._lock:
            now = self._now
            now.execute("BEGIN IMMEDIATE")
            try:
                yield now
            except BaseException:
                now.execute("ROLLBACK")
                raise
            now.execute("COMMIT")
        self._wrote()

    async def _rows(self, sql: str, *args: object) -> Iterable[sqlite3.Row]:
        async with self._lock:
            return await self._db.execute_fetchall(sql, args)

    async def _one(self, sql: str, *args: object) -> tuple | None:
        return next(iter(await self._rows(sql, *args)), None)

    async def _keyed_rows(self, sql: str, *args: object) -> list[tuple]:
        """The few rows a key names (or the first few of an index, a LIMIT of at most a few
        hundred), read on the event loop's connection (module docstring)."""
        async with self._lock:
            return self._now.execute(sql, args).fetchall()  # (read to the end: none left open)

    async def _keyed(self, sql: str, *args: object) -> tuple | None:
        """The row a key names, read on the event loop's connection."""
        rows = await self._keyed_rows(sql, *args)
        return rows[0] if rows else None

    async def _alone(self, sql: str, *args: object) -> int:
        """Run one writing statement on rows a key names, atomic on its own (no transaction
        around it), on the event loop's connection; the number of rows it changed."""
        async with self._lock:
            changed = self._now.execute(sql, args).rowcount
        self._wrote()
        return changed

    def _wrote(self) -> None:
        """Count a write on the event loop's connection: every `CHECKPOINT_EVERY`, the WAL is
        checkpointed in aiosqlite's thread (one at a time)."""
        self._writes += 1
        running = self._checkpoint is not None and not self._checkpoint.done()
        if self._writes % CHECKPOINT_EVERY == 0 and not running:
            self._checkpoint = asyncio.create_task(self._checkpoint_wal())

    async def _checkpoint_wal(self) -> None:
        """Copy the WAL's pages into the file, under the lock: no write comes between, so the
        checkpoint takes every page and the next write starts the WAL again from its start (a
        checkpoint racing the writes never catches up, and the WAL would only grow)."""
        async with self._lock:
            await self._db.execute("PRAGMA wal_checkpoint(PASSIVE)")

    def _remember(self, record: TableRecord) -> None:
        """Keep `record` as its table's last committed one (called after the commit), as
        `get_table` reads it back: its last outcome without the motion (invariant 5). A record
        that moves its table to another rack begins that rack's log in memory, empty; a
        finished table's is dropped (no rack of it ends again)."""
        known = self._tables.get(record.id)
        if record.finished:
            self._racks.forget(record.id)
        elif known is not None and known.rack != record.rack:
            self._racks.begin(record.id, record.rack)
        self._tables[record.id] = last_without_motion(record)
        self._tables.move_to_end(record.id)
        if len(self._tables) > CACHED_TABLES:
            self._tables.popitem(last=False)

    # ----- players ----------------------------------------------------------------------
    async def add_player(self, player: PlayerInfo, now: float) -> None:
        doc = dump(player)
        await self._alone("INSERT OR REPLACE INTO players VALUES (?, ?, ?)", player.id, doc, now)

    async def get_player(self, player_id: str) -> PlayerInfo | None:
        row = await self._keyed("SELECT doc FROM players WHERE id = ?", player_id)
        return load(PlayerInfo, row[0]) if row else None

    async def claim_name(self, key: str, player_id: str, until: float, now: float) -> bool:
        async with self._transaction_here() as db:
            claimed = db.execute(
                "INSERT INTO names VALUES (?, ?, ?) ON CONFLICT (key) DO UPDATE SET "
                "player = excluded.player, until = excluded.until "
                "WHERE names.player = excluded.player OR names.until < ?",
                (key, player_id, until, now),
            )
            if claimed.rowcount != 1:
                return False
            db.execute("UPDATE players SET seen = ? WHERE id = ?", (now, player_id))
        return True

    async def name_holder(self, key: str) -> tuple[str, float] | None:
        row = await self._keyed("SELECT player, until FROM names WHERE key = ?", key)
        return (row[0], row[1]) if row else None

    async def last_seen(self, player_id: str) -> float | None:
        row = await self._keyed("SELECT seen FROM players WHERE id = ?", player_id)
        return row[0] if row else None

    async def expire_players(self, before: float, limit: int) -> list[str]:
        async with self._transaction() as db:
            rows = await db.execute_fetchall(
                "SELECT id FROM players WHERE seen < ? AND id NOT IN "
                "(SELECT player FROM ratings) ORDER BY seen LIMIT ?",
                (before, limit),
            )
            ids = [player_id for (player_id,) in rows]
            await db.executemany("DELETE FROM players WHERE id = ?", [(i,) for i in ids])
        return ids

    async def online_players(self, now: float) -> int:
        row = await self._one("SELECT COUNT(*) FROM names WHERE until >= ?", now)
        return row[0] if row else 0

    async def online(self, now: float, limit: int) -> list[str]:
        rows = await self._rows(
            "SELECT player FROM names WHERE until >= ? ORDER BY until DESC LIMIT ?", now, limit
        )
        return [row[0] for row in rows]

    # ----- tables -----------------------------------------------------------------------
    async def create_table(self, record: TableRecord) -> None:
        outcome = record.last_outcome and dump(record.last_outcome)
        try:
            await self._alone(
                "INSERT INTO tables (id, version, pending, listed, created, deadline, doc, "
                "expires, outcome) VALUES (?, ?, '', ?, ?, ?, ?, ?, ?)",
                record.id,
                record.version,
                int(record.listed),
                record.created,
                record.deadline,
                dump(record, exclude=_DOC),
                record.expires,
                outcome,
            )
        except aiosqlite.IntegrityError:
            raise ValueError(f"table {record.id} exists") from None
        self._racks.begin(record.id, record.rack)
        self._remember(record)

    async def get_table(self, table_id: str) -> TableRecord | None:
        record = self._tables.get(table_id)
        if record is not None:
            self._tables.move_to_end(table_id)
            return record
        row = await self._keyed(
            "SELECT t.doc, json_replace(t.outcome, '$.trajectory', NULL), "
            "json_replace(i.doc, '$.outcome.trajectory', NULL) FROM tables t "
            "LEFT JOIN inputs i ON i.table_id = t.id AND i.shot_id = t.last_shot "
            "WHERE t.id = ?",
            table_id,
        )
        if row is None:
            return None
        record = load(TableRecord, row[0])
        last = _last_outcome(row[1], row[2])
        if last is not None:
            record = record.model_copy(update={"last_outcome": last})
        self._remember(record)
        return record

    def _write(
        self,
        record: TableRecord,
        was: tuple[int, str],
        pending: str,
        new_shot: str | None = None,
        last_shot: str | None = None,
    ) -> bool:
        """Store `record` (with `pending`) if the stored table is at version and pending
        `was` (and, given `new_shot`, the table has played no input of that shot id): one
        statement, so the check and the write are one step, run on the event loop's
        connection under the caller's lock (who counts the write, `_wrote`).

        The last outcome is written only when it is not the one the stored record has: as
        `last_shot`, the shot id of the logged input whose outcome it is (so a shot's outcome,
        a break's some 30 KB, is written once, in the log, and the table's row stays small:
        SQLite rewrites a whole row on every update, and the table's is updated twice a
        shot), else by value in `outcome`."""
        sets = "version = ?, pending = ?, listed = ?, deadline = ?, doc = ?, expires = ?"
        args: list[object] = [
            record.version,
            pending,
            int(record.listed),
            record.deadline,
            dump(record, exclude=_DOC),
            record.expires,
        ]
        stored = self._tables.get(record.id)
        if last_shot is not None:
            sets += ", last_shot = ?, outcome = NULL"
            args.append(last_shot)
        elif stored is None or stored.last_outcome is not record.last_outcome:
            sets += ", last_shot = NULL, outcome = ?"
            args.append(record.last_outcome and dump(record.last_outcome))
        sql = f"UPDATE tables SET {sets} WHERE id = ? AND version = ? AND pending = ?"
        args += [record.id, *was]
        if new_shot is not None:
            sql += _UNPLAYED
            args += [record.id, new_shot]
        return self._now.execute(sql, args).rowcount == 1

    async def accept(self, record: TableRecord) -> Accepted:
        """One statement: the pending input is stored in the table's document (the inputs
        table holds played inputs), so the compare-and-set, the shot id's check and the
        write are one atomic UPDATE. When the record is the stored one with its pending input
        and nothing else, only the input is encoded and set into the stored document
        (`ACCEPT_INTO`): encoding the whole table again, and rewriting the columns its
        indexes are over, cost 2-3% of the server's instructions a shot in
        bench/match_instructions.py (3.51M against 3.43M)."""
        entry = record.pending
        if entry is None:
            raise ValueError("accept needs a record with its pending input")
        async with self._lock:
            if _adds_pending(self._tables.get(record.id), record):
                doc = InputEntry.__pydantic_serializer__.to_json(entry).decode()
                args = (entry.shot_id, doc, record.id, record.version, record.id, entry.shot_id)
                accepted = self._now.execute(ACCEPT_INTO, args).rowcount == 1
            else:
                accepted = self._write(record, (record.version, ""), entry.shot_id, entry.shot_id)
            self._wrote()
        if accepted:
            self._remember(record)
            return Accepted(AcceptResult.ACCEPTED)
        seen = await self.find_input(record.id, entry.shot_id)
        return Accepted(AcceptResult.CONFLICT if seen is None else AcceptResult.DUPLICATE, seen)

    async def resolve(
        self, record: TableRecord, entry: InputEntry, outcome_json: bytes | None = None
    ) -> bool:
        """The table's compare-and-set and the played input's log, one transaction on the
        event loop's connection (two statements, no await between them)."""
        doc = dump(entry, outcome_json and {"outcome": outcome_json})
        last = entry.outcome is not None and entry.outcome is record.last_outcome
        last_shot = entry.shot_id if last else None
        logged = (record.id, entry.shot_id, record.version, doc, entry.rack)
        async with self._transaction_here() as now:
            was = (record.version - 1, entry.shot_id)
            stored = self._write(record, was, "", last_shot=last_shot)
            if stored:
                now.execute(LOG_INPUT, logged)
                self._racks.logged(record.id, without_motion(entry))
        if stored:
            self._remember(record)
        return stored

    async def update(self, record: TableRecord) -> bool:
        async with self._lock:  # one statement: atomic without a transaction of its own
            changed = self._write(record, (record.version - 1, ""), "")
            self._wrote()
            if not changed:
                return False
        self._remember(record)
        return True

    async def find_input(self, table_id: str, shot_id: str) -> InputEntry | None:
        row = await self._keyed(
            "SELECT doc FROM inputs WHERE table_id = ? AND shot_id = ?", table_id, shot_id
        )
        if row is not None:
            return load(InputEntry, row[0])
        record = await self.get_table(table_id)
        pending = None if record is None else record.pending
        return pending if pending is not None and pending.shot_id == shot_id else None

    async def inputs(self, table_id: str) -> list[InputEntry]:
        rows = await self._rows(
            "SELECT doc FROM inputs WHERE table_id = ? AND seq IS NOT NULL ORDER BY seq", table_id
        )
        return [load(InputEntry, row[0]) for row in rows]

    async def rack_inputs(self, table_id: str, rack: int) -> list[InputEntry]:
        """From memory where the rack under way is kept (server/storage/rack_log); else read
        from the log, and kept from then on if it is the table's rack under way (under the
        lock: no input is logged between the read and keeping it)."""
        kept = self._racks.get(table_id, rack)
        if kept is not None:
            return kept
        async with self._lock:
            rows = await self._db.execute_fetchall(  # (JSON functions copy numbers as written)
                "SELECT json_replace(doc, '$.outcome.trajectory', NULL) FROM inputs "
                "WHERE table_id = ? AND rack = ? AND seq IS NOT NULL ORDER BY seq",
                (table_id, rack),
            )
            entries = [load(InputEntry, row[0]) for row in rows]
            known = self._tables.get(table_id)
            if known is not None and known.rack == rack and not known.finished:
                self._racks.begin(table_id, rack, entries)
        return entries

    async def expire_tables(self, now: float, limit: int) -> list[str]:
        async with self._transaction() as db:
            async with db.execute(
                "SELECT id FROM tables WHERE expires <= ? ORDER BY expires LIMIT ?", (now, limit)
            ) as cursor:
                ids = [row[0] for row in await cursor.fetchall()]
            for sql in (
                "DELETE FROM inputs WHERE table_id = ?",
                "DELETE FROM heartbeats WHERE table_id = ?",
                "DELETE FROM tables WHERE id = ?",
            ):
                await db.executemany(sql, [(table_id,) for table_id in ids])
            for table_id in ids:
                self._tables.pop(table_id, None)
                self._racks.forget(table_id)
        return ids

    async def heartbeat(self, table_id: str, seat: int, now: float) -> None:
        await self._alone("INSERT OR REPLACE INTO heartbeats VALUES (?, ?, ?)", table_id, seat, now)

    async def heartbeats(self, table_id: str) -> tuple[float | None, float | None]:
        rows = await self._keyed_rows(
            "SELECT seat, seen FROM heartbeats WHERE table_id = ?", table_id
        )
        seen = dict(rows)
        return seen.get(0), seen.get(1)

    async def service_since(self, now: float, outage: float) -> float:
        async with self._transaction_here() as db:
            row = db.execute("SELECT since, alive FROM service WHERE id = 0").fetchone()
            since = now if row is None or now - row[1] > outage else row[0]
            alive = now if row is None else max(now, row[1])
            db.execute("INSERT OR REPLACE INTO service VALUES (0, ?, ?)", (since, alive))
        return since

    async def due_tables(self, now: float, limit: int) -> list[str]:
        rows = await self._keyed_rows(  # (an index's first `limit`)
            "SELECT id FROM tables WHERE deadline <= ? ORDER BY deadline LIMIT ?", now, limit
        )
        return [row[0] for row in rows]

    async def listed_tables(self, limit: int) -> list[TableRecord]:
        rows = await self._keyed_rows(  # (an index's first `limit`)
            "SELECT id FROM tables WHERE listed = 1 ORDER BY created DESC LIMIT ?", limit
        )
        records = [await self.get_table(table_id) for (table_id,) in rows]
        return [record for record in records if record is not None]

    # ----- ratings ----------------------------------------------------------------------
    async def ratings(self, player_id: str) -> dict[str, Rating]:
        rows = await self._keyed_rows("SELECT game, doc FROM ratings WHERE player = ?", player_id)
        return {game: load(Rating, doc) for game, doc in rows}

    async def rate(self, table_id: str, game: str, ratings: dict[str, Rating]) -> RateResult:
        async with self._transaction_here() as db:
            if db.execute("SELECT 1 FROM rated WHERE table_id = ?", (table_id,)).fetchall():
                return RateResult.ALREADY
            for player, rating in ratings.items():
                rows = db.execute(
                    "SELECT doc FROM ratings WHERE player = ? AND game = ?", (player, game)
                ).fetchall()
                stored = load(Rating, rows[0][0]).games if rows else 0
                if rating.games != stored + 1:
                    return RateResult.CONFLICT
            db.execute("INSERT INTO rated VALUES (?)", (table_id,))
            for player, rating in ratings.items():
                db.execute(
                    "INSERT OR REPLACE INTO ratings VALUES (?, ?, ?)",
                    (player, game, dump(rating)),
                )
            return RateResult.RATED

    # ----- match history ----------------------------------------------------------------
    async def add_result(self, result: MatchResult) -> bool:
        async with self._transaction_here() as db:
            cursor = db.execute(
                "INSERT OR IGNORE INTO results VALUES (?, ?)", (result.table, dump(result))
            )
            if cursor.rowcount == 0:
                return False
            for player in result.seats:
                db.execute(
                    "INSERT INTO history VALUES (?, ?, ?)", (player.id, result.at, result.table)
                )
            return True

    async def results(self, player_id: str, limit: int) -> list[MatchResult]:
        rows = await self._rows(
            "SELECT doc FROM history JOIN results USING (table_id) WHERE player = ?"
            " ORDER BY at DESC LIMIT ?",
            player_id,
            limit,
        )
        return [load(MatchResult, row[0]) for row in rows]

    # ----- challenges -------------------------------------------------------------------
    async def add_challenge(self, challenge: ChallengeRecord) -> None:
        await self._alone(
            "INSERT INTO challenges VALUES (?, ?, ?, ?, ?, ?)",
            challenge.id,
            challenge.challenger.id,
            challenge.challenged.id,
            challenge.status.value,
            challenge.created,
            dump(challenge),
        )

    async def get_challenge(self, challenge_id: str) -> ChallengeRecord | None:
        row = await self._keyed("SELECT doc FROM challenges WHERE id = ?", challenge_id)
        return load(ChallengeRecord, row[0]) if row else None

    async def settle_challenge(self, challenge: ChallengeRecord) -> bool:
        changed = await self._alone(
            "UPDATE challenges SET status = ?, doc = ? WHERE id = ? AND status = 'pending'",
            challenge.status.value,
            dump(challenge),
            challenge.id,
        )
        return changed == 1

    async def pending_challenges(self, player_id: str) -> list[ChallengeRecord]:
        rows = await self._rows(
            "SELECT doc FROM challenges WHERE status = 'pending' AND"
            " (challenger = ? OR challenged = ?) ORDER BY created",
            player_id,
            player_id,
        )
        return [load(ChallengeRecord, row[0]) for row in rows]

    async def touch_lobby(self, player_id: str, until: float) -> None:
        await self._alone("INSERT OR REPLACE INTO lobby VALUES (?, ?)", player_id, until)

    async def in_lobby(self, player_id: str, now: float) -> bool:
        row = await self._keyed("SELECT until FROM lobby WHERE player = ?", player_id)
        return row is not None and row[0] >= now

    # ----- replays and the leaderboard ---------------------------------------------------
    async def add_replay(self, replay: ReplayView) -> None:
        await self._alone("INSERT INTO replays VALUES (?, ?)", replay.id, dump(replay))

    async def get_replay(self, replay_id: str) -> ReplayView | None:
        row = await self._keyed("SELECT doc FROM replays WHERE id = ?", replay_id)
        return load(ReplayView, row[0]) if row else None

    async def add_break(self, entry: BreakEntry, key: str) -> bool:
        try:
            await self._alone(
                "INSERT INTO breaks VALUES (?, ?, ?, ?, ?, ?)",
                key,
                entry.game,
                entry.score,
                entry.name,
                entry.at,
                dump(entry),
            )
        except aiosqlite.IntegrityError:
            return False
        return True

    async def top_breaks(self, game: str, limit: int) -> list[BreakEntry]:
        rows = await self._keyed_rows(  # (an index's first `limit`)
            "SELECT doc FROM breaks WHERE game = ? ORDER BY score DESC, at LIMIT ?", game, limit
        )
        return [load(BreakEntry, row[0]) for row in rows]

    async def best_break(self, game: str, name: str) -> BreakEntry | None:
        row = await self._one(
            "SELECT doc FROM breaks WHERE game = ? AND name = ? ORDER BY score DESC, at LIMIT 1",
            game,
            name,
        )
        return load(BreakEntry, row[0]) if row else None

    # ----- quick match ------------------------------------------------------------------
    async def pair(
        self, pool: str, player_id: str, table_id: str, now: float, until: float
    ) -> str | None:
        async with self._transaction() as db:
            await db.execute(
                "DELETE FROM quick WHERE status LIKE 'waiting:%' AND alive < ? AND player != ?",
                (now, player_id),
            )
            async with db.execute("SELECT status FROM quick WHERE player = ?", (player_id,)) as c:
                row = await c.fetchone()
            if row is not None and row[0] == waiting(pool):
                await db.execute("UPDATE quick SET alive = ? WHERE player = ?", (until, player_id))
                return None
            async with db.execute(
                "SELECT player FROM quick WHERE status = ? AND player != ? ORDER BY queued LIMIT 1",
                (waiting(pool), player_id),
            ) as cursor:
                partner = await cursor.fetchone()
            if partner is None:
                await db.execute(
                    "INSERT OR REPLACE INTO quick VALUES (?, ?, ?, ?)",
                    (player_id, waiting(pool), next(self._queued), until),
                )
                return None
            status = f"{paired(table_id, pool, now)}{partner[0]}:{player_id}"
            for who in (player_id, partner[0]):
                await db.execute(
                    "INSERT OR REPLACE INTO quick VALUES (?, ?, ?, 0)",
                    (who, status, next(self._queued)),
                )
            return partner[0]

    async def touch_quick(self, player_id: str, until: float) -> None:
        async with self._transaction() as db:
            await db.execute(
                "UPDATE quick SET alive = ? WHERE player = ? AND status LIKE 'waiting:%'"
                " AND alive >= ?",
                (until, player_id, time.time()),
            )

    async def _quick_value(self, player_id: str) -> str | None:
        row = await self._keyed("SELECT status, alive FROM quick WHERE player = ?", player_id)
        if row is None or (row[0].startswith("waiting:") and row[1] < time.time()):
            return None  # a lapsed request reads as none (invariant 11)
        return row[0]

    async def cancel_quick(self, player_id: str) -> bool:
        async with self._transaction() as db:
            cursor = await db.execute(
                "DELETE FROM quick WHERE player = ? AND status LIKE 'waiting:%'", (player_id,)
            )
            return cursor.rowcount > 0

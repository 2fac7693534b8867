"""The storage contract (server/storage/__init__.py), one suite run on SQLite and on Redis."""

from __future__ import annotations

import asyncio
import sqlite3
import time
from pathlib import Path

import pytest

from server.game import refereeing
from server.game.actor import rate
from server.game.history import MatchResult
from server.game.ratings import Rating
from server.game.tables import (
    KEEP_FINISHED,
    KEEP_IDLE,
    InputEntry,
    TableRecord,
    bump,
    join,
    outcome_json,
    played,
)
from server.protocol.models import BreakEntry, Ending, PlayerInfo, Source, Status
from server.storage import AcceptResult, RateResult, Storage
from server.storage import sqlite as sqlite_storage
from server.storage.rack_log import RackLog
from server.storage.records import dump
from server.storage.sqlite import SCHEMA, SqliteStorage
from tests.service.conftest import ADA, BOB, OpenStorage, a_table


def pending(record: TableRecord, shot_id: str, rack: int = 1) -> TableRecord:
    entry = InputEntry(
        shot_id=shot_id,
        seat=0,
        input=refereeing.Choice(option="play_on"),
        version=record.version,
        rack=rack,
        accepted_at=time.time(),
    )
    return record.model_copy(update={"pending": entry})


async def test_players_and_name_claims(storage: Storage) -> None:
    await storage.add_player(ADA, 0.0)
    assert await storage.get_player("p_ada") == ADA
    assert await storage.get_player("p_nobody") is None
    now = time.time()
    assert await storage.claim_name("ada", "p_ada", now + 60, now)
    assert not await storage.claim_name("ada", "p_bob", now + 60, now)
    assert await storage.claim_name("ada", "p_ada", now + 120, now)  # extends its own claim
    assert await storage.online_players(now) == 1
    expired = await storage.claim_name("bob", "p_bob", now + 0.05, now)
    await asyncio.sleep(0.1)
    later = time.time()
    assert expired and await storage.claim_name("bob", "p_ada", later + 60, later)
    assert await storage.online_players(later) == 2


async def test_unused_guests_expire_and_rated_players_stay(storage: Storage) -> None:
    """Invariant 13 (before: player rows were never deleted)."""
    old = [PlayerInfo(id=f"p_{n:016x}", name=f"guest {n}") for n in range(5)]
    for seen, player in enumerate(old):
        await storage.add_player(player, 100.0 + seen)
    await storage.claim_name("guest0", old[0].id, 600.0, 500.0)  # seen again at 500
    assert await storage.rate("c" * 20, "nineball", {old[1].id: Rating(games=1)}) is (
        RateResult.RATED
    )
    assert await storage.expire_players(400.0, 2) == [old[2].id, old[3].id]  # earliest first
    assert await storage.expire_players(400.0, 10) == [old[4].id]
    assert await storage.expire_players(400.0, 10) == []
    for player in old[2:]:
        assert await storage.get_player(player.id) is None
    assert await storage.get_player(old[0].id) == old[0]  # seen since
    assert await storage.get_player(old[1].id) == old[1]  # rated: kept for good
    assert await storage.expire_players(10_000.0, 10) == [old[0].id]


async def test_a_table_reads_back_after_reopening(open_storage: OpenStorage) -> None:
    first = await open_storage()
    record = a_table()
    await first.create_table(record)
    with pytest.raises(ValueError):
        await first.create_table(record)
    await first.close()
    second = await open_storage()
    assert await second.get_table(record.id) == record
    assert await second.get_table("f" * 20) is None


async def test_update_is_a_compare_and_set_on_the_version(storage: Storage) -> None:
    record = a_table()
    await storage.create_table(record)
    joined = join(record, BOB)
    assert await storage.update(joined)
    assert not await storage.update(joined)  # the stored version moved on
    assert not await storage.update(bump(record))  # built from a stale read
    assert (await storage.get_table(record.id)) == joined


async def test_accept_then_resolve_plays_each_input_once(storage: Storage) -> None:
    record = join(a_table(), BOB)
    await storage.create_table(record)
    accepted = pending(record, "shot-0001")
    assert (await storage.accept(accepted)).result is AcceptResult.ACCEPTED
    # While an input is pending, nothing else is accepted or updated.
    assert (await storage.accept(pending(record, "shot-0002"))).result is AcceptResult.CONFLICT
    assert not await storage.update(bump(record))
    duplicate = await storage.accept(pending(record, "shot-0001"))
    assert duplicate.result is AcceptResult.DUPLICATE
    assert duplicate.entry == accepted.pending
    assert await storage.find_input(record.id, "shot-0001") == accepted.pending
    assert await storage.inputs(record.id) == []  # pending, not yet played

    after = bump(record)
    assert not await storage.resolve(after, pending(record, "shot-0009").pending)
    assert await storage.resolve(after, accepted.pending)
    assert not await storage.resolve(after, accepted.pending)  # resolved at most once
    assert await storage.get_table(record.id) == after
    assert await storage.inputs(record.id) == [accepted.pending]
    again = await storage.accept(pending(after, "shot-0001"))
    assert again.result is AcceptResult.DUPLICATE  # a shot id is never accepted twice


async def test_concurrent_accepts_of_one_version_let_exactly_one_through(
    open_storage: OpenStorage,
) -> None:
    stores = [await open_storage() for _ in range(4)]  # as if four replicas
    record = join(a_table(), BOB)
    await stores[0].create_table(record)
    results = await asyncio.gather(
        *(s.accept(pending(record, f"shot-{i:04d}")) for i, s in enumerate(stores * 5))
    )
    assert [r.result for r in results].count(AcceptResult.ACCEPTED) == 1


async def test_listed_tables_are_the_public_unfinished_ones(storage: Storage) -> None:
    public = a_table("1" * 20)
    private = a_table("2" * 20, private=True)
    for record in (public, private):
        await storage.create_table(record)
    assert [r.id for r in await storage.listed_tables(10)] == [public.id]
    assert await storage.update(bump(public, status=Status.CANCELLED))
    assert await storage.listed_tables(10) == []


async def wait_quick(storage: Storage, game: str, player: str, table: str) -> str | None:
    """Ask for a quick match, the request kept for a minute."""
    now = time.time()
    return await storage.pair(game, player, table, now, now + 60)


async def test_pairing_is_atomic_under_one_hundred_simultaneous_requests(
    open_storage: OpenStorage,
) -> None:
    stores = [await open_storage() for _ in range(4)]
    players = [f"p_{i:03d}" for i in range(100)]
    partners = await asyncio.gather(
        *(
            wait_quick(stores[i % 4], "nineball", player, f"{i:020x}")
            for i, player in enumerate(players)
        )
    )
    pairs = [(p, q) for p, q in zip(players, partners, strict=True) if q is not None]
    seated = [who for pair in pairs for who in pair]
    assert len(pairs) == 50 and len(set(seated)) == 100  # nobody seated twice
    statuses = {p: await stores[0].quick_status(p) for p in players}
    for p, q in pairs:
        assert statuses[p].status == statuses[q].status == "paired"
        assert statuses[p].table == statuses[q].table  # a table of exactly these two
        pairing = await stores[1].pairing(p)
        assert pairing == await stores[2].pairing(q)  # one record of it, for both
        assert pairing is not None and pairing.table == statuses[p].table
        assert pairing.seats == (q, p) and pairing.pool == "nineball"  # the waiter first
    assert len({statuses[p].table for p in players}) == 50


async def test_waiting_twice_queues_once_and_cancel_leaves_the_queue(storage: Storage) -> None:
    assert await wait_quick(storage, "snooker", "p_a", "a" * 20) is None
    assert await wait_quick(storage, "snooker", "p_a", "b" * 20) is None
    assert (await storage.quick_status("p_a")).status == "waiting"
    assert await storage.cancel_quick("p_a")
    assert not await storage.cancel_quick("p_a")
    assert await wait_quick(storage, "snooker", "p_b", "c" * 20) is None  # p_a is gone
    assert await wait_quick(storage, "nineball", "p_c", "d" * 20) is None  # another game
    assert await wait_quick(storage, "snooker", "p_c", "e" * 20) == "p_b"  # moved queues
    assert (await storage.quick_status("p_b")).table == "e" * 20
    assert (await storage.quick_status("p_z")).status == "idle"


async def test_a_request_lapses_unless_it_is_kept(storage: Storage) -> None:
    now = time.time()
    assert await storage.pair("nineball", "p_gone", "a" * 20, now, now + 0.3) is None
    assert await storage.pair("eightball", "p_kept", "b" * 20, now, now + 0.3) is None
    await storage.touch_quick("p_kept", now + 60)
    await storage.touch_quick("p_idle", now + 60)  # not waiting: nothing to keep
    await asyncio.sleep(0.5)
    assert (await storage.quick_status("p_gone")).status == "idle"  # lapsed
    assert (await storage.quick_status("p_idle")).status == "idle"
    await storage.touch_quick("p_gone", time.time() + 60)  # too late: it stays lapsed
    assert (await storage.quick_status("p_gone")).status == "idle"
    assert await wait_quick(storage, "nineball", "p_new", "c" * 20) is None  # not p_gone
    assert (await storage.quick_status("p_kept")).status == "waiting"
    assert await wait_quick(storage, "eightball", "p_other", "d" * 20) == "p_kept"


async def test_heartbeats_are_kept_per_seat_beside_the_record(storage: Storage) -> None:
    record = a_table()
    await storage.create_table(record)
    assert await storage.heartbeats(record.id) == (None, None)
    await storage.heartbeat(record.id, 1, 1234.5)
    await storage.heartbeat(record.id, 1, 1235.25)
    assert await storage.heartbeats(record.id) == (None, 1235.25)
    assert await storage.update(join(record, BOB))  # the version did not move


async def test_the_services_run_outlasts_a_replica_not_an_outage(
    open_storage: OpenStorage,
) -> None:
    """Invariant 16: a replica that starts while another runs joins the run; once no process
    has said it was up for longer than the outage, the next one starts a new run."""
    one, other = await open_storage(), await open_storage()
    assert await one.service_since(1000.25, 10.0) == 1000.25
    assert await other.service_since(1004.5, 10.0) == 1000.25  # a replica starting meanwhile
    assert await one.service_since(1013.0, 10.0) == 1000.25  # 8.5 s after the last word
    assert await other.service_since(1008.0, 10.0) == 1000.25  # a late word moves nothing back
    assert await other.service_since(1023.5, 10.0) == 1023.5  # 10.5 s of silence: a new run
    assert await one.service_since(1024.0, 10.0) == 1023.5


async def test_a_match_is_rated_once(open_storage: OpenStorage) -> None:
    stores = [await open_storage() for _ in range(3)]
    new = {"p_ada": Rating(rating=1600, games=1), "p_bob": Rating(rating=1400, games=1)}
    applied = await asyncio.gather(*(s.rate("t" * 20, "snooker", new) for s in stores))
    assert sorted(applied) == [RateResult.ALREADY, RateResult.ALREADY, RateResult.RATED]
    assert await stores[1].ratings("p_ada") == {"snooker": new["p_ada"]}
    again = {"p_ada": Rating(rating=9, games=2)}
    assert await stores[0].rate("t" * 20, "snooker", again) is RateResult.ALREADY
    assert (await stores[0].ratings("p_ada"))["snooker"].rating == 1600
    assert await stores[0].ratings("p_nobody") == {}


async def test_a_rating_computed_from_a_stale_read_is_refused(storage: Storage) -> None:
    first = {"p_ada": Rating(rating=1600, games=1), "p_bob": Rating(rating=1400, games=1)}
    assert await storage.rate("a" * 20, "nineball", first) is RateResult.RATED
    # Computed from the unrated state (games 0 -> 1) after the first match landed: refused.
    stale = {"p_ada": Rating(rating=1450, games=1), "p_cy": Rating(rating=1550, games=1)}
    assert await storage.rate("b" * 20, "nineball", stale) is RateResult.CONFLICT
    assert (await storage.ratings("p_ada"))["nineball"] == first["p_ada"]
    assert await storage.ratings("p_cy") == {}  # nothing of the refused table stored
    fresh = {"p_ada": Rating(rating=1500, games=2), "p_cy": Rating(rating=1550, games=1)}
    assert await storage.rate("b" * 20, "nineball", fresh) is RateResult.RATED


async def test_two_replicas_rating_one_player_at_once_lose_nothing(
    open_storage: OpenStorage,
) -> None:
    """Ada finishes a match against Bob on one replica and one against Cy on another at the
    same moment: both ratings land (each replica reads, computes and compare-and-sets)."""
    stores = [await open_storage() for _ in range(2)]
    cy = BOB.model_copy(update={"id": "p_cy", "name": "Cy"})
    matches = []
    for i, opponent in enumerate((BOB, cy)):
        seated = join(a_table(f"{i + 1}" * 20), opponent)
        matches.append(bump(seated, status=Status.OVER, winner=0))
    await asyncio.gather(
        *(rate(s, m, m.seats) for s, m in zip(stores * 4, matches * 4, strict=True))
    )
    ada = (await stores[0].ratings("p_ada"))["nineball"]
    assert ada.games == 2 and ada.rating > (await stores[1].ratings("p_bob"))["nineball"].rating
    assert (await stores[1].ratings("p_cy"))["nineball"].games == 1


async def test_due_tables_follow_the_stored_deadline(storage: Storage) -> None:
    record = a_table()
    await storage.create_table(record)
    assert await storage.due_tables(time.time() + 1e6, 10) == []  # no clock
    ticking = bump(record).model_copy(update={"deadline": 1000.0})
    assert await storage.update(ticking)
    assert await storage.due_tables(999.0, 10) == []
    assert await storage.due_tables(1000.0, 10) == [record.id]
    stopped = bump(ticking)  # this table has no clock: the next version has no deadline
    assert stopped.deadline is None and await storage.update(stopped)
    assert await storage.due_tables(time.time(), 10) == []


async def test_breaks_rank_once_per_key(storage: Storage) -> None:
    def entry(score: int, name: str) -> BreakEntry:
        return BreakEntry(game="snooker", score=score, name=name, source=Source.CLAIM, at=score)

    assert await storage.add_break(entry(40, "Ada"), "k1")
    assert not await storage.add_break(entry(147, "Eve"), "k1")  # a key enters once
    assert await storage.add_break(entry(75, "Bob"), "k2")
    assert await storage.add_break(entry(60, "Ada"), "k3")
    assert await storage.add_break(entry(10, "Ada"), "k4")
    top = await storage.top_breaks("snooker", 2)
    assert [(b.name, b.score) for b in top] == [("Bob", 75), ("Ada", 60)]
    assert (await storage.best_break("snooker", "Ada")).score == 60
    assert await storage.best_break("snooker", "Eve") is None
    assert await storage.top_breaks("nineball", 5) == []


async def test_rack_inputs_are_one_racks_inputs_in_order(storage: Storage) -> None:
    record = join(a_table(), BOB)
    await storage.create_table(record)
    for i, rack in enumerate((1, 1, 2, 2, 2, 3)):
        accepted = pending(record, f"shot-{i:04d}", rack)
        assert (await storage.accept(accepted)).result is AcceptResult.ACCEPTED
        record = bump(record)
        assert await storage.resolve(record, accepted.pending)
    shots = {r: [e.shot_id for e in await storage.rack_inputs(record.id, r)] for r in (1, 2, 3)}
    assert shots == {1: ["shot-0000", "shot-0001"], 2: [f"shot-{i:04d}" for i in (2, 3, 4)]} | {
        3: ["shot-0005"]
    }
    assert await storage.rack_inputs(record.id, 4) == []
    assert len(await storage.inputs(record.id)) == 6


async def test_a_racks_inputs_read_the_same_by_the_storage_that_played_them_and_after_a_restart(
    open_storage: OpenStorage,
) -> None:
    """Invariant 5 through a storage's own memory of the rack under way (SQLite keeps it,
    server/storage/rack_log.py): racks ended by a shot and by a change of the table, one
    begun on a table read back after a restart, each rack read before and after its inputs."""

    async def play(storage: Storage, record: TableRecord, shot_id: str, **after: object):
        accepted = pending(record, shot_id, record.rack)
        assert (await storage.accept(accepted)).result is AcceptResult.ACCEPTED
        entry = accepted.pending.model_copy(update={"outcome": None})
        moved = bump(record, **after)
        assert await storage.resolve(moved, entry)
        return moved

    async def racks(storage: Storage, record: TableRecord) -> dict[int, list[str]]:
        return {
            rack: [e.shot_id for e in await storage.rack_inputs(record.id, rack)]
            for rack in range(1, record.rack + 2)
        }

    first = await open_storage()
    record = join(a_table(), BOB)
    await first.create_table(record)
    assert await racks(first, record) == {1: [], 2: []}
    record = await play(first, record, "a1")
    record = await play(first, record, "a2", rack=2)  # the rack's last shot racks the next
    assert await racks(first, record) == {1: ["a1", "a2"], 2: [], 3: []}
    record = await play(first, record, "b1")
    record = bump(record, rack=3)  # a change of the table racks again (practice's rerack)
    assert await first.update(record)
    record = await play(first, record, "c1")
    seen = await racks(first, record)
    assert seen == {1: ["a1", "a2"], 2: ["b1"], 3: ["c1"], 4: []}
    await first.close()
    second = await open_storage()
    record = await second.get_table(record.id)
    assert await racks(second, record) == seen
    record = await play(second, record, "c2")
    record = await play(second, await second.get_table(record.id), "c3", rack=4)
    record = await play(second, record, "d1")
    seen = {1: ["a1", "a2"], 2: ["b1"], 3: ["c1", "c2", "c3"], 4: ["d1"], 5: []}
    assert await racks(second, record) == seen
    await second.close()
    assert await racks(await open_storage(), record) == seen


async def test_sqlite_accepts_into_the_stored_document_only_what_is_new(tmp_path: Path) -> None:
    """SQLite's accept of the stored record with its pending input sets the input into the
    stored document; an accept that changes more stores the whole record. Both read back
    after a restart as the record accepted, and play on."""
    first = await SqliteStorage.open(tmp_path / "game.sqlite")
    same, changed = join(a_table("1" * 20), BOB), join(a_table("2" * 20), BOB)
    for record in (same, changed):
        await first.create_table(record)
    just_the_input = pending(same, "shot-0001")
    more = pending(changed, "shot-0001").model_copy(update={"deadline": 1e10})
    for record in (just_the_input, more):
        assert (await first.accept(record)).result is AcceptResult.ACCEPTED
    await first.close()
    again = await SqliteStorage.open(tmp_path / "game.sqlite")
    for record in (just_the_input, more):
        assert await again.get_table(record.id) == record
        assert await again.resolve(bump(record, pending=None), record.pending)
        assert [e.shot_id for e in await again.rack_inputs(record.id, 1)] == ["shot-0001"]
    await again.close()


def test_a_rack_log_keeps_a_bounded_number_of_inputs_oldest_tables_first() -> None:
    entry = pending(a_table(), "shot").pending
    log = RackLog(limit=5)
    log.begin("t1", 1, [entry] * 3)
    log.begin("t2", 1)
    log.logged("t2", entry)
    assert log.get("t1", 1) == [entry] * 3 and log.get("t2", 2) is None
    log.logged("t2", entry)
    log.logged("t2", entry)  # six in all: t1 was read before t2, so it goes first
    assert log.get("t1", 1) is None and log.get("t2", 1) == [entry] * 3
    log.logged("t2", entry.model_copy(update={"rack": 2}))  # not the rack kept: nothing kept
    assert log.get("t2", 1) is None and log.get("t2", 2) is None


@pytest.mark.parametrize("encoded", [False, True], ids=["model", "outcome_json"])
async def test_rack_inputs_leave_out_the_motion_and_keep_the_state(
    open_storage: OpenStorage, encoded: bool
) -> None:
    """A rack's record needs its inputs and states; `find_input` and `inputs` keep the whole
    outcome, after a restart too, whether storage encodes the outcome itself or is given the
    JSON the service publishes (its trajectory encoded by the worker, `tables.outcome_json`);
    the table's last outcome is read without its motion, whatever the stored record held."""
    storage = await open_storage()
    record = join(a_table(), BOB)
    await storage.create_table(record)
    action = refereeing.bot_input(record.state, "picker")
    entry = InputEntry(
        shot_id="break-0001", seat=0, input=action, version=record.version, accepted_at=0.0
    )
    accepted = record.model_copy(update={"pending": entry})
    assert (await storage.accept(accepted)).result is AcceptResult.ACCEPTED
    result = refereeing.referee(record.state, action)
    after, outcome = played(accepted, entry, result)
    whole = outcome.model_copy(update={"trajectory": result.trajectory})
    assert result.trajectory is not None and outcome.trajectory is None
    if encoded:  # the service's way: the outcome kept without motion, its JSON with it
        stored = entry.model_copy(update={"outcome": outcome})
        assert await storage.resolve(after, stored, outcome_json(outcome, result))
    else:
        stored = entry.model_copy(update={"outcome": whole})
        assert await storage.resolve(after.model_copy(update={"last_outcome": whole}), stored)
    (logged,) = await storage.rack_inputs(record.id, 1)
    assert logged.outcome is not None and logged.outcome.trajectory is None
    assert logged.outcome.state == outcome.state and logged.input == action
    assert [e.outcome for e in await storage.inputs(record.id)] == [whole]  # invariant 5
    assert (await storage.find_input(record.id, "break-0001")).outcome == whole
    assert (await storage.get_table(record.id)).last_outcome == outcome
    await storage.close()
    again = await open_storage()
    assert await again.get_table(record.id) == after and after.last_outcome == outcome
    assert (await again.find_input(record.id, "break-0001")).outcome == whole


async def test_finished_and_abandoned_tables_expire_with_their_inputs(storage: Storage) -> None:
    playing = join(a_table("1" * 20), BOB)
    finished = join(a_table("2" * 20), BOB)
    for record in (playing, finished):
        await storage.create_table(record)
    accepted = pending(finished, "shot-0001")
    assert (await storage.accept(accepted)).result is AcceptResult.ACCEPTED
    over = bump(finished, status=Status.OVER, winner=0)
    assert await storage.resolve(over, accepted.pending)
    await storage.heartbeat(over.id, 0, time.time())
    now = time.time()
    assert over.expires <= now + KEEP_FINISHED < playing.expires
    assert await storage.expire_tables(now, 10) == []  # nothing is due yet
    assert await storage.expire_tables(now + KEEP_FINISHED + 1, 10) == [over.id]
    assert await storage.get_table(over.id) is None
    assert await storage.inputs(over.id) == [] and await storage.rack_inputs(over.id, 1) == []
    assert await storage.find_input(over.id, "shot-0001") is None
    assert await storage.heartbeats(over.id) == (None, None)
    assert await storage.get_table(playing.id) == playing  # unfinished: kept KEEP_IDLE
    assert [r.id for r in await storage.listed_tables(10)] == [playing.id]
    # A change moves the expiry on; an abandoned table goes KEEP_IDLE after its last change.
    touched = bump(playing)
    assert await storage.update(touched)
    assert await storage.expire_tables(playing.expires, 10) == []
    assert await storage.expire_tables(touched.expires, 10) == [playing.id]
    assert await storage.listed_tables(10) == [] and touched.expires - touched.updated == KEEP_IDLE


async def test_expiry_is_bounded_per_call_and_earliest_first(storage: Storage) -> None:
    records = [a_table(f"{i:020x}") for i in range(5)]
    for i, record in enumerate(records):
        await storage.create_table(record.model_copy(update={"created": 1000.0 + i}))
    later = 1000.0 + KEEP_IDLE + 10
    first = await storage.expire_tables(later, 3)
    assert first == [r.id for r in records[:3]]
    assert await storage.expire_tables(later, 3) == [r.id for r in records[3:]]
    assert await storage.expire_tables(later, 3) == []


#: Each column added to `SCHEMA` since the first file, as it is written there.
ADDED = {
    "expires": ",\n    expires REAL",
    "outcome": ",\n    outcome TEXT",
    "last_shot": ",\n    last_shot TEXT",
    "rack": "\n    rack INTEGER,",
}


def older_schema(*columns: str) -> str:
    """`SCHEMA` as a server from before `columns` made it (before the inputs' `rack`, they
    were indexed by the rack in their documents)."""
    schema = SCHEMA
    for column in columns:
        assert ADDED[column] in schema
        schema = schema.replace(ADDED[column], "")
    if "rack" in columns:
        schema += "CREATE INDEX inputs_rack ON inputs (table_id, json_extract(doc, '$.rack'), seq);"
    return schema


async def test_a_database_from_before_expiry_gets_its_expiry_column(tmp_path: Path) -> None:
    """A SQLite file written before invariant 12 opens, and its tables expire KEEP_IDLE after
    they were created (or as their next change says)."""
    path = tmp_path / "old.sqlite3"
    old_schema = older_schema("expires", "outcome", "last_shot", "rack")
    record = a_table()
    with sqlite3.connect(path) as db:
        db.executescript(old_schema)
        row = (record.id, 0, "", 1, record.created, None, record.model_dump_json())
        db.execute("INSERT INTO tables VALUES (?, ?, ?, ?, ?, ?, ?)", row)
    db.close()
    storage = await SqliteStorage.open(path)
    try:
        assert await storage.get_table(record.id) == record
        assert await storage.expire_tables(record.created + KEEP_IDLE - 1, 10) == []
        assert await storage.expire_tables(record.created + KEEP_IDLE, 10) == [record.id]
    finally:
        await storage.close()


FAR_FUTURE = 4e9  # unix seconds: every table has expired by then


async def test_a_memory_database_is_one_database_for_both_connections_and_gone_on_close() -> None:
    """`:memory:` (the game service without a database file): what the event loop's
    connection writes, the thread's reads, and the other way round; a second such storage
    is another database; closing removes its file."""
    storage, other = await SqliteStorage.open(":memory:"), await SqliteStorage.open(":memory:")
    record = join(a_table(), BOB).model_copy(update={"deadline": None})  # none falls due
    try:
        await storage.create_table(record)  # the loop's connection
        await storage.heartbeat(record.id, 0, 5.0)
        assert await storage.due_tables(float("inf"), 10) == []  # the loop's, and no error
        assert await storage.expire_tables(FAR_FUTURE, 10) == [record.id]
        assert await storage.get_table(record.id) is None  # the thread's delete, seen here
        await other.create_table(record)
        assert await other.expire_tables(FAR_FUTURE, 10) == [record.id]
        scratch = storage._scratch
        assert scratch is not None and scratch.exists()
    finally:
        await storage.close()
        await other.close()
    assert not scratch.exists()


async def wal_reach(path: Path, writes: int) -> int:
    """The bytes the WAL of a new SQLite storage at `path` reaches over `writes` single-row
    writes on the event loop's connection, the loop yielding between them as a server's
    does (the storage is closed after)."""
    storage = await SqliteStorage.open(path)
    try:
        record = join(a_table(), BOB)
        await storage.create_table(record)
        for i in range(writes):
            await storage.heartbeat(record.id, i % 2, float(i))
            await asyncio.sleep(0)
        return Path(f"{path}-wal").stat().st_size
    finally:
        await storage.close()


async def test_sqlite_checkpoints_the_wal_in_its_thread_so_the_wal_stays_bounded(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The event loop's connection never checkpoints (that would sync the disk on the loop);
    every CHECKPOINT_EVERY of its writes the storage checkpoints in aiosqlite's thread, so
    the WAL restarts instead of growing with every write: without those checkpoints the same
    writes take it several times as far."""
    writes = 10 * sqlite_storage.CHECKPOINT_EVERY
    bounded = await wal_reach(tmp_path / "a.sqlite3", writes)
    monkeypatch.setattr(sqlite_storage, "CHECKPOINT_EVERY", 10 * writes)
    unchecked = await wal_reach(tmp_path / "b.sqlite3", writes)
    assert unchecked > 4 * bounded


async def test_a_database_from_before_the_outcome_column_keeps_its_last_outcomes(
    tmp_path: Path,
) -> None:
    """Tables stored with the last outcome inside their document read back the same."""
    path = tmp_path / "old.sqlite3"
    old_schema = older_schema("outcome", "last_shot", "rack")
    record = join(a_table(), BOB)
    action = refereeing.bot_input(record.state, "picker")
    entry = InputEntry(shot_id="break-0001", seat=0, input=action, version=1, accepted_at=0.0)
    after, _ = played(record, entry, refereeing.referee(record.state, action))
    with sqlite3.connect(path) as db:
        db.executescript(old_schema)
        row = (after.id, after.version, "", 1, after.created, None, after.model_dump_json(), 0.0)
        db.execute("INSERT INTO tables VALUES (?, ?, ?, ?, ?, ?, ?, ?)", row)
    db.close()
    storage = await SqliteStorage.open(path)
    try:
        assert await storage.get_table(after.id) == after
    finally:
        await storage.close()
    storage = await SqliteStorage.open(path)  # read from the moved columns, not the cache
    try:
        assert await storage.get_table(after.id) == after
        assert await storage.update(bump(after))  # a write that keeps the last outcome
    finally:
        await storage.close()
    storage = await SqliteStorage.open(path)
    try:
        assert (await storage.get_table(after.id)).last_outcome == after.last_outcome
    finally:
        await storage.close()


#: What a server from before the played input's log in `resolve` added to `SCHEMA`: a column
#: the table's UPDATE set to the played input, and a trigger that logged it from there.
PLAYED_DOC_TRIGGER = """
CREATE TRIGGER tables_log_played AFTER UPDATE OF played_doc ON tables
WHEN NEW.played_doc IS NOT NULL
BEGIN
    INSERT OR REPLACE INTO inputs (table_id, shot_id, seq, doc, rack)
    VALUES (NEW.id, OLD.pending, NEW.version, NEW.played_doc, 1);
    UPDATE tables SET played_doc = NULL WHERE id = NEW.id;
END
"""


async def test_a_database_from_the_logging_trigger_loses_it_and_logs_each_input_once(
    tmp_path: Path,
) -> None:
    """A file whose tables logged their played inputs through a trigger: the trigger is
    dropped on open (its column stays, unused), an input played there is in the log once, and
    a refused resolve logs nothing."""
    path = tmp_path / "old.sqlite3"
    column = ",\n    last_shot TEXT"
    assert column in SCHEMA
    with sqlite3.connect(path) as db:
        db.executescript(SCHEMA.replace(column, ",\n    played_doc TEXT" + column))
        db.executescript(PLAYED_DOC_TRIGGER)
    db.close()
    storage = await SqliteStorage.open(path)
    try:
        record = join(a_table(), BOB)
        await storage.create_table(record)
        accepted = pending(record, "shot-0001")
        assert (await storage.accept(accepted)).result is AcceptResult.ACCEPTED
        after = bump(accepted, pending=None)
        assert not await storage.resolve(after, pending(record, "shot-0002").pending)
        assert await storage.inputs(record.id) == []
        assert await storage.resolve(after, accepted.pending)
        assert await storage.inputs(record.id) == [accepted.pending]
        assert await storage.find_input(record.id, "shot-0001") == accepted.pending
    finally:
        await storage.close()
    with sqlite3.connect(path) as db:
        triggers = db.execute("SELECT name FROM sqlite_master WHERE type = 'trigger'").fetchall()
    db.close()
    assert triggers == []


async def test_a_database_from_before_the_rack_column_keeps_its_racks_and_last_outcome(
    tmp_path: Path,
) -> None:
    """A file from before the inputs' `rack` and the tables' `last_shot` columns: its logged
    inputs are still found by rack, its last outcome (stored by value) reads back, and a shot
    played after the upgrade stores its outcome once, in the log, referred to by the table."""
    path = tmp_path / "old.sqlite3"
    record = join(a_table(), BOB)
    action = refereeing.bot_input(record.state, "picker")
    entry = InputEntry(shot_id="break-0001", seat=0, input=action, version=1, accepted_at=0.0)
    after, outcome = played(record, entry, refereeing.referee(record.state, action))
    logged = [pending(record, f"shot-{i:04d}", rack).pending for i, rack in enumerate((1, 2, 2))]
    with sqlite3.connect(path) as db:
        db.executescript(older_schema("last_shot", "rack"))
        doc = dump(after, exclude={"last_outcome"})
        row = (after.id, after.version, "", 1, after.created, None, doc, 0.0, dump(outcome))
        db.execute("INSERT INTO tables VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)", row)
        for seq, e in enumerate(logged):
            db.execute(
                "INSERT INTO inputs VALUES (?, ?, ?, ?)", (after.id, e.shot_id, seq, dump(e))
            )
    db.close()
    storage = await SqliteStorage.open(path)
    try:
        assert await storage.get_table(after.id) == after
        assert await storage.rack_inputs(after.id, 2) == logged[1:]
        accepted = pending(after, "shot-0009", 3)
        assert (await storage.accept(accepted)).result is AcceptResult.ACCEPTED
        nxt = accepted.pending.model_copy(
            update={"outcome": outcome.model_copy(update={"version": 9})}
        )
        again = bump(accepted, pending=None, last_outcome=nxt.outcome)
        assert await storage.resolve(again, nxt)
    finally:
        await storage.close()
    with sqlite3.connect(path) as db:
        assert db.execute("SELECT outcome, last_shot FROM tables").fetchall() == [
            (None, "shot-0009")
        ]
    db.close()
    storage = await SqliteStorage.open(path)
    try:
        assert (await storage.get_table(after.id)).last_outcome == nxt.outcome
        assert [e.shot_id for e in await storage.rack_inputs(after.id, 3)] == [nxt.shot_id]
    finally:
        await storage.close()


def a_result(table: str, at: float, winner: int = 0) -> MatchResult:
    return MatchResult(
        table=table,
        game="nineball",
        at=at,
        seats=(ADA, BOB),
        winner=winner,
        ended=Ending.RACKS,
        racks_won=(1, 0) if winner == 0 else (0, 1),
        before=(Rating(), Rating()),
        after=(Rating(rating=1600.0, games=1), Rating(rating=1400.0, games=1)),
        replays=("a" * 24,),
    )


async def test_a_result_is_kept_once_in_both_histories_newest_first(
    open_storage: OpenStorage,
) -> None:
    stores = [await open_storage() for _ in range(2)]
    first, second = a_result("1" * 20, 1000.0), a_result("2" * 20, 2000.0, winner=1)
    added = await asyncio.gather(*(s.add_result(first) for s in stores * 3))
    assert sorted(added) == [False] * 5 + [True]  # once, whoever stores it first
    assert await stores[1].add_result(second)
    for player in (ADA, BOB):
        assert await stores[0].results(player.id, 10) == [second, first]
        assert await stores[1].results(player.id, 1) == [second]
    assert await stores[0].results("p_nobody", 10) == []

"""The storage contract (server/storage/__init__.py), one suite run on SQLite and on Redis."""

from __future__ import annotations

import asyncio
import time

import pytest

from server import refereeing
from server.api_models import BreakEntry, Source
from server.ratings import Rating
from server.storage import AcceptResult, Storage
from server.tables import InputEntry, TableRecord, bump, join
from tests.service.conftest import ADA, BOB, OpenStorage, a_table


def pending(record: TableRecord, shot_id: str) -> TableRecord:
    entry = InputEntry(
        shot_id=shot_id,
        seat=0,
        input=refereeing.Choice(option="play_on"),
        version=record.version,
        accepted_at=time.time(),
    )
    return record.model_copy(update={"pending": entry})


async def test_players_and_name_claims(storage: Storage) -> None:
    await storage.add_player(ADA)
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
    from server.api_models import Status

    assert await storage.update(bump(public, status=Status.CANCELLED))
    assert await storage.listed_tables(10) == []


async def test_pairing_is_atomic_under_one_hundred_simultaneous_requests(
    open_storage: OpenStorage,
) -> None:
    stores = [await open_storage() for _ in range(4)]
    players = [f"p_{i:03d}" for i in range(100)]
    partners = await asyncio.gather(
        *(stores[i % 4].pair("nineball", player, f"{i:020x}") for i, player in enumerate(players))
    )
    pairs = [(p, q) for p, q in zip(players, partners, strict=True) if q is not None]
    seated = [who for pair in pairs for who in pair]
    assert len(pairs) == 50 and len(set(seated)) == 100  # nobody seated twice
    statuses = {p: await stores[0].quick_status(p) for p in players}
    for p, q in pairs:
        assert statuses[p].status == statuses[q].status == "paired"
        assert statuses[p].table == statuses[q].table  # a table of exactly these two
    assert len({statuses[p].table for p in players}) == 50


async def test_waiting_twice_queues_once_and_cancel_leaves_the_queue(storage: Storage) -> None:
    assert await storage.pair("snooker", "p_a", "a" * 20) is None
    assert await storage.pair("snooker", "p_a", "b" * 20) is None
    assert (await storage.quick_status("p_a")).status == "waiting"
    assert await storage.cancel_quick("p_a")
    assert not await storage.cancel_quick("p_a")
    assert await storage.pair("snooker", "p_b", "c" * 20) is None  # p_a is gone
    assert await storage.pair("nineball", "p_c", "d" * 20) is None  # another game
    assert await storage.pair("snooker", "p_c", "e" * 20) == "p_b"  # moved queues
    assert (await storage.quick_status("p_b")).table == "e" * 20
    assert (await storage.quick_status("p_z")).status == "idle"


async def test_heartbeats_are_kept_per_seat_beside_the_record(storage: Storage) -> None:
    record = a_table()
    await storage.create_table(record)
    assert await storage.heartbeats(record.id) == (None, None)
    await storage.heartbeat(record.id, 1, 1234.5)
    await storage.heartbeat(record.id, 1, 1235.25)
    assert await storage.heartbeats(record.id) == (None, 1235.25)
    assert await storage.update(join(record, BOB))  # the version did not move


async def test_a_match_is_rated_once(open_storage: OpenStorage) -> None:
    stores = [await open_storage() for _ in range(3)]
    new = {"p_ada": Rating(rating=1600, games=1), "p_bob": Rating(rating=1400, games=1)}
    applied = await asyncio.gather(*(s.rate("t" * 20, "snooker", new) for s in stores))
    assert sorted(applied) == [False, False, True]
    assert await stores[1].ratings("p_ada") == {"snooker": new["p_ada"]}
    assert not await stores[0].rate("t" * 20, "snooker", {"p_ada": Rating(rating=9)})
    assert (await stores[0].ratings("p_ada"))["snooker"].rating == 1600
    assert await stores[0].ratings("p_nobody") == {}


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

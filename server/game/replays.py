"""Replays: every rack (frame, game) played at every table, as a record anyone can replay.

A replay is the rack's game record (setup and inputs, `rules.record.GameRecord`) under an id of
96 random bits, so a private table's racks cannot be found by guessing; `/replay/{id}` is its
page in the web client and `GET /api/replays/{id}` its JSON. The record's players are the
table's seats and its setup names the rack's breaker, so it replays exactly as it was played.
A rack is archived when it ends, and so is the rack being played when a match ends off the
table (a resignation, a claim: server/game/actor.py, invariant 7); that record stops where the
rack stopped, its final result unfinished (no winner), and replays like any other.

The browser runs no physics, so `GET /api/replays/{id}/shots?page=N` answers the inputs'
outcomes (`ReplayShots`), computed by replaying the record in the background worker. Its
guarantees:

1. The shots are the record's replay: one per input, in order, each state the one the rules
   reach (`rules.record.replay`, which checks every digest), in the outcome message's form,
   `REPLAY_SHOTS_PAGE` inputs per page (a page's `next` names the following one), so one
   answer carries a bounded number of shots whatever the record's length.
2. No replay is computed on the event loop, and at most `MAX_REPLAYING` replays at once per
   process; a request for another one past that is refused (429 `rate_limited`), while one
   for a replay being computed waits for that computation.
3. Computing costs the asker: each client address may have at most `REPLAY_SECONDS` of
   worker time per minute spent on replays it asked for and that were not kept (429 with the
   wait once spent, before any work: server/game/budget.py); a kept page costs nothing.
4. Pages are kept in a least-recently-used cache of at most `CACHE_BYTES` bytes per process (a
   replay never changes, so a page never goes stale); a computation makes the page asked for
   and the next (`PAGES_AT_ONCE`), replaying the record up to them and holding only their
   motions, so that its memory is bounded by the pages asked for, not the record's length.
"""

from __future__ import annotations

import asyncio
import time
from collections import OrderedDict
from typing import TYPE_CHECKING

from server.game import refereeing
from server.game.budget import WorkBudget
from server.game.refereeing import GameRecord
from server.game.tables import TableRecord
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import REPLAY_SHOTS_PAGE, new_replay_id
from server.protocol.models import ReplayShot, ReplayShots, ReplayView
from server.storage import Storage

if TYPE_CHECKING:
    from server.game.workers import WorkerPool

#: Replays computed at once per process (a long frame keeps a worker busy for seconds), so that
#: replays cannot starve the matches of workers.
MAX_REPLAYING = 1
#: Bytes of pages kept per process (a nine-ball rack's is some 100 KB, a snooker frame's a
#: few MB).
CACHE_BYTES = 32 * 1024 * 1024
#: Pages one computation makes: the one asked for and the next. The record is replayed up to
#: them and only their shots' motions are held (before, every page of a replay was computed
#: at once: a 5,000-input record held 0.85 GB of a worker).
PAGES_AT_ONCE = 2
#: Seconds of worker time per minute one client address may spend on replays not kept.
REPLAY_SECONDS = 10.0


def replay_url(replay_id: str) -> str:
    return f"/replay/{replay_id}"


def rack_replay(record: TableRecord, game_record: GameRecord, best: tuple[int, int]) -> ReplayView:
    """The replay of a rack, finished or not (`game_record`: its inputs as the rules record
    them, from `refereeing.rack_archive`), with each seat's `best` break in it. A private
    table's replay does not name it: its breaks reach the leaderboard and the players'
    profiles, and before, anyone who followed one read the match being played and wrote to
    its chat."""
    replay_id = new_replay_id()
    view = ReplayView(
        id=replay_id,
        url=replay_url(replay_id),
        table=None if record.options.private else record.id,
        rack=record.rack,
        game=record.game,
        players=list(record.seats),
        best=best,
        record=game_record,
        created=time.time(),
    )
    return view


def record_refused(error: Exception) -> ServiceError:
    """The refusal of a record that does not replay (`refereeing.NOT_REPLAYED`: an illegal or
    differing input, another engine version, a shot the engine refuses or abandons)."""
    rule = refereeing.rule_code(error) if isinstance(error, refereeing.RuleError) else None
    return ServiceError(ErrorCode.ILLEGAL_INPUT, f"the record does not replay: {error}", rule)


def page_count(inputs: int) -> int:
    """The pages of a replay of `inputs` inputs (one, empty, for none)."""
    return max(1, -(-inputs // REPLAY_SHOTS_PAGE))


def shots_pages(
    replay_id: str, record: GameRecord, first: int = 0, count: int | None = None
) -> list[bytes]:
    """The `ReplayShots` JSON of pages `first` to `first + count - 1` of a replay (None: to
    its last; run in a worker process, which also encodes them)."""
    pages = page_count(len(record.inputs))
    last = pages if count is None else min(pages, first + count)
    window = range(first * REPLAY_SHOTS_PAGE, min(len(record.inputs), last * REPLAY_SHOTS_PAGE))
    shots = [
        ReplayShot(
            player=played.player,
            input=played.action,
            decision=played.refereed.decision,
            trajectory=played.refereed.trajectory,
            state=played.refereed.state,
        )
        for played in refereeing.replay_record(record, window)
    ]
    return [
        ReplayShots(
            id=replay_id,
            page=page,
            shots=shots[
                (page - first) * REPLAY_SHOTS_PAGE : (page - first + 1) * REPLAY_SHOTS_PAGE
            ],
            next=page + 1 if page + 1 < pages else None,
        )
        .model_dump_json()
        .encode()
        for page in range(first, last)
    ]


class ReplayShotsCache:
    """`await cache.shots(replay_id, page, asker)`: a page of the replay's `ReplayShots` JSON
    (see the guarantees above); ServiceError for an unknown replay or page, a busy process, an
    asker out of worker time or a record that does not replay."""

    def __init__(self, storage: Storage, pool: WorkerPool) -> None:
        self._storage = storage
        self._pool = pool
        self._kept: OrderedDict[tuple[str, int], bytes] = OrderedDict()
        self._kept_bytes = 0
        self._running: dict[str, asyncio.Task[dict[int, bytes]]] = {}
        self.budget = WorkBudget(REPLAY_SECONDS, "your replays")

    def _keep(self, replay_id: str, pages: dict[int, bytes]) -> None:
        """Keep the pages computed, the first asked the most recently used."""
        for page in sorted(pages, reverse=True):
            old = self._kept.pop((replay_id, page), None)  # kept before: counted once
            if old is not None:
                self._kept_bytes -= len(old)
            self._kept[(replay_id, page)] = pages[page]
            self._kept_bytes += len(pages[page])
        while self._kept_bytes > CACHE_BYTES:
            self._kept_bytes -= len(self._kept.popitem(last=False)[1])

    async def _compute(
        self, replay_id: str, record: GameRecord, asked: int, asker: str
    ) -> dict[int, bytes]:
        began = self.budget.clock()
        try:
            found = await self._pool.replay_shots(replay_id, record, asked, PAGES_AT_ONCE)
        except refereeing.NOT_REPLAYED as error:
            raise record_refused(error) from None
        finally:
            del self._running[replay_id]
            self.budget.charge(self.budget.clock() - began, asker)
        pages = dict(enumerate(found, asked))
        self._keep(replay_id, pages)
        return pages

    def _kept_page(self, replay_id: str, page: int) -> bytes | None:
        kept = self._kept.get((replay_id, page))
        if kept is not None:
            self._kept.move_to_end((replay_id, page))
        return kept

    async def shots(self, replay_id: str, page: int = 0, asker: str = "") -> bytes:
        for _ in range(2):  # a computation under way for other pages of it: then ours
            if replay_id not in self._running:
                await self._start(replay_id, page, asker)
            if (kept := self._kept_page(replay_id, page)) is not None:
                return kept
            # Shielded: a client that goes away does not cancel the others' computation.
            pages = await asyncio.shield(self._running[replay_id])
            if page in pages:
                return pages[page]
        raise ServiceError(ErrorCode.RATE_LIMITED, "this replay is being computed: retry")

    async def _start(self, replay_id: str, page: int, asker: str) -> None:
        """Start computing the replay's pages from `page` (unless kept, or started meanwhile):
        NOT_FOUND for an unknown replay or page, RATE_LIMITED past the limits."""
        if self._kept_page(replay_id, page) is not None:
            return
        replay = await self._storage.get_replay(replay_id)
        if replay is None:
            raise ServiceError(ErrorCode.NOT_FOUND, "no such replay")
        if page >= (count := page_count(len(replay.record.inputs))):
            raise ServiceError(ErrorCode.NOT_FOUND, f"the replay has {count} pages")
        if replay_id in self._running or self._kept_page(replay_id, page) is not None:
            return  # another request started it, or kept the page, meanwhile
        self.budget.check(asker)
        if len(self._running) >= MAX_REPLAYING:
            raise ServiceError(ErrorCode.RATE_LIMITED, "replays are being computed")
        computing = self._compute(replay_id, replay.record, page, asker)
        self._running[replay_id] = asyncio.ensure_future(computing)

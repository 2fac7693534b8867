"""The lobby: the `public-lobby` channel's batched snapshots, and quick-match pairing.

Lobby updates are batched as lichess batches its crowd updates: a change only marks the lobby
dirty, and at most once per `BATCH` seconds one snapshot (open tables, games in progress with
their spectators, players online) is published; the last value wins. So a thousand players
joining within a second cost two snapshots, not a million messages, and a client that
subscribes late gets the newest snapshot from the relay's buffer.

Pairing is atomic in storage (server/storage, invariant 11): the caller who finds a partner
creates the table for both; nobody is seated twice and no table gets a third player. A
request lapses `QUICK_LAPSE` seconds after the client last asked or polled (`GET /api/quick`
every `QUICK_POLL` s while waiting), so a client that died is never paired; and a quick match
plays with a `QUICK_SHOT_CLOCK` shot clock, so that no seat can hold it forever.
"""

from __future__ import annotations

import asyncio
import logging
import secrets
import time
from collections import Counter
from contextlib import AbstractAsyncContextManager

from server.game import tables
from server.game.background import running
from server.game.publisher import Publisher
from server.game.tables import TableRecord
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import LOBBY, QUICK_LAPSE, QUICK_SHOT_CLOCK, new_table_id, player_channel
from server.protocol.models import (
    LobbyMessage,
    PairedMessage,
    PlayerInfo,
    QuickStatus,
    Status,
    TableCreate,
    TableList,
    TableSummary,
)
from server.storage import Pairing, Storage

log = logging.getLogger(__name__)

#: Seconds between lobby snapshots while something changes.
BATCH = 0.7
#: Most tables a snapshot lists (newest first).
LISTED = 100
#: Open public tables (waiting for an opponent) one player may have at once, and show.
OPEN_PER_PLAYER = 3
#: Listed tables read to choose a snapshot's: enough that floods cannot hide the others'.
SCANNED = 4 * LISTED
#: Seconds after a pairing during which a missing table is created by whoever asks (the
#: request that paired them normally creates it within milliseconds); later it has expired.
PAIRING_KEPT = 60.0


def new_seed() -> int:
    return secrets.randbelow(2**62)


def creator(record: TableRecord) -> str | None:
    """The player waiting at an open table (None for a table that is not open)."""
    if record.status is not Status.OPEN:
        return None
    return next((seat.id for seat in record.seats if seat is not None), None)


def fair_share(listed: list[TableRecord]) -> list[TableRecord]:
    """The tables a snapshot shows: the newest first, at most `LISTED`, and of one player's
    open tables at most `OPEN_PER_PLAYER` (the newest), so that nobody's tables push the
    others' out of the lobby."""
    shown: list[TableRecord] = []
    open_tables: Counter[str] = Counter()
    for record in listed:
        if (who := creator(record)) is not None:
            open_tables[who] += 1
            if open_tables[who] > OPEN_PER_PLAYER:
                continue
        shown.append(record)
        if len(shown) == LISTED:
            break
    return shown


class Lobby:
    def __init__(self, storage: Storage, publisher: Publisher) -> None:
        self._storage = storage
        self._publisher = publisher
        self._dirty = asyncio.Event()

    def changed(self) -> None:
        """Something the lobby shows changed: a snapshot goes out within `BATCH` seconds."""
        self._dirty.set()

    def running(self) -> AbstractAsyncContextManager[None]:
        """Publish batched snapshots while the context is open."""
        return running(self._run)

    async def _run(self) -> None:
        while True:
            await self._dirty.wait()
            self._dirty.clear()
            try:
                await self._publisher.publish(LOBBY, await self.snapshot())
            except Exception:  # storage or relay trouble: the next change tries again
                log.exception("lobby snapshot failed")
            await asyncio.sleep(BATCH)

    async def spectators(self, record: TableRecord) -> int:
        """Readers of the table's channel who are not its seated players: connections, not
        people (subscribing needs no token, so one holder's sockets cannot be told from
        several people's; docs/protocol.md says so, and `--max-connections-per-address`
        bounds what one address adds)."""
        readers = await self._publisher.subscribers(record.channel)
        seated = sum(1 for p in record.seats if p is not None and not tables.is_bot(p))
        return max(0, readers - seated)

    async def tables(self) -> TableList:
        listed = fair_share(await self._storage.listed_tables(SCANNED))
        summaries: list[TableSummary] = [
            tables.summary(record, await self.spectators(record)) for record in listed
        ]
        return TableList(tables=summaries)

    async def snapshot(self) -> LobbyMessage:
        online = await self._storage.online_players(time.time())
        return LobbyMessage(tables=(await self.tables()).tables, players_online=online)

    async def check_open_tables(self, player: PlayerInfo) -> None:
        """TOO_MANY_TABLES if `player` already has `OPEN_PER_PLAYER` open public tables (among
        the newest `SCANNED` listed: an older one would not be shown anyway)."""
        listed = await self._storage.listed_tables(SCANNED)
        if sum(creator(record) == player.id for record in listed) >= OPEN_PER_PLAYER:
            raise ServiceError(
                ErrorCode.TOO_MANY_TABLES,
                f"you have {OPEN_PER_PLAYER} open tables: cancel one or wait for an opponent",
            )

    # ----- quick match ------------------------------------------------------------------
    async def quick(self, player: PlayerInfo, create: TableCreate) -> QuickStatus:
        """Pair `player` with the next player waiting for the same game, or queue it (until
        `QUICK_LAPSE` after its last request or poll)."""
        table_id, now = new_table_id(), time.time()
        partner_id = await self._storage.pair(
            create.game, player.id, table_id, now, now + QUICK_LAPSE
        )
        if partner_id is None:
            return QuickStatus(status="waiting")
        pairing = await self._storage.pairing(player.id)
        if pairing is None or pairing.table != table_id:
            raise ServiceError(ErrorCode.UNAVAILABLE, "the pairing was undone meanwhile")
        await self._seat(pairing)
        return QuickStatus(status="paired", table=table_id)

    async def quick_status(self, player: PlayerInfo) -> QuickStatus:
        """Where the player's quick match stands. A fresh pairing whose table is missing (the
        request that paired them failed, or its replica died, before creating it) gets its
        table from this request; an old one whose table is gone (expired) is over: idle."""
        pairing = await self._storage.pairing(player.id)
        if pairing is None:
            await self._storage.touch_quick(player.id, time.time() + QUICK_LAPSE)
            return await self._storage.quick_status(player.id)
        if await self._storage.get_table(pairing.table) is None:
            if time.time() - pairing.at > PAIRING_KEPT:
                return QuickStatus(status="idle")
            await self._seat(pairing)
        return QuickStatus(status="paired", table=pairing.table)

    async def _seat(self, pairing: Pairing) -> None:
        """Create the pairing's table, the first waiting player breaking, and tell both players
        (unless another request created it meanwhile: that one tells them)."""
        first, second = [await self._storage.get_player(who) for who in pairing.seats]
        if first is None or second is None:
            raise ServiceError(ErrorCode.UNAVAILABLE, "the paired player vanished")
        create = TableCreate(game=pairing.game, shot_clock=QUICK_SHOT_CLOCK)
        record = tables.join(tables.new_table(pairing.table, create, first, new_seed()), second)
        try:
            await self._storage.create_table(record)
        except ValueError:
            return
        for who in (first, second):
            await self._publisher.publish(
                player_channel(who.id), PairedMessage(table=pairing.table)
            )
        self.changed()

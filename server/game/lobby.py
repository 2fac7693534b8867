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
import contextlib
import logging
import secrets
import time
from collections import Counter
from collections.abc import Awaitable, Callable
from contextlib import AbstractAsyncContextManager

from server.game import tables
from server.game.background import running
from server.game.publisher import Publisher
from server.game.tables import TableRecord
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import LOBBY, QUICK_LAPSE, QUICK_SHOT_CLOCK, new_table_id, player_channel
from server.protocol.models import (
    Doing,
    GameChoice,
    LobbyMessage,
    Mode,
    OnlinePlayer,
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
#: Most tables a snapshot lists (newest first), and most players online.
LISTED = 100
#: Seconds between snapshots while nothing changes (who is online still does).
REFRESH = 10.0
#: Open public tables (waiting for an opponent) one player may have at once; and of the tables
#: a player sits at alone (open, practice, against the bot), how many the lobby shows.
OPEN_PER_PLAYER = 3
#: Listed tables read to choose a snapshot's: enough that floods cannot hide the others'.
SCANNED = 4 * LISTED
#: Seconds after a pairing during which a missing table is created by whoever asks (the
#: request that paired them normally creates it within milliseconds); later it has expired.
PAIRING_KEPT = 60.0


def new_seed() -> int:
    return secrets.randbelow(2**62)


def pool_of(choice: GameChoice) -> str:
    """The quick-match pool of a game and options: the game's name, then each option that is
    not its default as `~name=value` (so that players asking for the same are paired)."""
    defaults = GameChoice(game=choice.game)
    changed = [
        f"~{name}={value}"
        for name, value in choice.model_dump().items()
        if name != "game" and value != getattr(defaults, name)
    ]
    return choice.game + "".join(changed)


def choice_of(pool: str) -> GameChoice:
    """The game and options a pool stands for (`pool_of` read back)."""
    game, *options = pool.split("~")
    fields = dict(option.split("=", 1) for option in options)
    return GameChoice.model_validate({"game": game, **{k: int(v) for k, v in fields.items()}})


def creator(record: TableRecord) -> str | None:
    """The player waiting at an open table (None for a table that is not open)."""
    if record.status is not Status.OPEN:
        return None
    return next((seat.id for seat in record.seats if seat is not None), None)


def alone(record: TableRecord) -> str | None:
    """The one person at a table no other person sits at (open, practice, against the bot):
    whoever makes such a table makes it alone, as many as the create limit lets them."""
    seated = tables.people(record)
    return seated[0] if len(seated) == 1 else None


def fair_share(listed: list[TableRecord]) -> list[TableRecord]:
    """The tables a snapshot shows: the newest first, at most `LISTED`, and of the tables one
    player sits at alone (open, practice, against the bot) at most `OPEN_PER_PLAYER` (the
    newest), so that nobody's tables push the others' out of the lobby (before, 100 practice
    tables of one player did)."""
    shown: list[TableRecord] = []
    held: Counter[str] = Counter()
    for record in listed:
        if (who := alone(record)) is not None:
            held[who] += 1
            if held[who] > OPEN_PER_PLAYER:
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
        #: Each seat's last heartbeat of a table, as presence counts it (the service sets the
        #: matches' `MatchContext.seen`, which counts none older than the service's run).
        self.seen: Callable[[str], Awaitable[tables.Seen]] = storage.heartbeats

    def changed(self) -> None:
        """Something the lobby shows changed: a snapshot goes out within `BATCH` seconds."""
        self._dirty.set()

    def running(self) -> AbstractAsyncContextManager[None]:
        """Publish batched snapshots while the context is open."""
        return running(self._run)

    async def _run(self) -> None:
        while True:
            # Players come and go without a change to any table: a snapshot at least every
            # `REFRESH` seconds keeps the list of who is online current.
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(self._dirty.wait(), REFRESH)
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
        """The listed tables the lobby shows (`fair_share`), less those whose players have
        left (`tables.attended`)."""
        listed = fair_share(await self._storage.listed_tables(SCANNED))
        now = time.time()
        summaries: list[TableSummary] = [
            tables.summary(record, await self.spectators(record))
            for record in listed
            if tables.attended(record, await self.seen(record.id), now)
        ]
        return TableList(tables=summaries)

    async def snapshot(self) -> LobbyMessage:
        now = time.time()
        listed = (await self.tables()).tables
        return LobbyMessage(
            tables=listed,
            players_online=await self._storage.online_players(now),
            online=await self._online(listed, now),
        )

    async def _online(self, listed: list[TableSummary], now: float) -> list[OnlinePlayer]:
        """Who is online and what each is doing (at most `LISTED` of them)."""
        playing = {
            seat.id: summary.id
            for summary in listed
            if summary.status is Status.PLAYING
            for seat in summary.seats
            if seat is not None
        }
        online = []
        for player_id in await self._storage.online(now, LISTED):
            player = await self._storage.get_player(player_id)
            if player is None:
                continue
            if player_id in playing:
                doing, table = Doing.PLAYING, playing[player_id]
            elif (await self._storage.quick_status(player_id)).status == "waiting":
                doing, table = Doing.WAITING, None
            else:
                doing, table = Doing.ONLINE, None
            online.append(OnlinePlayer(player=player, doing=doing, table=table))
        return online

    async def listing(self, player: PlayerInfo, create: TableCreate) -> TableCreate:
        """The table `player` asks for, as the lobby will list it (among the newest `SCANNED`
        listed tables: an older one would not be shown anyway). A public open table past the
        player's `OPEN_PER_PLAYER` is refused (TOO_MANY_TABLES); a public practice or bot
        table past as many that the player sits at alone is made unlisted: nobody joins it,
        and its listing is all it would take from the others' (before, a few accounts' 400
        practice tables left the lobby no room for anyone's open table)."""
        if create.private:
            return create
        listed = await self._storage.listed_tables(SCANNED)
        if create.mode is Mode.MATCH:
            if sum(creator(record) == player.id for record in listed) >= OPEN_PER_PLAYER:
                raise ServiceError(
                    ErrorCode.TOO_MANY_TABLES,
                    f"you have {OPEN_PER_PLAYER} open tables: cancel one or wait for an opponent",
                )
            return create
        if sum(alone(record) == player.id for record in listed) >= OPEN_PER_PLAYER:
            return create.model_copy(update={"private": True})
        return create

    # ----- quick match ------------------------------------------------------------------
    async def quick(self, player: PlayerInfo, choice: GameChoice) -> QuickStatus:
        """Pair `player` with the next player waiting for the same game and options, or queue
        it (until `QUICK_LAPSE` after its last request or poll)."""
        table_id, now = new_table_id(), time.time()
        partner_id = await self._storage.pair(
            pool_of(choice), player.id, table_id, now, now + QUICK_LAPSE
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
        table from this request; an old one whose table is gone (expired) is over: idle. So a
        `paired` answer always names a table that exists."""
        await self._storage.touch_quick(player.id, time.time() + QUICK_LAPSE)  # if waiting
        pairing = await self._storage.pairing(player.id)
        if pairing is None:
            status = await self._storage.quick_status(player.id)
            if status.status != "paired":
                return status
            pairing = await self._storage.pairing(player.id)  # paired between the two reads
            assert pairing is not None
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
        choice = choice_of(pairing.pool)
        create = TableCreate(**choice.model_dump(), shot_clock=QUICK_SHOT_CLOCK)
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

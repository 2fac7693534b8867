"""The lobby channel, quick match over HTTP, and the bot's table."""

from __future__ import annotations

import asyncio
import time

import pytest
from aiohttp.test_utils import TestClient

from server.game import lobby, tables
from server.game.lobby import BATCH, OPEN_PER_PLAYER
from server.protocol.ids import new_table_id
from server.protocol.models import Mode, PlayerInfo, TableCreate
from tests.service.conftest import StartServer, Watcher, register, service_of, up_a_while, watch


async def test_one_hundred_simultaneous_quick_match_requests_seat_everyone_once(
    start_server: StartServer,
) -> None:
    server = await start_server(names_per_address=100)  # all 100 come from one address
    players = [await register(server, f"Q{i}") for i in range(100)]
    answers = await asyncio.gather(
        *(p.call("POST", "/api/quick", {"game": "eightball"}, 200) for p in players)
    )
    assert sum(a[1]["status"] == "paired" for a in answers) == 50  # the other half waited
    statuses = [(await p.call("GET", "/api/quick", expect=200))[1] for p in players]
    tables: dict[str, list[str]] = {}
    for player, status in zip(players, statuses, strict=True):
        assert status["status"] == "paired"
        tables.setdefault(status["table"], []).append(player.info["id"])
    assert len(tables) == 50
    for table_id, seated in tables.items():
        view = await (await server.get(f"/api/tables/{table_id}")).json()
        assert sorted(s["id"] for s in view["seats"]) == sorted(seated)  # two, these two
        assert view["status"] == "playing" and view["game"] == "eightball"


async def test_a_waiting_player_hears_of_its_pairing_and_can_cancel(server: TestClient) -> None:
    ada, bob, cy = [await register(server, name) for name in ("Ada", "Bob", "Cy")]
    inbox = await watch(server, f"player-{ada.info['id']}")
    _, first = await ada.call("POST", "/api/quick", {"game": "snooker"}, 200)
    assert first == {"status": "waiting", "table": None}
    _, second = await bob.call("POST", "/api/quick", {"game": "snooker"}, 200)
    assert second["status"] == "paired"
    assert await inbox.next() == {"kind": "paired", "protocol": 1, "table": second["table"]}
    await cy.call("POST", "/api/quick", {"game": "snooker"}, 200)
    _, cancelled = await cy.call("DELETE", "/api/quick", expect=200)
    assert cancelled["status"] == "cancelled"
    assert (await cy.call("GET", "/api/quick", expect=200))[1]["status"] == "idle"


async def test_a_pairing_left_without_its_table_gets_one_from_the_next_status_request(
    server: TestClient,
) -> None:
    """The replica that paired two players died before creating their table: the pairing is
    stored, the table is not. Either player's next status request creates it (once, with the
    first waiter breaking) and tells both; a pairing too old for that is over."""
    storage = service_of(server).storage
    ada, bob = [await register(server, name) for name in ("Ada", "Bob")]
    inbox = await watch(server, f"player-{ada.info['id']}")
    await ada.call("POST", "/api/quick", {"game": "nineball"}, 200)
    table_id = new_table_id()
    now = time.time()
    assert await storage.pair("nineball", bob.info["id"], table_id, now, now + 60) == ada.info["id"]
    assert await storage.get_table(table_id) is None

    statuses = await asyncio.gather(
        *(p.call("GET", "/api/quick", expect=200) for p in (bob, ada, bob))
    )
    assert {status["table"] for _, status in statuses} == {table_id}
    view = await (await server.get(f"/api/tables/{table_id}")).json()
    assert [seat["id"] for seat in view["seats"]] == [ada.info["id"], bob.info["id"]]
    assert view["status"] == "playing" and view["game"] == "nineball"
    assert await inbox.next() == {"kind": "paired", "protocol": 1, "table": table_id}


async def test_a_pairing_whose_table_is_gone_is_over(
    server: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Long after a pairing its table may have expired: the players are idle, not waiting,
    and no table comes back to life."""
    monkeypatch.setattr(lobby, "PAIRING_KEPT", 0.0)
    storage = service_of(server).storage
    cy, dee = [await register(server, name) for name in ("Cy", "Dee")]
    await cy.call("POST", "/api/quick", {"game": "snooker"}, 200)
    table_id = new_table_id()
    now = time.time()
    assert await storage.pair("snooker", dee.info["id"], table_id, now, now + 60) == cy.info["id"]
    for player in (cy, dee):
        assert (await player.call("GET", "/api/quick", expect=200))[1]["status"] == "idle"
    assert await storage.get_table(table_id) is None


async def snapshots_until_quiet(lobby: Watcher) -> list[dict]:
    """The lobby snapshots that arrive until none has for a few batch periods."""
    snapshots = []
    while True:
        try:
            snapshots.append(await asyncio.wait_for(lobby.next(), 3 * BATCH))
        except TimeoutError:
            return snapshots


async def test_the_lobby_batches_a_crowd_into_few_snapshots(server: TestClient) -> None:
    lobby = await watch(server, "public-lobby")
    started = time.monotonic()
    hosts = [await register(server, f"H{i}") for i in range(30)]
    created = await asyncio.gather(*(h.create("nineball") for h in hosts))
    elapsed = time.monotonic() - started
    snapshots = await snapshots_until_quiet(lobby)
    # 60 changes (30 arrivals, 30 tables): at most one snapshot per batch period.
    assert 1 <= len(snapshots) <= elapsed / BATCH + 2
    last = snapshots[-1]
    assert last["kind"] == "lobby" and last["players_online"] == 30
    assert {t["id"] for t in last["tables"]} == {c["id"] for c in created}
    # The channel keeps the newest snapshot alone: a lobby page opened now is sent that one.
    assert len(snapshots) > 1, "(the crowd made one snapshot: nothing to keep or drop)"
    kept = await service_of(server).publisher.relay.backend.info("public-lobby")
    assert kept is not None and kept.messages == 1
    latecomer = await watch(server, "public-lobby")
    assert (await latecomer.next())["players_online"] == 30
    private = await hosts[0].create("nineball", private=True)
    listed = await (await server.get("/api/tables")).json()
    assert private["id"] not in {t["id"] for t in listed["tables"]}


@pytest.mark.parametrize("bot", ["picker", "bot:1", None])
async def test_the_bot_answers_through_the_same_match_path(server: TestClient, bot) -> None:
    """The pickers and the searching bot (None: the default level, 3) play through the same
    path as a person: the foul gives them ball in hand, and their input is refereed."""
    ada = await register(server, "Ada")
    view = await ada.create("nineball", mode="bot", **({"bot": bot} if bot else {}))
    assert view["status"] == "playing" and view["seats"][1]["id"] == f"bot:{bot or 'bot:3'}"
    watcher = await watch(server, view["channel"])
    miss = {"strike": {"ball": "cue", "speed": 0.5, "heading": 270.0}}  # away from every ball
    status, _ = await ada.shoot(view["id"], view["version"], miss)
    assert status == 202
    mine = await watcher.next_kind("outcome")
    assert mine["seat"] == 0 and mine["next"]["seat"] == 1  # a foul: the bot's turn
    theirs = await watcher.next_kind("outcome")
    assert theirs["seat"] == 1 and theirs["shot_id"] == f"bot:{mine['version']:08d}"
    assert theirs["version"] == mine["version"] + 1 and theirs["trajectory"] is not None


async def test_a_thousand_players_arriving_cost_a_few_lobby_snapshots(server: TestClient) -> None:
    lobby = await watch(server, "public-lobby")
    service = service_of(server)
    started = time.monotonic()
    for i in range(1000):  # as the registration endpoint does, without 1000 HTTP round trips
        await service.identity.register(f"Crowd{i}")
        service.lobby.changed()
    elapsed = time.monotonic() - started
    snapshots = await snapshots_until_quiet(lobby)
    assert snapshots[-1]["players_online"] == 1000  # the last value wins
    assert len(snapshots) <= elapsed / BATCH + 2  # one per batch period at most


async def test_one_player_keeps_a_few_open_tables_and_the_lobby_shows_everyones(
    server: TestClient,
) -> None:
    """Before: one player's 100 new tables in 0.3 s pushed every other open table out of the
    lobby (the newest 100)."""
    ada, eve = await register(server, "Ada"), await register(server, "Eve")
    adas = await ada.create("nineball")
    for _ in range(OPEN_PER_PLAYER):
        await eve.create("nineball")
    status, refused = await eve.call("POST", "/api/tables", {"game": "nineball"})
    assert (status, refused["code"]) == (409, "too_many_tables")
    await eve.call("POST", "/api/tables", {"game": "nineball", "private": True}, 201)
    # A flood from storage itself (as many holders would make it): still one lobby for all.
    storage = service_of(server).storage
    flooder = PlayerInfo(id="p_" + "f" * 16, name="Flood")
    for _ in range(150):
        record = tables.new_table(new_table_id(), TableCreate(game="nineball"), flooder, 1)
        await storage.create_table(record)
    listed = (await (await server.get("/api/tables")).json())["tables"]
    ids = {table["id"] for table in listed}
    assert adas["id"] in ids
    by_flooder = [t for t in listed if any(s and s["id"] == flooder.id for s in t["seats"])]
    assert len(by_flooder) == OPEN_PER_PLAYER


@pytest.mark.parametrize("mode", ["practice", "bot"])
async def test_one_players_tables_alone_do_not_push_the_others_out_of_the_lobby(
    server: TestClient, mode: str
) -> None:
    """Before: one player's 100 public practice tables (or bot tables) left the lobby no room
    for anyone's open table; it shows a few of each player's tables alone, the newest."""
    ada = await register(server, "Ada")
    adas = await ada.create("nineball")
    storage = service_of(server).storage
    flooder = PlayerInfo(id="p_" + "e" * 16, name="Flood")
    made = []
    for _ in range(120):
        create = TableCreate(game="nineball", mode=Mode(mode))
        record = tables.new_table(new_table_id(), create, flooder, 1)
        await storage.create_table(record)
        made.append(record.id)
    listed = (await (await server.get("/api/tables")).json())["tables"]
    assert adas["id"] in {table["id"] for table in listed}
    by_flooder = [t["id"] for t in listed if any(s and s["id"] == flooder.id for s in t["seats"])]
    assert len(by_flooder) == OPEN_PER_PLAYER and set(by_flooder) <= set(made)


async def test_a_table_its_players_have_left_is_neither_shown_nor_joined(
    server: TestClient,
) -> None:
    """Before: an open table stayed in the lobby until it expired (7 days) after its player
    had gone, and whoever joined it sat at a match against nobody there, which they claimed
    as soon as the grace ran out: a rated win, a rated loss for the one who had left. So did a
    match both players had left, shown as being played."""
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    waiting = await ada.create("nineball")
    await ada.call("POST", f"/api/tables/{waiting['id']}/heartbeat", expect=200)
    left = await ada.create("nineball")
    storage = service_of(server).storage
    up_a_while(server)
    await storage.heartbeat(left["id"], 0, time.time() - 3600)  # Ada left an hour ago

    async def shown() -> set[str]:
        return {t["id"] for t in (await (await server.get("/api/tables")).json())["tables"]}

    assert waiting["id"] in await shown() and left["id"] not in await shown()
    status, body = await bob.call("POST", f"/api/tables/{left['id']}/join")
    assert (status, body["code"]) == (409, "wrong_phase")
    view = await (await server.get(f"/api/tables/{left['id']}")).json()
    assert view["status"] == "open" and view["presence"] == [False, True]  # a page says so
    await ada.call("POST", f"/api/tables/{left['id']}/heartbeat", expect=200)  # she is back
    assert left["id"] in await shown()
    _, joined = await bob.call("POST", f"/api/tables/{left['id']}/join", expect=200)
    assert joined["status"] == "playing" and left["id"] in await shown()
    for seat in (0, 1):  # both leave the match
        await storage.heartbeat(left["id"], seat, time.time() - 3600)
    assert left["id"] not in await shown()


@pytest.mark.parametrize("mode", ["practice", "bot"])
async def test_a_players_tables_alone_past_a_few_are_not_listed(
    server: TestClient, mode: str
) -> None:
    """Before, a few accounts' 400 practice tables filled the listed tables the lobby reads,
    and everyone's open tables dropped out of it."""
    ada = await register(server, "Ada")
    made = [await ada.create("nineball", mode=mode) for _ in range(OPEN_PER_PLAYER + 2)]
    assert [view["options"]["private"] for view in made] == [False] * OPEN_PER_PLAYER + [True] * 2
    listed = await service_of(server).storage.listed_tables(lobby.SCANNED)
    assert {record.id for record in listed} == {view["id"] for view in made[:OPEN_PER_PLAYER]}

"""Each way a match could once be stalled, over real sockets (the table actor's invariants,
server/game/actor.py): reserved input ids, a seat that never said it was here, a quick-match
request whose client died, a restart that lost the relay's buffers, a rematch race."""

from __future__ import annotations

import asyncio
import time
from typing import Any

import pytest
from aiohttp.test_utils import TestClient

from server.game import lobby, tables
from server.protocol.ids import BotName
from server.protocol.models import Mode, TableCreate
from server.relay.frames import GAP_TYPE
from server.storage import Storage
from tests.service.conftest import (
    Player,
    StartServer,
    register,
    service_of,
    watch,
)
from tests.service.test_match import picked, seated_match


async def run_out_the_clock(storage: Storage, table_id: str) -> int:
    """Store the table again with its deadline passed (not waiting the clock's seconds); the
    version the clock's input will be played at."""
    record = await storage.get_table(table_id)
    expired = record.model_copy(update={"version": record.version + 1, "deadline": time.time()})
    assert await storage.update(expired)
    return expired.version


async def test_a_client_cannot_take_the_id_of_the_clocks_input(server: TestClient) -> None:
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    table = await ada.create("nineball", shot_clock=30)
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    channel = await watch(server, view["channel"])
    # The server's own ids carry a `:`, which no client shot id may.
    status, refused = await ada.shoot(view["id"], view["version"], picked(view), "clock:00000003")
    assert status == 400 and refused["code"] == "bad_request"
    # The old form of the clock's id is an ordinary shot id now: played, and the clock still
    # plays for Bob once his deadline passes.
    version = view["version"]
    shot = await ada.shoot(view["id"], version, picked(view), f"clock-{version + 2:08d}")
    assert shot[0] == 202
    await channel.next_kind("outcome")
    clocked = await run_out_the_clock(service_of(server).storage, view["id"])
    outcome = await channel.next_kind("outcome")
    assert outcome["shot_id"] == f"clock:{clocked:08d}" and outcome["version"] == clocked + 1


async def test_a_bot_plays_whatever_ids_its_opponent_used(server: TestClient) -> None:
    ada = await register(server, "Ada")
    view = await ada.create("nineball", mode="bot", bot="picker")
    channel = await watch(server, view["channel"])
    await ada.shoot(view["id"], view["version"], picked(view), f"bot-{view['version'] + 1:08d}")
    mine = await channel.next_kind("outcome")
    if mine["next"] and mine["next"]["seat"] == 1:
        theirs = await channel.next_kind("outcome")
        assert theirs["seat"] == 1 and theirs["shot_id"] == f"bot:{mine['version']:08d}"


async def test_reads_start_no_bot_search_and_a_version_is_searched_once(
    server: TestClient,
) -> None:
    """A table whose bot is to act (as a restart leaves it): a hundred reads search nothing;
    the seated player's heartbeat starts the one search of that version."""
    service = service_of(server)
    searches: list[int] = []
    search = service.pool.bot_input

    async def counted(state: Any, bot: str) -> Any:
        searches.append(state.turn)
        return await search(state, bot)

    service.pool.bot_input = counted  # type: ignore[method-assign]
    ada = await register(server, "Ada")
    create = TableCreate(game="nineball", mode=Mode.BOT, bot=BotName.PICKER)
    player = tables.PlayerInfo.model_validate(ada.info)
    record = tables.new_table("b" * 20, create, player, seed=11)
    record = record.model_copy(update={"state": record.state.model_copy(update={"turn": 1})})
    await service.storage.create_table(record)
    reads = await asyncio.gather(*(server.get(f"/api/tables/{record.id}") for _ in range(100)))
    assert {response.status for response in reads} == {200}
    await service.matches.idle()
    assert searches == []
    channel = await watch(server, record.channel)
    for _ in range(3):
        await ada.call("POST", f"/api/tables/{record.id}/heartbeat", expect=200)
    outcome = await channel.next_kind("outcome")
    assert outcome["shot_id"] == f"bot:{record.version:08d}"
    bot_moves = 1
    while outcome["next"] is not None and outcome["next"]["seat"] == 1:  # the bot goes on
        outcome = await channel.next_kind("outcome")
        bot_moves += 1
    await service.matches.idle()
    assert len(searches) == bot_moves  # three heartbeats at the first version, one search


async def test_a_seat_that_never_sent_a_heartbeat_can_be_claimed(
    start_server: StartServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(tables, "PRESENCE_TIMEOUT", 0.3)
    server = await start_server(grace=0.3)
    ada, _, view = await seated_match(server)
    status, early = await ada.call("POST", f"/api/tables/{view['id']}/claim")
    assert status == 409 and early["code"] == "wrong_phase"  # Bob has just sat down
    await asyncio.sleep(0.8)
    _, presence = await ada.call("POST", f"/api/tables/{view['id']}/heartbeat", expect=200)
    assert presence["presence"] == [True, False] and presence["grace_until"][1] <= time.time()
    _, won = await ada.call("POST", f"/api/tables/{view['id']}/claim", expect=200)
    assert won["status"] == "over" and won["winner"] == 0


async def test_a_quick_match_request_lapses_when_its_client_stops_polling(
    server: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(lobby, "QUICK_LAPSE", 0.4)
    ghost, ada, bob = [await register(server, name) for name in ("Ghost", "Ada", "Bob")]
    assert (await ghost.call("POST", "/api/quick", {"game": "nineball"}, 200))[1]["status"] == (
        "waiting"
    )
    await ada.call("POST", "/api/quick", {"game": "eightball"}, 200)
    for _ in range(4):  # Ada keeps polling; the ghost has gone
        await asyncio.sleep(0.2)
        assert (await ada.call("GET", "/api/quick", expect=200))[1]["status"] == "waiting"
    _, mine = await bob.call("POST", "/api/quick", {"game": "nineball"}, 200)
    assert mine["status"] == "waiting"  # not paired with the ghost
    assert (await ghost.call("GET", "/api/quick", expect=200))[1]["status"] == "idle"
    _, paired = await bob.call("POST", "/api/quick", {"game": "eightball"}, 200)
    assert paired["status"] == "paired"  # Ada polled: still waiting, and paired now
    _, table = await bob.call("GET", f"/api/tables/{paired['table']}", expect=200)
    assert table["options"]["shot_clock"] == lobby.QUICK_SHOT_CLOCK > 0
    assert table["next"]["deadline"] is not None


async def test_after_a_restart_a_resuming_player_hears_of_what_it_missed(
    start_server: StartServer,
) -> None:
    """The embedded relay loses its buffers with the process: a player resuming its table
    feed with the last id it had gets a gap notice (and resyncs), not silence."""
    first = await start_server()
    ada, bob, view = await seated_match(first)
    channel = await watch(first, view["channel"])
    await ada.shoot(view["id"], view["version"], picked(view))
    outcome = await channel.next_kind("outcome")
    last_id = channel.last_id
    await first.close()
    second = await start_server()
    resumed = await watch(second, view["channel"], last_id)
    frame = await asyncio.wait_for(resumed.ws.receive(), 30)
    header = frame.data.partition("\n\n")[0] if isinstance(frame.data, str) else ""
    assert f"content-type: {GAP_TYPE}" in header
    bob_again = Player(http=second, info=bob.info, token=bob.token)
    _, fresh = await bob_again.call("GET", f"/api/tables/{view['id']}", expect=200)
    assert fresh["version"] == outcome["version"]


async def _finished_match(server: TestClient) -> tuple[Player, Player, dict[str, Any]]:
    ada, bob, view = await seated_match(server)
    _, over = await ada.call("POST", f"/api/tables/{view['id']}/resign", expect=200)
    assert over["status"] == "over"
    return ada, bob, over


async def _rematch_tables(storage: Storage) -> list[str]:
    return [r.id for r in await storage.listed_tables(100) if r.status.value == "playing"]


async def test_concurrent_rematch_accepts_make_one_table(server: TestClient) -> None:
    ada, bob, over = await _finished_match(server)
    path = f"/api/tables/{over['id']}/rematch"
    await bob.call("POST", path, expect=200)
    answers = await asyncio.gather(*(ada.call("POST", path) for _ in range(10)))
    assert {status for status, _ in answers} == {200}
    links = {view["rematch_table"] for _, view in answers}
    assert links == {tables.rematch_id(over["id"])}
    assert await _rematch_tables(service_of(server).storage) == list(links)
    _, rematch = await bob.call("GET", f"/api/tables/{links.pop()}", expect=200)
    assert [seat["id"] for seat in rematch["seats"]] == [bob.info["id"], ada.info["id"]]


async def test_concurrent_rematch_accepts_on_two_replicas_make_one_table(
    start_server: StartServer, redis_url: str
) -> None:
    replicas = [await start_server(redis_url=redis_url) for _ in range(2)]
    ada, bob, over = await _finished_match(replicas[0])
    path = f"/api/tables/{over['id']}/rematch"
    await bob.call("POST", path, expect=200)
    clients = [Player(http=r, info=ada.info, token=ada.token) for r in replicas]
    answers = await asyncio.gather(*(clients[n % 2].call("POST", path) for n in range(10)))
    assert {status for status, _ in answers} == {200}
    assert {view["rematch_table"] for _, view in answers} == {tables.rematch_id(over["id"])}
    assert len(await _rematch_tables(service_of(replicas[0]).storage)) == 1

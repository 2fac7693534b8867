"""Each way a match could once be stalled, over real sockets (the table actor's invariants,
server/game/actor.py): reserved input ids, a seat that never said it was here, a quick-match
request whose client died, a restart that lost the relay's buffers, a rematch race, a
command that failed and left its request waiting, a rack the workers failed to archive.

Each runs on one server with SQLite and on two replicas sharing a Redis (storage and relay),
the players' requests going to both replicas in turn.
"""

from __future__ import annotations

import asyncio
import sqlite3
import time
from pathlib import Path
from typing import Any

import pytest
from aiohttp.test_utils import TestClient

from server.game import lobby, tables
from server.protocol.feed import GAP_TYPE
from server.protocol.ids import QUICK_SHOT_CLOCK, BotName
from server.protocol.models import Mode, PlayerInfo, TableCreate
from server.storage import Storage, StorageError
from server.storage.sqlite import SqliteStorage
from tests.service.conftest import (
    Deploy,
    Player,
    StartServer,
    on,
    register,
    service_of,
    up_a_while,
    watch,
)
from tests.service.test_match import picked

#: How long a request may take to be answered here before the test calls it a stall.
ANSWER_S = 10.0
#: More shots than the pickers take to end a nine-ball rack.
MAX_SHOTS = 200


async def seated(replicas: list[TestClient], **options: Any) -> tuple[Player, Player, dict]:
    """Ada (seat 0, on the first replica) and Bob (seat 1, on the last) at a nine-ball match."""
    ada = await register(replicas[0], "Ada")
    bob = on(replicas, await register(replicas[0], "Bob"), -1)
    table = await ada.create("nineball", **options)
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    return ada, bob, view


async def run_out_the_clock(storage: Storage, table_id: str) -> int:
    """Store the table again with its deadline passed (not waiting the clock's seconds); the
    version the clock's input will be played at."""
    record = await storage.get_table(table_id)
    expired = record.model_copy(update={"version": record.version + 1, "deadline": time.time()})
    assert await storage.update(expired)
    return expired.version


async def test_a_client_cannot_take_the_id_of_the_clocks_input(deploy: Deploy) -> None:
    replicas = await deploy()
    ada, _, view = await seated(replicas, shot_clock=30)
    channel = await watch(replicas[-1], view["channel"])
    # The server's own ids carry a `:`, which no client shot id may.
    status, refused = await ada.shoot(view["id"], view["version"], picked(view), "clock:00000003")
    assert status == 400 and refused["code"] == "bad_request"
    # The old form of the clock's id is an ordinary shot id now: played, and the clock still
    # plays for Bob once his deadline passes.
    version = view["version"]
    shot = await ada.shoot(view["id"], version, picked(view), f"clock-{version + 2:08d}")
    assert shot[0] == 202
    await channel.next_kind("outcome")
    clocked = await run_out_the_clock(service_of(replicas[0]).storage, view["id"])
    outcome = await channel.next_kind("outcome")
    assert outcome["shot_id"] == f"clock:{clocked:08d}" and outcome["version"] == clocked + 1


async def test_a_bot_plays_whatever_ids_its_opponent_used(deploy: Deploy) -> None:
    replicas = await deploy()
    ada = on(replicas, await register(replicas[0], "Ada"), -1)
    view = await ada.create("nineball", mode="bot", bot="picker")
    channel = await watch(replicas[0], view["channel"])
    await ada.shoot(view["id"], view["version"], picked(view), f"bot-{view['version'] + 1:08d}")
    mine = await channel.next_kind("outcome")
    if mine["next"] and mine["next"]["seat"] == 1:
        theirs = await channel.next_kind("outcome")
        assert theirs["seat"] == 1 and theirs["shot_id"] == f"bot:{mine['version']:08d}"


async def test_reads_start_no_bot_search_and_a_version_is_searched_once(deploy: Deploy) -> None:
    """A table whose bot is to act (as a restart leaves it): a hundred reads on every replica
    search nothing; the seated player's heartbeats start the one search of that version."""
    replicas = await deploy()
    searches: list[int] = []
    for replica in replicas:
        pool = service_of(replica).bots
        search = pool.bot_input

        async def counted(state: Any, bot: str, search: Any = search) -> Any:
            searches.append(state.turn)
            return await search(state, bot)

        pool.bot_input = counted  # type: ignore[method-assign]
    ada = await register(replicas[0], "Ada")
    create = TableCreate(game="nineball", mode=Mode.BOT, bot=BotName.PICKER)
    record = tables.new_table("b" * 20, create, PlayerInfo(**ada.info), seed=11)
    record = record.model_copy(update={"state": record.state.model_copy(update={"turn": 1})})
    await service_of(replicas[0]).storage.create_table(record)
    path = f"/api/tables/{record.id}"
    reads = [replicas[n % len(replicas)].get(path) for n in range(100)]
    assert {response.status for response in await asyncio.gather(*reads)} == {200}
    for replica in replicas:
        await service_of(replica).matches.idle()
    assert searches == []
    channel = await watch(replicas[0], record.channel)
    for _ in range(3):  # on one replica: its actor searches once for the version
        await ada.call("POST", f"{path}/heartbeat", expect=200)
    outcome = await channel.next_kind("outcome")
    assert outcome["shot_id"] == f"bot:{record.version:08d}"
    bot_moves = 1
    while outcome["next"] is not None and outcome["next"]["seat"] == 1:  # the bot goes on
        outcome = await channel.next_kind("outcome")
        bot_moves += 1
    for replica in replicas:
        await service_of(replica).matches.idle()
    assert len(searches) == bot_moves  # three heartbeats at the first version, one search


async def test_a_seat_that_never_sent_a_heartbeat_can_be_claimed(
    deploy: Deploy, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(tables, "PRESENCE_TIMEOUT", 0.3)
    replicas = await deploy(grace=0.3)
    ada, _, view = await seated(replicas)
    status, early = await ada.call("POST", f"/api/tables/{view['id']}/claim")
    assert status == 409 and early["code"] == "wrong_phase"  # Bob has just sat down
    await asyncio.sleep(0.8)
    ada = on(replicas, ada, -1)
    _, presence = await ada.call("POST", f"/api/tables/{view['id']}/heartbeat", expect=200)
    assert presence["presence"] == [True, False] and presence["grace_until"][1] <= time.time()
    _, won = await ada.call("POST", f"/api/tables/{view['id']}/claim", expect=200)
    assert won["status"] == "over" and won["winner"] == 0


async def test_an_outage_is_nobodys_absence(
    start_server: StartServer, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Both players were here when the server went down for longer than the grace: after the
    restart neither may claim at once (before, the first one back claimed a rated win), and
    a player who does not come back is claimable as if they had left at the restart."""
    monkeypatch.setattr(tables, "PRESENCE_TIMEOUT", 0.3)
    first = await start_server(grace=0.3)
    ada, bob = await register(first, "Ada"), await register(first, "Bob")
    table = await ada.create("nineball")
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    for player in (ada, bob):
        await player.call("POST", f"/api/tables/{view['id']}/heartbeat", expect=200)
    await first.close()
    storage = await SqliteStorage.open(tmp_path / "game.sqlite")  # the outage: 1,000 s
    for seat in (0, 1):
        await storage.heartbeat(view["id"], seat, time.time() - 1000)
    await storage.close()
    _shift_service_run(tmp_path, -1000.0, -1000.0)
    second = await start_server(grace=0.3)
    ada = Player(http=second, info=ada.info, token=ada.token)
    status, early = await ada.call("POST", f"/api/tables/{view['id']}/claim")
    assert (status, early["code"]) == (409, "wrong_phase")
    _, shown = await ada.call("GET", f"/api/tables/{view['id']}", expect=200)
    assert shown["presence"] == [True, True]
    await asyncio.sleep(0.8)  # Bob does not come back
    await ada.call("POST", f"/api/tables/{view['id']}/heartbeat", expect=200)
    _, won = await ada.call("POST", f"/api/tables/{view['id']}/claim", expect=200)
    assert won["status"] == "over" and won["winner"] == 0


def _shift_service_run(tmp_path: Path, since: float, alive: float) -> None:
    """Move the stored run's start and its last word (storage invariant 16) by these seconds."""
    with sqlite3.connect(tmp_path / "game.sqlite") as db:
        db.execute("UPDATE service SET since = since + ?, alive = alive + ?", (since, alive))


async def test_a_replica_started_while_others_run_counts_absences_as_they_do(
    start_server: StartServer, tmp_path: Path
) -> None:
    """Bob left long ago; a replica started since (others running all along) lets Ada claim,
    as the others do: before, it counted nobody as gone from before its own start, showed Bob
    present and refused the claim for the grace and more."""
    first = await start_server()
    ada, bob = await register(first, "Ada"), await register(first, "Bob")
    table = await ada.create("nineball")
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    up_a_while(first)
    await service_of(first).storage.heartbeat(view["id"], 1, time.time() - 1000)
    _shift_service_run(tmp_path, -2000.0, 0.0)  # the service has run for a while
    second = await start_server()
    ada = Player(http=second, info=ada.info, token=ada.token)
    _, presence = await ada.call("POST", f"/api/tables/{view['id']}/heartbeat", expect=200)
    assert presence["presence"] == [True, False]
    _, won = await ada.call("POST", f"/api/tables/{view['id']}/claim", expect=200)
    assert won["status"] == "over" and won["winner"] == 0


async def test_a_quick_match_request_lapses_when_its_client_stops_polling(
    deploy: Deploy, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(lobby, "QUICK_LAPSE", 1.5)
    replicas = await deploy()
    ghost, ada, bob = [await register(replicas[0], name) for name in ("Ghost", "Ada", "Bob")]
    ada, bob = on(replicas, ada, -1), on(replicas, bob, -1)
    _, waiting = await ghost.call("POST", "/api/quick", {"game": "nineball"}, 200)
    assert waiting["status"] == "waiting"
    await ada.call("POST", "/api/quick", {"game": "eightball"}, 200)
    for n in range(8):  # Ada keeps polling, on both replicas; the ghost has gone
        await asyncio.sleep(0.25)
        _, status = await on(replicas, ada, n).call("GET", "/api/quick", expect=200)
        assert status["status"] == "waiting"
    _, mine = await bob.call("POST", "/api/quick", {"game": "nineball"}, 200)
    assert mine["status"] == "waiting"  # not paired with the ghost
    assert (await ghost.call("GET", "/api/quick", expect=200))[1]["status"] == "idle"
    _, paired = await bob.call("POST", "/api/quick", {"game": "eightball"}, 200)
    assert paired["status"] == "paired"  # Ada polled: still waiting, and paired now
    _, table = await bob.call("GET", f"/api/tables/{paired['table']}", expect=200)
    assert table["options"]["shot_clock"] == QUICK_SHOT_CLOCK > 0
    assert table["next"]["deadline"] is not None


async def test_after_a_restart_a_resuming_player_hears_of_what_it_missed(
    deploy: Deploy, storage_kind: str
) -> None:
    """A player resumes its table feed, with the last id it had, from a server started after
    the one it was reading: it gets what it missed or a gap notice (then resyncs), never
    silence. The embedded relay lost its buffers with the process: a gap notice; the Redis
    relay kept them: the message itself."""
    replicas = await deploy()
    ada, bob, view = await seated(replicas)
    channel = await watch(replicas[0], view["channel"])
    await ada.shoot(view["id"], view["version"], picked(view))
    await channel.next_kind("outcome")
    last_id = channel.last_id
    _, after = await on(replicas, bob, 0).call("POST", f"/api/tables/{view['id']}/resign", 200)
    for replica in replicas:
        await replica.close()
    restarted = await deploy()
    resumed = await watch(restarted[-1], view["channel"], last_id)
    frame = await asyncio.wait_for(resumed.ws.receive(), 30)
    header, _, data = frame.data.partition("\n\n")
    if storage_kind == "sqlite":
        assert f"content-type: {GAP_TYPE}" in header
    else:
        assert '"kind":"table"' in data and f'"version":{after["version"]}' in data
    _, fresh = await on(restarted, bob, 1).call("GET", f"/api/tables/{view['id']}", expect=200)
    assert fresh["version"] == after["version"] and fresh["status"] == "over"


async def _rematch_tables(storage: Storage) -> list[str]:
    return [r.id for r in await storage.listed_tables(100) if r.status.value == "playing"]


async def test_concurrent_rematch_accepts_make_one_table(deploy: Deploy) -> None:
    replicas = await deploy()
    ada, bob, view = await seated(replicas)
    _, over = await ada.call("POST", f"/api/tables/{view['id']}/resign", expect=200)
    path = f"/api/tables/{over['id']}/rematch"
    await bob.call("POST", path, expect=200)
    answers = await asyncio.gather(*(on(replicas, ada, n).call("POST", path) for n in range(10)))
    assert {status for status, _ in answers} == {200}
    links = {view["rematch_table"] for _, view in answers}
    assert links == {tables.rematch_id(over["id"])}
    assert await _rematch_tables(service_of(replicas[0]).storage) == list(links)
    _, rematch = await bob.call("GET", f"/api/tables/{links.pop()}", expect=200)
    assert [seat["id"] for seat in rematch["seats"]] == [bob.info["id"], ada.info["id"]]


async def test_a_bot_whose_search_fails_still_moves(deploy: Deploy) -> None:
    """A bug in the bot's search must not hold its opponent: the bot plays the clock's input."""
    replicas = await deploy()

    async def broken(state: Any, bot: str) -> Any:
        raise RuntimeError("the search fell over")

    for replica in replicas:
        service_of(replica).bots.bot_input = broken  # type: ignore[method-assign]
    ada = await register(replicas[0], "Ada")
    create = TableCreate(game="nineball", mode=Mode.BOT, bot=BotName.LEVEL_1)
    record = tables.new_table("c" * 20, create, PlayerInfo(**ada.info), seed=5)
    record = record.model_copy(update={"state": record.state.model_copy(update={"turn": 1})})
    await service_of(replicas[0]).storage.create_table(record)
    channel = await watch(replicas[0], record.channel)
    await ada.call("POST", f"/api/tables/{record.id}/heartbeat", expect=200)
    outcome = await channel.next_kind("outcome")
    assert outcome["shot_id"] == f"bot:{record.version:08d}" and outcome["seat"] == 1
    assert outcome["decision"]["fouls"] and outcome["next"]["seat"] == 0  # Ada's turn again


async def test_a_command_that_fails_is_answered_and_the_table_goes_on(deploy: Deploy) -> None:
    """A command that meets the storage down, or a bug, is answered (503 with its code, or
    500) rather than left waiting on the table's actor; the table takes the next command."""
    replicas = await deploy()
    ada, _, view = await seated(replicas)
    storage = service_of(replicas[0]).storage
    working = storage.heartbeat
    failures = iter([StorageError("the database went away"), RuntimeError("a bug")])

    async def failing(table_id: str, seat: int, now: float) -> None:
        raise next(failures)

    storage.heartbeat = failing  # type: ignore[method-assign]
    heartbeat = f"/api/tables/{view['id']}/heartbeat"
    answered = await asyncio.wait_for(ada.call("POST", heartbeat), ANSWER_S)
    assert answered[0] == 503 and answered[1]["code"] == "unavailable"
    response = await asyncio.wait_for(ada.http.post(heartbeat, headers=ada.auth), ANSWER_S)
    assert response.status == 500
    storage.heartbeat = working  # type: ignore[method-assign]
    await asyncio.wait_for(ada.call("POST", heartbeat, expect=200), ANSWER_S)
    shot = await ada.shoot(view["id"], view["version"], picked(view))
    assert shot[0] == 202


async def test_a_rack_the_workers_fail_to_archive_does_not_hold_its_table(
    deploy: Deploy,
) -> None:
    """A bug in archiving a rack (the shot workers' replay of it) costs that rack its replay,
    not the match: the rack's last shot is published and the match ends, and a resignation
    after a shot ends its match too."""
    replicas = await deploy()

    async def broken(setup: Any, played: Any) -> Any:
        raise RuntimeError("the archive fell over")

    for replica in replicas:
        service_of(replica).pool.rack_archive = broken  # type: ignore[method-assign]
    ada, bob, view = await seated(replicas)
    channel = await watch(replicas[0], view["channel"])
    players = {ada.info["id"]: ada, bob.info["id"]: bob}
    for _ in range(MAX_SHOTS):
        if view["status"] != "playing":
            break
        shooter = players[view["seats"][view["next"]["seat"]]["id"]]
        shot = await shooter.shoot(view["id"], view["version"], picked(view))
        assert shot[0] == 202
        outcome = await channel.next_kind("outcome")
        _, view = await ada.call("GET", f"/api/tables/{view['id']}", expect=200)
        assert view["version"] == outcome["version"]
    assert view["status"] == "over" and view["replays"] == []

    table = await ada.create("nineball")
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    assert (await ada.shoot(view["id"], view["version"], picked(view)))[0] == 202
    _, over = await bob.call("POST", f"/api/tables/{view['id']}/resign", expect=200)
    assert over["status"] == "over" and over["replays"] == []

"""Match life: restarts, abandoned inputs, presence and claims, resign, rematch, messages."""

from __future__ import annotations

import asyncio
import time

import pytest
from aiohttp.test_utils import TestClient

from server.game import actor, tables
from server.protocol.ids import PRESENCE_TIMEOUT
from server.protocol.models import Ending, PresenceMessage, Status
from tests.service.conftest import StartServer, register, service_of, up_a_while, watch
from tests.service.test_match import abandon_input, both_played, picked, seated_match


async def test_a_restarted_server_resumes_the_match_and_honours_old_tokens(
    start_server: StartServer,
) -> None:
    first = await start_server()
    ada, bob, view = await seated_match(first)
    status, _ = await ada.shoot(view["id"], view["version"], picked(view))
    assert status == 202
    await service_of(first).matches.idle()
    before = await (await first.get(f"/api/tables/{view['id']}")).json()
    await first.close()

    second = await start_server()
    after = await (await second.get(f"/api/tables/{view['id']}")).json()
    assert after == before
    ada.http = bob.http = second
    assert (await ada.call("GET", "/api/me", expect=200))[1] == ada.info
    player = ada if after["next"]["seat"] == 0 else bob
    status, ack = await player.shoot(view["id"], after["version"], picked(after))
    assert (status, ack["version"]) == (202, after["version"] + 1)


async def test_an_input_abandoned_by_a_dead_replica_is_played_after_the_lease(
    server: TestClient,
) -> None:
    ada, _, view = await seated_match(server)
    await abandon_input(service_of(server).storage, view, "orphan-0001")
    watcher = await watch(server, view["channel"])
    # A seated player's next command finishes it (a read would not: reads start no work).
    await ada.call("POST", f"/api/tables/{view['id']}/heartbeat", expect=200)
    outcome = await watcher.next_kind("outcome")
    assert (outcome["shot_id"], outcome["version"]) == ("orphan-0001", view["version"] + 1)
    status, again = await ada.shoot(view["id"], view["version"], picked(view), "orphan-0001")
    assert status == 200 and again["outcome"] == outcome


async def test_presence_claim_and_resign(server: TestClient) -> None:
    ada, bob, view = await seated_match(server)
    table = view["id"]
    watcher = await watch(server, view["channel"])
    _, presence = await ada.call("POST", f"/api/tables/{table}/heartbeat", expect=200)
    assert presence["presence"] == [True, True]
    assert (await watcher.next_kind("presence"))["presence"] == [True, True]
    storage = service_of(server).storage
    up_a_while(server)
    await storage.heartbeat(table, 1, time.time() - 1000)  # Bob left long ago
    _, presence = await ada.call("POST", f"/api/tables/{table}/heartbeat", expect=200)
    assert presence["presence"] == [True, False] and presence["grace_until"][1] < time.time()
    assert (await watcher.next_kind("presence"))["presence"] == [True, False]
    status, body = await bob.call("POST", f"/api/tables/{table}/claim")
    assert (status, body["code"]) == (409, "wrong_phase")  # Ada is here
    _, won = await ada.call("POST", f"/api/tables/{table}/claim", expect=200)
    assert (won["status"], won["winner"]) == ("over", 0)
    message = await watcher.next_kind("table")
    assert message["version"] == won["version"] and message["view"]["winner"] == 0
    status, body = await bob.call("POST", f"/api/tables/{table}/resign")
    assert (status, body["code"]) == (409, "wrong_phase")

    _, _, other = await seated_match(server, (ada, bob))
    _, resigned = await ada.call("POST", f"/api/tables/{other['id']}/resign", expect=200)
    assert (resigned["status"], resigned["winner"]) == ("over", 1)


async def test_the_grace_period_is_the_servers_setting(start_server: StartServer) -> None:
    server = await start_server(grace=30.0)
    ada, _, view = await seated_match(server)
    table = view["id"]
    gone = time.time() - 45  # Bob's last heartbeat: past 10 + 30 s, within the default 10 + 60
    up_a_while(server)
    await service_of(server).storage.heartbeat(table, 1, gone)
    _, presence = await ada.call("POST", f"/api/tables/{table}/heartbeat", expect=200)
    assert presence["presence"] == [True, False]
    assert presence["grace_until"][1] == pytest.approx(gone + PRESENCE_TIMEOUT + 30.0)
    _, won = await ada.call("POST", f"/api/tables/{table}/claim", expect=200)
    assert (won["status"], won["winner"]) == ("over", 0)


async def test_a_rematch_swaps_the_break_once_both_ask(server: TestClient) -> None:
    ada, bob, view = await seated_match(server)
    table = view["id"]
    status, body = await ada.call("POST", f"/api/tables/{table}/rematch")
    assert (status, body["code"]) == (409, "wrong_phase")  # not over yet
    await bob.call("POST", f"/api/tables/{table}/resign", expect=200)
    _, offered = await ada.call("POST", f"/api/tables/{table}/rematch", expect=200)
    assert offered["rematch"] == [True, False] and offered["rematch_table"] is None
    _, accepted = await bob.call("POST", f"/api/tables/{table}/rematch", expect=200)
    fresh = await (await server.get(f"/api/tables/{accepted['rematch_table']}")).json()
    assert [s["id"] for s in fresh["seats"]] == [bob.info["id"], ada.info["id"]]
    assert fresh["status"] == "playing" and fresh["next"]["seat"] == 0


async def test_a_rematch_offer_lapses(server: TestClient, monkeypatch: pytest.MonkeyPatch) -> None:
    """Before: an offer stood for as long as the table was kept, and accepting it a while after
    its player had gone seated that player at a rated match the other then claimed."""
    monkeypatch.setattr(tables, "REMATCH_LAPSE", 0.3)
    ada, bob, view = await seated_match(server)
    table = view["id"]
    await bob.call("POST", f"/api/tables/{table}/resign", expect=200)
    await ada.call("POST", f"/api/tables/{table}/rematch", expect=200)
    await asyncio.sleep(0.5)  # Ada's offer lapses
    _, late = await bob.call("POST", f"/api/tables/{table}/rematch", expect=200)
    assert late["rematch"] == [False, True] and late["rematch_table"] is None
    _, accepted = await ada.call("POST", f"/api/tables/{table}/rematch", expect=200)
    assert accepted["rematch"] == [True, True] and accepted["rematch_table"] is not None


async def test_quick_messages_are_a_fixed_set_and_rate_limited(server: TestClient) -> None:
    ada, _, view = await seated_match(server)
    eve = await register(server, "Eve")  # a spectator may talk too
    watcher = await watch(server, view["channel"])
    path = f"/api/tables/{view['id']}/messages"
    status, body = await ada.call("POST", path, {"message": "you are bad"})
    assert (status, body["code"]) == (400, "bad_request")
    await ada.call("POST", path, {"message": "good_shot"}, 201)
    status, body = await ada.call("POST", path, {"message": "good_shot"})
    assert (status, body["code"]) == (429, "rate_limited")
    await eve.call("POST", path, {"message": "hello"}, 201)
    first, second = await watcher.next_kind("chat"), await watcher.next_kind("chat")
    assert (first["from_name"], first["seat"], first["message"]) == ("Ada", 0, "good_shot")
    assert (second["from_name"], second["seat"]) == ("Eve", None)
    assert first["version"] == view["version"]  # messages do not move the version


async def test_the_shooters_aim_is_passed_on_throttled_and_only_the_shooters(
    server: TestClient,
) -> None:
    ada, bob, view = await seated_match(server)
    watcher = await watch(server, view["channel"])
    path = f"/api/tables/{view['id']}/aim"
    shooter, other = (ada, bob) if view["next"]["seat"] == 0 else (bob, ada)
    aim = {"heading": 91.5, "power": 0.4, "elevation": 0.0, "a": 0.1, "b": -0.2}
    status, body = await other.call("POST", path, aim)
    assert (status, body["code"]) == (409, "wrong_phase")  # not the player to act
    status, body = await shooter.call("POST", path, {**aim, "a": 0.9})
    assert (status, body["code"]) == (400, "bad_request")  # no wider than a shot
    await shooter.call("POST", path, {**aim, "place": [0.5, 0.4]}, 201)
    status, body = await shooter.call("POST", path, aim)
    assert (status, body["code"]) == (429, "rate_limited")  # not two within 200 ms
    shown = await watcher.next_kind("aim")
    assert shown["seat"] == view["next"]["seat"] and shown["heading"] == 91.5
    assert shown["place"] == [0.5, 0.4] and shown["version"] == view["version"]
    # Never played: the table has not moved.
    assert (await (await server.get(f"/api/tables/{view['id']}")).json())["version"] == view[
        "version"
    ]


async def test_names_are_unique_among_players_online(server: TestClient) -> None:
    await register(server, "Ada")
    response = await server.post("/api/players", json={"name": "ADA"})
    assert (response.status, (await response.json())["code"]) == (409, "name_taken")
    for bad in ("", " Ada", "<b>x</b>", "x" * 25, "a\nb"):
        response = await server.post("/api/players", json={"name": bad})
        assert response.status == 400, bad


async def test_a_decided_match_between_two_people_is_rated_once(server: TestClient) -> None:
    """Once both have played: before, two accounts farmed a rating by creating, joining and
    resigning (300 points in six loops)."""
    ada, bob, view = await seated_match(server)
    path = f"/api/players/{ada.info['id']}/ratings"
    await bob.call("POST", f"/api/tables/{view['id']}/resign", expect=200)  # before a shot
    _, _, view = await seated_match(server, (ada, bob))
    status, _ = await ada.shoot(view["id"], view["version"], picked(view))  # Ada breaks
    assert status == 202
    await service_of(server).matches.idle()
    await ada.call("POST", f"/api/tables/{view['id']}/resign", expect=200)  # Bob never shot
    await service_of(server).matches.idle()
    assert (await (await server.get(path)).json())["ratings"] == {}
    profile = await (await server.get(f"/api/players/{ada.info['id']}/profile")).json()
    assert profile["matches"] == []
    _, _, view = await seated_match(server, (ada, bob))
    view = await both_played(server, ada, bob, view)
    await bob.call("POST", f"/api/tables/{view['id']}/resign", expect=200)
    await service_of(server).matches.idle()
    won = (await (await server.get(path)).json())["ratings"]["nineball"]
    lost = await (await server.get(f"/api/players/{bob.info['id']}/ratings")).json()
    assert won["rating"] > 1500 > lost["ratings"]["nineball"]["rating"]
    assert won["games"] == 1 and won["provisional"]
    assert (await server.get("/api/players/p_0000000000000000/ratings")).status == 404


async def test_what_a_client_makes_the_server_store_is_rate_limited(server: TestClient) -> None:
    ada = await register(server, "Ada")
    # Private tables: how many public ones the lobby shows is bounded apart (test_lobby).
    practice = {"game": "nineball", "mode": "practice", "private": True}
    answers = [(await ada.call("POST", "/api/tables", practice))[0] for _ in range(25)]
    assert 20 <= answers.count(201) <= 21 and answers[-1] == 429  # a burst of 20, then 1/s


async def test_heartbeats_are_kept_while_a_dead_replicas_input_waits_out_its_lease(
    server: TestClient,
) -> None:
    """A heartbeat changes nothing of the table, so it is not queued behind the job that waits
    for a dead replica's input: before, every heartbeat waited up to the lease (15 s) unkept,
    and then the player was announced gone."""
    ada, _, view = await seated_match(server)
    storage = service_of(server).storage
    await abandon_input(storage, view, "orphan-0002", lease_left=3.0)
    watcher = await watch(server, view["channel"])
    path = f"/api/tables/{view['id']}/heartbeat"
    await ada.call("POST", path, expect=200)  # lets the table wait for the input (a job)
    _, beat = await ada.call("POST", path, expect=200)
    assert beat["version"] == view["version"]  # answered while the input still waits
    assert (await storage.heartbeats(view["id"]))[0] > time.time() - PRESENCE_TIMEOUT
    outcome = await watcher.next_kind("outcome")  # then played, once the lease is out
    assert (outcome["shot_id"], outcome["version"]) == ("orphan-0002", view["version"] + 1)


async def test_presence_is_announced_again_after_a_while(
    server: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each replica announces the presence changes it sees; another's wrong announcement (here
    published straight on the channel, as by a replica that then died) is put right at the
    next heartbeat after PRESENCE_REPEAT, not left standing for good."""
    monkeypatch.setattr(actor, "PRESENCE_REPEAT", 0.3)
    ada, bob, view = await seated_match(server)
    path = f"/api/tables/{view['id']}/heartbeat"
    watcher = await watch(server, view["channel"])
    for player in (ada, bob):
        await player.call("POST", path, expect=200)
    assert (await watcher.next_kind("presence"))["presence"] == [True, True]  # said once
    wrong = PresenceMessage(
        version=view["version"], presence=(True, False), grace_until=(None, 1.0)
    )
    await service_of(server).publisher.publish(view["channel"], wrong)
    assert (await watcher.next_kind("presence"))["presence"] == [True, False]
    await asyncio.sleep(0.4)
    await ada.call("POST", path, expect=200)
    assert (await watcher.next_kind("presence"))["presence"] == [True, True]


async def test_a_match_its_racks_decided_is_rated_though_the_loser_never_shot(
    server: TestClient,
) -> None:
    """Only a match ended off the table before both played goes unrated: a sweep, the loser
    never at the table, counts."""
    ada, _, view = await seated_match(server)
    storage = service_of(server).storage
    record = await storage.get_table(view["id"])
    won = record.model_copy(
        update={
            "version": record.version + 1,
            "status": Status.OVER,
            "winner": 0,
            "ended": Ending.RACKS,
            "racks_won": (record.options.race_to, 0),
        }
    )
    actor_ = service_of(server).matches.owner(view["id"])
    await actor_._status_changed(record, won)  # as the last rack's outcome stores it
    ratings = await storage.ratings(ada.info["id"])
    assert ratings["nineball"].games == 1

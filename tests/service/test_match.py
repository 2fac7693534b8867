"""Matches over real sockets: intents over HTTP, outcomes on the relay, the referee's checks."""

from __future__ import annotations

import asyncio
import json
import time
from typing import Any

from aiohttp.test_utils import TestClient

from server.client.api_client import from_json
from server.game import refereeing
from server.game.actor import LEASE
from server.game.commands import Play
from server.game.tables import InputEntry
from server.protocol.models import Intent, PlayerInfo
from server.storage import Storage
from tests.service.conftest import WAIT_S, Player, register, service_of, watch


def picked(view_or_outcome: dict[str, Any]) -> dict[str, Any]:
    """The shot pickers' input for a published state (a client choosing its shot)."""
    state = from_json(refereeing.State, view_or_outcome["state"])
    return refereeing.bot_input(state, "picker").model_dump(mode="json")


async def abandon_input(
    storage: Storage, view: dict[str, Any], shot_id: str, seat: int = 0, lease_left: float = -1.0
) -> None:
    """Store an accepted, unplayed input of `seat` as a replica that died left it, its lease
    out in `lease_left` seconds (by default, out a second ago)."""
    record = await storage.get_table(view["id"])
    entry = InputEntry(
        shot_id=shot_id,
        seat=seat,
        input=from_json(refereeing.Shot, picked(view)),
        version=record.version,
        accepted_at=time.time() - LEASE + lease_left,
        replica="a-replica-that-died",
    )
    await storage.accept(record.model_copy(update={"pending": entry}))


async def seated_match(
    server: TestClient, players: tuple[Player, Player] | None = None
) -> tuple[Player, Player, dict[str, Any]]:
    """A nine-ball match between Ada (seat 0) and Bob (seat 1), registered if not given."""
    ada, bob = players or (await register(server, "Ada"), await register(server, "Bob"))
    table = await ada.create("nineball")
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    return ada, bob, view


async def both_played(server: TestClient, ada: Player, bob: Player, view: dict[str, Any]) -> dict:
    """Ada's and Bob's first shots of a match seated by `seated_match` (each the clock's
    dead-slow foul, which hands the table over), so that its result counts; the view after."""
    for player in (ada, bob):
        state = from_json(refereeing.State, view["state"])
        foul = refereeing.timeout_input(state).model_dump(mode="json")
        status, body = await player.shoot(view["id"], view["version"], foul)
        assert status == 202, body
        played = body["version"]
        for _ in range(int(WAIT_S / 0.05)):  # played by whichever replica took it
            view = await (await server.get(f"/api/tables/{view['id']}")).json()
            if view["version"] >= played:
                break
            await asyncio.sleep(0.05)
        assert view["version"] >= played
    return view


async def test_a_shot_is_acknowledged_then_published_once_with_its_trajectory(
    server: TestClient,
) -> None:
    ada, _, view = await seated_match(server)
    assert view["status"] == "playing" and view["next"]["seat"] == 0
    players, spectator = await watch(server, view["channel"]), await watch(server, view["channel"])
    status, ack = await ada.shoot(view["id"], view["version"], picked(view), "break-shot-1")
    assert (status, ack) == (202, {"status": "accepted", "version": view["version"] + 1})
    seen = [await w.next_kind("outcome") for w in (players, spectator)]
    assert seen[0] == seen[1]  # spectators see exactly what the players see
    outcome = seen[0]
    assert outcome["version"] == view["version"] + 1 and outcome["seat"] == 0
    assert outcome["decision"]["player"] == 0
    cue = outcome["trajectory"]["balls"]["cue"]
    assert all(len(segment) == 14 for segment in cue)
    assert "sliding" in [segment[1] for segment in cue]
    assert cue[0][2:4] == view["state"]["balls"]["cue"]  # it starts where the cue ball was
    assert outcome["next"]["seat"] == outcome["state"]["turn"]
    fresh = await (await server.get(f"/api/tables/{view['id']}")).json()
    assert fresh["version"] == outcome["version"]
    assert fresh["last_outcome"] == {**outcome, "trajectory": None}  # a view carries no motion

    status, duplicate = await ada.shoot(view["id"], view["version"], picked(view), "break-shot-1")
    assert status == 200 and duplicate["status"] == "duplicate"
    assert duplicate["outcome"] == outcome  # answered with its first outcome, not replayed
    replayed = await (await server.get(f"/api/tables/{view['id']}")).json()
    assert replayed["version"] == fresh["version"]


async def test_only_its_sender_hears_a_shot_id_played_before(server: TestClient) -> None:
    """A shot id is answered with its first outcome to the seat that sent it alone: a stranger
    resending it is refused as a stranger, and the other seat's input under it is refused
    without being played."""
    ada, bob, view = await seated_match(server)
    table = view["id"]
    ada_watch = await watch(server, view["channel"])
    foul = refereeing.timeout_input(from_json(refereeing.State, view["state"]))  # Bob to act
    await ada.shoot(table, view["version"], foul.model_dump(mode="json"), "ada-shot-01")
    outcome = await ada_watch.next_kind("outcome")
    assert outcome["next"]["seat"] == 1
    eve = await register(server, "Eve")
    status, body = await eve.shoot(table, outcome["version"], picked(outcome), "ada-shot-01")
    assert (status, body["code"]) == (403, "forbidden")
    status, body = await bob.shoot(table, view["version"], picked(view), "ada-shot-01")
    assert (status, body["code"]) == (409, "stale_version")
    status, body = await bob.shoot(table, outcome["version"], picked(outcome), "ada-shot-01")
    assert (status, body["code"]) == (409, "duplicate")
    status, body = await ada.shoot(table, view["version"], picked(view), "ada-shot-01")
    assert status == 200 and body["outcome"] == outcome
    after = await (await server.get(f"/api/tables/{table}")).json()
    assert after["version"] == outcome["version"]


async def test_out_of_turn_stale_and_foreign_intents_are_refused_and_change_nothing(
    server: TestClient,
) -> None:
    ada, bob, view = await seated_match(server)
    table, version = view["id"], view["version"]
    status, body = await bob.shoot(table, version, picked(view))
    assert (status, body["code"]) == (409, "not_your_turn")
    status, body = await ada.shoot(table, version - 1, picked(view))
    assert (status, body["code"]) == (409, "stale_version")
    eve = await register(server, "Eve")
    status, body = await eve.shoot(table, version, picked(view))
    assert (status, body["code"]) == (403, "forbidden")
    status, body = await ada.shoot(table, version, {"option": "play_on"})
    assert (status, body["code"]) == (409, "wrong_phase")
    wrong_ball = picked(view)
    wrong_ball["strike"]["ball"] = "9"
    status, body = await ada.shoot(table, version, wrong_ball)
    assert (status, body["code"]) == (422, "illegal_input")
    assert view["next"]["ball_in_hand"] == "kitchen"
    placed = picked(view) | {"place": [0.5, 2.0]}
    status, body = await ada.shoot(table, version, placed)
    assert (status, body["code"]) == (422, "illegal_input")  # beyond the head string
    after = await (await server.get(f"/api/tables/{table}")).json()
    assert after["version"] == version and after["state"] == view["state"]


async def test_bad_bodies_get_json_errors_with_codes(server: TestClient) -> None:
    ada, _, view = await seated_match(server)
    path = f"/api/tables/{view['id']}/intents"
    shot = {"version": view["version"], "shot_id": "x" * 10, "input": picked(view)}
    # A number past the rules' bounds is malformed (400) where the bound is a field's range and
    # illegal (422) where a rule model checks it: the rules decide which; both change nothing.
    too_fast = json.dumps({**shot, "input": {"strike": {"ball": "cue", "speed": 99, "heading": 0}}})
    response = await server.post(
        path, data=too_fast, headers={**ada.auth, "Content-Type": "application/json"}
    )
    assert (await response.json())["code"] in ("bad_request", "illegal_input")
    cases = [
        (json.dumps(shot).replace('"speed": ', '"speed": NaN, "x": '), 400, "bad_request"),
        (json.dumps({**shot, "shot_id": "short"}), 400, "bad_request"),
        (json.dumps({**shot, "extra": 1}), 400, "bad_request"),
        ("[" * 100_000 + "]" * 100_000, 413, "body_too_large"),
        ("[" * 5000 + "]" * 5000, 400, "bad_request"),
        ("{not json", 400, "bad_request"),
        # A key twice is refused, not read as its last value (the version 0 would be stale).
        (json.dumps(shot)[:-1] + ', "version": 0}', 400, "bad_request"),
        (json.dumps(shot).replace('"speed": ', '"speed": 1.0, "speed": '), 400, "bad_request"),
    ]  # fmt: skip
    for body, status, code in cases:
        response = await server.post(
            path, data=body, headers={**ada.auth, "Content-Type": "application/json"}
        )
        assert (response.status, (await response.json())["code"]) == (status, code), body[:80]
    response = await server.post(path, data="x", headers={**ada.auth, "Content-Type": "text/plain"})
    assert response.status == 415
    forged = ada.token[:-2] + ("AA" if not ada.token.endswith("AA") else "BB")
    response = await server.post(path, json=shot, headers={"Authorization": f"Bearer {forged}"})
    assert (response.status, (await response.json())["code"]) == (401, "unauthorized")
    assert (await (await server.get(f"/api/tables/{view['id']}")).json())["version"] == view[
        "version"
    ]


async def test_a_client_cannot_publish_on_a_table_channel(server: TestClient) -> None:
    ada, _, view = await seated_match(server)
    forged = {"kind": "outcome", "version": view["version"] + 1}
    response = await server.post(f"/pub/{view['channel']}", json=forged, headers=ada.auth)
    assert response.status == 403


async def test_a_practice_table_plays_every_shot_from_seat_zero(server: TestClient) -> None:
    ada = await register(server, "Ada")
    view = await ada.create("nineball", mode="practice")
    watcher = await watch(server, view["channel"])
    for _ in range(4):
        status, ack = await ada.shoot(view["id"], view["version"], picked(view))
        assert status == 202, ack
        outcome = await watcher.next_kind("outcome")
        assert outcome["version"] == ack["version"] and outcome["seat"] == 0
        view = await (await server.get(f"/api/tables/{view['id']}")).json()
        assert view["next"]["seat"] == 0


async def test_every_game_plays_through_the_same_path(server: TestClient) -> None:
    ada = await register(server, "Ada")
    for game in ("eightball", "snooker", "three_cushion"):
        view = await ada.create(game, mode="practice")
        watcher = await watch(server, view["channel"])
        for _ in range(3):
            status, ack = await ada.shoot(view["id"], view["version"], picked(view))
            assert status == 202, ack
            outcome = await watcher.next_kind("outcome")
            assert outcome["version"] == ack["version"] and outcome["void"] is None, game
            assert outcome["state"]["game"] == game
            view = await (await server.get(f"/api/tables/{view['id']}")).json()


async def test_spectators_are_the_readers_who_are_not_seated(server: TestClient) -> None:
    _, _, view = await seated_match(server)
    watchers = [await watch(server, view["channel"]) for _ in range(3)]
    for _ in range(100):
        fresh = await (await server.get(f"/api/tables/{view['id']}")).json()
        if fresh["spectators"] == 1:  # three readers, two of them count as the players
            break
        await asyncio.sleep(0.02)
    assert fresh["spectators"] == 1 and len(watchers) == 3


async def test_an_intent_whose_client_left_before_its_answer_is_still_played(
    server: TestClient,
) -> None:
    """A client that disconnects cancels the request's wait for its answer; the input is
    stored by then, and is played and published at once all the same (not left pending
    until someone next touches the table)."""
    ada, _, view = await seated_match(server)
    watcher = await watch(server, view["channel"])
    intent = from_json(Intent, {"version": view["version"], "shot_id": "gone-before-its-answer",
                                "input": picked(view)})  # fmt: skip
    owner = service_of(server).matches.owner(view["id"])
    request = asyncio.ensure_future(owner.ask(Play(from_json(PlayerInfo, ada.info), intent)))
    await asyncio.sleep(0)  # the job is queued; its request waits for the answer
    request.cancel()
    outcome = await watcher.next_kind("outcome")
    assert outcome["shot_id"] == "gone-before-its-answer"
    assert outcome["version"] == view["version"] + 1

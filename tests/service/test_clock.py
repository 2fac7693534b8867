"""The shot clock: set by every change, ruled by the server through the ordinary match path."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from aiohttp.test_utils import TestClient

from server.client.api_client import from_json
from server.game import clock, refereeing
from server.game.commands import ClockExpiry
from server.protocol.ids import TURN_LIMIT
from server.storage.sqlite import SqliteStorage
from tests.service.conftest import StartServer, register, service_of, up_a_while, watch


async def test_a_clock_that_runs_out_is_a_foul_played_by_the_server(server: TestClient) -> None:
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    table = await ada.create("nineball", shot_clock=30)
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    assert view["next"]["deadline"] > time.time() + 25
    storage = service_of(server).storage
    record = await storage.get_table(view["id"])
    # Let the clock run out without waiting 30 s: store the same table with a past deadline.
    expired = record.model_copy(update={"version": record.version + 1, "deadline": time.time()})
    assert await storage.update(expired)
    watcher = await watch(server, view["channel"])
    outcome = await watcher.next_kind("outcome")
    assert outcome["shot_id"] == f"clock:{expired.version:08d}" and outcome["seat"] == 0
    assert outcome["decision"]["fouls"] and outcome["next"]["seat"] == 1
    assert outcome["next"]["ball_in_hand"] == "anywhere"
    assert outcome["next"]["deadline"] > time.time() + 25  # Bob's clock started


async def test_a_table_everyone_has_left_is_not_played_on(server: TestClient) -> None:
    """Before: a clocked match both players had left played a timeout every clock period, for
    ever (each stored, 3.6 KB); its clock now waits, and acts as soon as a player is back."""
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    table = await ada.create("three_cushion", shot_clock=30)
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    service = service_of(server)
    up_a_while(server)
    storage = service.storage
    for seat in (0, 1):  # both last seen long ago: gone
        await storage.heartbeat(view["id"], seat, time.time() - 1000)
    record = await storage.get_table(view["id"])
    expired = record.model_copy(update={"version": record.version + 1, "deadline": time.time()})
    assert await storage.update(expired)
    service.matches.owner(view["id"]).tell(ClockExpiry())
    await service.matches.idle()
    assert (await storage.get_table(view["id"])).version == expired.version
    watcher = await watch(server, view["channel"])
    await ada.call("POST", f"/api/tables/{view['id']}/heartbeat", expect=200)  # Ada is back
    outcome = await watcher.next_kind("outcome")
    assert outcome["shot_id"] == f"clock:{expired.version:08d}"


async def test_a_table_whose_clock_input_fails_does_not_hold_the_others_clocks(
    server: TestClient, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The clock looks at the oldest deadlines first; a table whose timeout input fails (a bug)
    stays due, and before, as many of those as the clock looks at stopped every other clock."""
    monkeypatch.setattr(clock, "BATCH", 1)
    made = refereeing.timeout_input

    def failing(state: refereeing.State) -> refereeing.PlayerInput:
        if state.game == "eightball":
            raise RuntimeError("a bug in the timeout input")
        return made(state)

    monkeypatch.setattr(refereeing, "timeout_input", failing)
    storage = service_of(server).storage
    views = []
    for game, overdue in (("eightball", 60), ("nineball", 30)):  # the failing one is oldest
        ada, bob = await register(server, f"Ada{game}"), await register(server, f"Bob{game}")
        table = await ada.create(game, shot_clock=30)
        _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
        record = await storage.get_table(view["id"])
        expired = record.model_copy(
            update={"version": record.version + 1, "deadline": time.time() - overdue}
        )
        watcher = await watch(server, view["channel"])
        assert await storage.update(expired)
        views.append((expired, watcher))
    (stuck, _), (expired, watcher) = views
    outcome = await watcher.next_kind("outcome")
    assert outcome["shot_id"] == f"clock:{expired.version:08d}"
    assert (await storage.get_table(stuck.id)).version == stuck.version


def test_the_timeout_input_hits_nothing_in_every_game_and_places_a_ball_in_hand() -> None:
    for game in ("nineball", "eightball", "snooker", "three_cushion"):
        state = refereeing.new_rack(game, 3, 0)
        action = refereeing.timeout_input(state)
        refereeing.check(state, action)
        result = refereeing.referee(state, action)
        touched = [e for e in result.trajectory.events if e.type == "ball_ball"]
        assert touched == [] and result.state.turn == 1, game
    in_hand = from_json(
        refereeing.State,
        refereeing.new_rack("nineball", 3, 0).model_dump()
        | {"ball_in_hand": "anywhere", "balls": {"1": (0.6, 1.5), "9": (0.6, 1.6)}},
    )
    action = refereeing.timeout_input(in_hand)
    assert action.place is not None
    refereeing.check(in_hand, action)


async def test_a_match_without_a_shot_clock_has_a_turn_limit(server: TestClient) -> None:
    """Before: at a match with no shot clock, a player who was there but never shot (or never
    chose) held it for ever, the opponent's one way out a rated resignation. Practice and bot
    tables, where nobody else waits, have no limit."""
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    table = await ada.create("nineball")
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    assert view["options"]["shot_clock"] == 0
    assert view["next"]["deadline"] == pytest.approx(time.time() + TURN_LIMIT, abs=30)
    for mode in ("practice", "bot"):
        alone = await ada.create("nineball", mode=mode)
        assert alone["next"]["deadline"] is None, mode
    storage = service_of(server).storage
    record = await storage.get_table(view["id"])
    expired = record.model_copy(update={"version": record.version + 1, "deadline": time.time()})
    watcher = await watch(server, view["channel"])
    assert await storage.update(expired)
    outcome = await watcher.next_kind("outcome")
    assert outcome["shot_id"] == f"clock:{expired.version:08d}" and outcome["next"]["seat"] == 1
    assert outcome["next"]["deadline"] == pytest.approx(time.time() + TURN_LIMIT, abs=30)


def test_the_timeout_input_calls_a_pocket_for_the_eight() -> None:
    """Eight-ball on the 8: a shot must call a pocket, the clock's too (before, it called none,
    was refused twice a second and the match never moved again)."""
    on_the_eight = from_json(
        refereeing.State,
        refereeing.new_rack("eightball", 3, 0).model_dump()
        | {
            "balls": {"cue": (0.6, 0.6), "8": (0.6, 1.8), "9": (0.3, 2.2)},
            "groups": ("solids", "stripes"),
            "shots": 5,
        },
    )
    action = refereeing.timeout_input(on_the_eight)
    assert action.call is not None
    refereeing.check(on_the_eight, action)
    assert refereeing.referee(on_the_eight, action).decision.fouls


def test_the_timeout_input_finds_room_in_a_crowded_d() -> None:
    """A set-up snooker position may put balls on every point of a coarse grid inside the D;
    the clock still places the cue ball in hand (before, it found no point and the table's
    clock failed every half second, forever)."""
    crowded = [(0.889, 0.446125), (0.66675, 0.55765625), (0.889, 0.55765625)]
    crowded += [(1.11125, 0.55765625), (0.66675, 0.6691875), (0.889, 0.6691875)]
    crowded += [(1.11125, 0.6691875)]
    names = ["black", *(f"red{i}" for i in range(1, 7))]
    state = from_json(
        refereeing.State,
        refereeing.new_rack("snooker", 3, 0).model_dump()
        | {"ball_in_hand": "D", "balls": dict(zip(names, crowded, strict=True)), "shots": 2},
    )
    action = refereeing.timeout_input(state)
    assert action.place is not None and action.place not in crowded
    refereeing.check(state, action)
    assert refereeing.referee(state, action).decision.fouls


async def test_a_clock_that_ran_out_while_the_server_was_down_is_ruled_on_return(
    start_server: StartServer, tmp_path: Path
) -> None:
    first = await start_server()
    ada, bob = await register(first, "Ada"), await register(first, "Bob")
    table = await ada.create("nineball", shot_clock=10)
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    await first.close()
    storage = await SqliteStorage.open(tmp_path / "game.sqlite")  # as the server left it
    record = await storage.get_table(view["id"])
    down = record.model_copy(update={"version": record.version + 1, "deadline": time.time() - 5})
    assert await storage.update(down)  # the clock ran out while nobody served the table
    await storage.close()
    second = await start_server()
    watcher = await watch(second, view["channel"])
    outcome = await watcher.next_kind("outcome")
    assert outcome["shot_id"] == f"clock:{down.version:08d}" and outcome["next"]["seat"] == 1

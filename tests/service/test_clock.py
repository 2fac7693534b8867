"""The shot clock: set by every change, ruled by the server through the ordinary match path."""

from __future__ import annotations

import time
from pathlib import Path

from aiohttp.test_utils import TestClient

from server.client.api_client import from_json
from server.game import refereeing
from server.storage.sqlite import SqliteStorage
from tests.service.conftest import StartServer, register, service_of, watch


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

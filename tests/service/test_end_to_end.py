"""A whole nine-ball rack over real sockets: quick match, a spectator, a reload mid-game."""

from __future__ import annotations

import asyncio
from typing import Any

from aiohttp.test_utils import TestClient

from tests.service.conftest import Player, Watcher, register, watch
from tests.service.test_match import picked

#: More inputs than a picker's nine-ball rack takes; a rack that does not end fails the test.
MAX_INPUTS = 400


async def quick_pair(server: TestClient, game: str) -> tuple[list[Player], dict[str, Any]]:
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    await ada.call("POST", "/api/quick", {"game": game}, 200)
    _, paired = await bob.call("POST", "/api/quick", {"game": game}, 200)
    view = await (await server.get(f"/api/tables/{paired['table']}")).json()
    return [ada, bob], view


async def test_two_players_pair_and_play_a_rack_to_its_end(server: TestClient) -> None:
    players, view = await quick_pair(server, "nineball")
    by_id = {p.info["id"]: p for p in players}
    spectator = await watch(server, view["channel"])
    player_feed: Watcher = await watch(server, view["channel"])
    seen_by_players: list[dict[str, Any]] = []
    seen_by_spectator: list[dict[str, Any]] = []
    current = view
    for n in range(MAX_INPUTS):
        if current["status"] == "over":
            break
        shooter = by_id[current["next"]["player"]]
        status, ack = await shooter.shoot(view["id"], current["version"], picked(current))
        assert status == 202, ack
        if n == 5:  # a reload: the player's page goes away and comes back with its last id
            last_id = player_feed.last_id
            await player_feed.ws.close()
            await asyncio.sleep(0.05)
            player_feed = await watch(server, view["channel"], last_id)
        current = await player_feed.next_kind("outcome")
        seen_by_players.append(current)
        seen_by_spectator.append(await spectator.next_kind("outcome"))
    assert current["status"] == "over" and current["winner"] in (0, 1)
    assert seen_by_players == seen_by_spectator  # identical outcomes, none missed
    versions = [o["version"] for o in seen_by_players]
    assert versions == list(range(view["version"] + 1, view["version"] + 1 + len(versions)))
    final = await (await server.get(f"/api/tables/{view['id']}")).json()
    assert final["status"] == "over" and final["version"] == versions[-1]
    assert final["racks_won"][current["winner"]] == 1

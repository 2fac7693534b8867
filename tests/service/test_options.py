"""The options a game is played with: snooker's reds and three-cushion's target reach the
rack and every later rack, the rematch and the quick-match pool; options of another game are
refused."""

from __future__ import annotations

from aiohttp.test_utils import TestClient

from server.game.lobby import choice_of, pool_of
from server.protocol.models import GameChoice
from tests.service.conftest import register


def reds_of(view: dict) -> int:
    return sum(ball.startswith("red") for ball in view["state"]["balls"])


async def test_a_six_red_table_racks_six_reds_and_keeps_them(server: TestClient) -> None:
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    table = await ada.create("snooker", reds=6, race_to=2)
    assert table["options"]["reds"] == 6 and reds_of(table) == 6
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    assert reds_of(view) == 6
    practice = await ada.create("snooker", mode="practice", reds=10)
    assert reds_of(practice) == 10


async def test_three_cushion_plays_to_its_target(server: TestClient) -> None:
    ada = await register(server, "Ada")
    table = await ada.create("three_cushion", target=5)
    assert table["options"]["target"] == 5 and table["state"]["target"] == 5
    default = await ada.create("three_cushion")
    assert default["state"]["target"] == 15


async def test_options_of_another_game_are_refused(server: TestClient) -> None:
    ada = await register(server, "Ada")
    for body in (
        {"game": "nineball", "reds": 6},
        {"game": "snooker", "target": 5},
        {"game": "snooker", "reds": 7},
        {"game": "three_cushion", "target": 101},
    ):
        status, refused = await ada.call("POST", "/api/tables", body)
        assert status in (400, 422) and refused["code"] in ("bad_request", "illegal_input"), body
        status, refused = await ada.call("POST", "/api/quick", body)
        assert status in (400, 422), body


async def test_quick_match_pairs_only_players_who_asked_for_the_same_options(
    server: TestClient,
) -> None:
    ada, bob, cy = [await register(server, name) for name in ("Ada", "Bob", "Cy")]
    _, first = await ada.call("POST", "/api/quick", {"game": "snooker", "reds": 6}, 200)
    _, other = await bob.call("POST", "/api/quick", {"game": "snooker"}, 200)
    assert first["status"] == other["status"] == "waiting"
    _, paired = await cy.call("POST", "/api/quick", {"game": "snooker", "reds": 6}, 200)
    assert paired["status"] == "paired"
    _, table = await cy.call("GET", f"/api/tables/{paired['table']}", expect=200)
    assert table["options"]["reds"] == 6 and reds_of(table) == 6
    assert [seat["id"] for seat in table["seats"]] == [ada.info["id"], cy.info["id"]]


def test_a_pool_names_the_options_that_differ_and_reads_back() -> None:
    for choice in (
        GameChoice(game="nineball"),
        GameChoice(game="snooker", reds=10, race_to=3),
        GameChoice(game="three_cushion", target=7),
    ):
        assert ":" not in pool_of(choice) and choice_of(pool_of(choice)) == choice
    assert pool_of(GameChoice(game="nineball")) == "nineball"

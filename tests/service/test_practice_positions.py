"""The practice table as a practice tool, and pool's table sizes, through the API on both
storage backends: a table set up from a position (checked: bad input changes nothing), re-racked,
its last shot taken again from the same position, positions shared as links; a set-up break is
never ranked and its claim is refused; 7, 8 and 9 ft pool tables."""

from __future__ import annotations

from typing import Any

import pytest
from aiohttp.test_utils import TestClient

from rules.spots import POOL_SIZES
from server.game import refereeing
from server.game.leaderboard import ranked
from server.protocol.models import TableOptions
from tests.service.conftest import Deploy, Player, on, register, watch

W, L = POOL_SIZES[9].width, POOL_SIZES[9].length
#: A straight pot of the 9 into the top right pocket: the rack is won at once.
POT = {"cue": [W - 0.5, L - 0.5], "9": [W - 0.2, L - 0.2]}
POT_SHOT = {"strike": {"ball": "cue", "speed": 2.0, "heading": 45.0}}


def balls(view: dict[str, Any]) -> dict[str, list[float]]:
    return {b: list(p) for b, p in view["state"]["balls"].items()}


async def shoot_and_wait(
    http: TestClient, player: Player, view: dict[str, Any], action: dict[str, Any]
) -> dict[str, Any]:
    """Play `action` at the table and return the outcome published for it (the channel
    replays earlier outcomes first)."""
    watcher = await watch(http, view["channel"])
    status, answer = await player.shoot(view["id"], view["version"], action)
    assert status == 202, answer
    while (outcome := await watcher.next_kind("outcome"))["version"] <= view["version"]:
        pass
    return outcome


async def test_a_practice_table_starts_from_a_set_up_position(deploy: Deploy) -> None:
    replicas = await deploy()
    ada = await register(replicas[0], "Ada")
    view = await ada.create("nineball", mode="practice", position=POT)
    assert balls(view) == POT and view["position"] == POT
    assert view["state"]["ball_in_hand"] is None and view["next"]["shot"]["push_out"] is False
    in_hand = await on(replicas, ada, 1).create(
        "nineball", mode="practice", position={"9": [0.6, 1.8], "3": [0.3, 1.2]}
    )
    assert in_hand["state"]["ball_in_hand"] == "anywhere"
    assert in_hand["next"]["shot"]["targets"] == ["3"]


#: How each kind of refusal answers: a position the rules refuse, or a malformed request.
REFUSED = {
    "bad_position": {(422, "bad_position")},
    "bad_request": {(400, "bad_request"), (422, "illegal_input")},
}


@pytest.mark.parametrize(
    ("body", "code"),
    [
        ({"position": {"9": [0.5, 1.0], "cue": [0.5, 1.03]}}, "bad_position"),  # overlapping
        ({"position": {"9": [0.5, 2.6]}}, "bad_position"),  # past the foot cushion
        ({"position": {"9": [0.02, 0.02]}}, "bad_position"),  # in a pocket
        ({"position": {"red1": [0.5, 1.0], "9": [0.5, 1.5]}}, "bad_position"),  # not its ball
        ({"position": {"1": [0.5, 1.0]}}, "bad_position"),  # no 9: the rack could not end
        ({"position": {"9": [0.5, 2.2]}, "size": 7}, "bad_position"),  # off a 7 ft bed
        ({"position": {"9": [0.5, 1.7e308]}}, "bad_position"),  # no rounding overflows
        ({"position": {"9": ["a", 1.0]}}, "bad_request"),
        ({"position": {"9": [0.5, 1.0]}, "mode": "match"}, "bad_request"),
    ],
)
async def test_bad_positions_are_refused_with_a_code_and_change_nothing(
    deploy: Deploy, body: dict[str, Any], code: str
) -> None:
    replicas = await deploy()
    ada = await register(replicas[0], "Ada")
    table = await ada.create("nineball", mode="practice")
    status, refused = await ada.call(
        "POST", "/api/tables", {"game": "nineball", "mode": "practice", **body}
    )
    assert (status, refused["code"]) in REFUSED[code], refused
    if "mode" in body or "size" in body:
        return
    status, refused = await on(replicas, ada, 1).call(
        "POST", f"/api/tables/{table['id']}/rack", body
    )
    assert (status, refused["code"]) in REFUSED[code], refused
    _, after = await ada.call("GET", f"/api/tables/{table['id']}", expect=200)
    assert after["version"] == table["version"] and balls(after) == balls(table)


async def test_rerack_sets_up_a_position_or_the_games_rack(deploy: Deploy) -> None:
    replicas = await deploy()
    ada, bob = await register(replicas[0], "Ada"), await register(replicas[0], "Bob")
    table = await ada.create("nineball", mode="practice")
    path = f"/api/tables/{table['id']}/rack"
    _, set_up = await on(replicas, ada, 1).call("POST", path, {"position": POT}, expect=200)
    assert balls(set_up) == POT and set_up["rack"] == table["rack"] + 1
    _, again = await ada.call("POST", path, {}, expect=200)
    assert again["position"] is None and len(again["state"]["balls"]) == 10
    assert set(again["presets"]) == {"combination", "long_pot"}
    assert again["ball_set"] == sorted(["cue", *map(str, range(1, 10))])
    named = again["presets"]["long_pot"]
    _, long_pot = await ada.call("POST", path, {"position": named}, expect=200)
    assert balls(long_pot) == named and long_pot["position"] == named
    status, refused = await bob.call("POST", path, {})
    assert (status, refused["code"]) == (403, "forbidden")
    match = await ada.create("nineball")
    status, refused = await ada.call("POST", f"/api/tables/{match['id']}/rack", {})
    assert (status, refused["code"]) == (409, "wrong_phase")


async def test_a_retake_sets_up_the_position_of_the_last_shot_and_replays_it(
    deploy: Deploy,
) -> None:
    replicas = await deploy()
    ada = await register(replicas[0], "Ada")
    position = {"9": [0.9, 2.0], "2": [0.4, 1.6], "5": [0.8, 0.9]}
    table = await ada.create("nineball", mode="practice", position=position)
    status, refused = await ada.call("POST", f"/api/tables/{table['id']}/retake")
    assert (status, refused["code"]) == (409, "wrong_phase")  # no shot yet
    placed = {"strike": {"ball": "cue", "speed": 1.5, "heading": 80.0}, "place": [0.35, 0.9]}
    first = await shoot_and_wait(replicas[0], ada, table, placed)
    assert first["state"]["balls"] != {**position, "cue": placed["place"]}
    _, view = await ada.call("GET", f"/api/tables/{table['id']}", expect=200)
    assert view["retake"] is True
    _, retaken = await on(replicas, ada, 1).call(
        "POST", f"/api/tables/{table['id']}/retake", expect=200
    )
    assert balls(retaken) == {**position, "cue": placed["place"]}
    assert retaken["state"]["ball_in_hand"] is None and retaken["position"] == balls(retaken)
    again = await shoot_and_wait(replicas[0], ada, retaken, {"strike": placed["strike"]})
    assert again["state"]["balls"] == first["state"]["balls"]
    assert again["decision"] == first["decision"]


async def test_a_retake_of_a_break_restores_the_frozen_rack_to_the_bit(deploy: Deploy) -> None:
    """The game's rack has its balls frozen (2R apart), which a player's position may not
    have: a retake starts from the balls as they lay, exactly, as often as wanted."""
    replicas = await deploy()
    ada = await register(replicas[0], "Ada")
    table = await ada.create("nineball", mode="practice")
    rack = balls(table)
    brk = {"strike": {"ball": "cue", "speed": 7.0, "heading": 90.0}}
    first = await shoot_and_wait(replicas[0], ada, table, brk)
    path = f"/api/tables/{table['id']}/retake"
    _, retaken = await on(replicas, ada, 1).call("POST", path, expect=200)
    assert balls(retaken) == rack and retaken["retake"] is True
    again = await shoot_and_wait(replicas[0], ada, retaken, brk)
    assert again["state"]["balls"] == first["state"]["balls"]
    _, twice = await ada.call("POST", path, expect=200)
    assert balls(twice) == rack and twice["version"] == again["version"] + 1


async def test_a_set_up_break_is_not_ranked_and_its_claim_is_refused(deploy: Deploy) -> None:
    replicas = await deploy()
    ada = await register(replicas[0], "Ada")
    table = await ada.create("nineball", mode="practice", position=POT)
    outcome = await shoot_and_wait(replicas[0], ada, table, POT_SHOT)
    assert outcome["decision"]["winner"] == 0 and outcome["replay"] is not None
    assert balls(outcome) == POT  # the next rack is the same set-up position
    _, replay = await ada.call("GET", f"/api/replays/{outcome['replay']}", expect=200)
    assert replay["record"]["setup"]["position"] == POT and max(replay["best"]) == 1
    verified = refereeing.verify(refereeing.GameRecord.model_validate(replay["record"]).to_json())
    assert verified.best == (1, 0)  # the record replays exactly from the position
    _, board = await ada.call("GET", "/api/leaderboard/nineball", expect=200)
    assert board["breaks"] == [] and board["ranks"] == {"reds": None, "target": None, "size": 9}
    claim = {"game": "nineball", "record": replay["record"], "score": 1}
    status, refused = await on(replicas, ada, 1).call("POST", "/api/leaderboard/claims", claim)
    assert (status, refused["code"]) == (422, "set_up_position"), refused


def test_only_the_standard_options_from_the_games_rack_are_ranked() -> None:
    assert ranked(TableOptions())
    assert not ranked(TableOptions(size=7)) and not ranked(TableOptions(size=8))
    assert not ranked(TableOptions(), position={"9": (0.5, 1.0)})


async def test_positions_are_shared_as_links_and_checked_when_opened(deploy: Deploy) -> None:
    replicas = await deploy()
    ada = await register(replicas[0], "Ada")
    body = {"game": "nineball", "size": 8, "position": {"9": [0.5, 1.0], "cue": [0.5, 0.3]}}
    _, shared = await ada.call("POST", "/api/positions", body, expect=200)
    assert shared["url"] == f"/practice/nineball?position={shared['code']}"
    assert len(shared["code"]) < 60
    _, opened = await on(replicas, ada, 1).call(
        "GET", f"/api/positions/{shared['code']}", expect=200
    )
    assert opened == shared and opened["size"] == 8
    table = await ada.create("nineball", mode="practice", size=8, position=opened["position"])
    assert balls(table) == body["position"] and table["options"]["size"] == 8
    for code in ("AAAA", "not-a-link", "x" * 300, "0"):
        status, refused = await ada.call("GET", f"/api/positions/{code}")
        assert (status, refused["code"]) == (422, "bad_position"), code
        assert "share link" in refused["reason"] or "position" in refused["reason"]
    overlapping = {**body, "position": {"9": [0.5, 1.0], "cue": [0.5, 1.02]}}
    status, refused = await ada.call("POST", "/api/positions", overlapping)
    assert (status, refused["code"]) == (422, "bad_position")


async def test_pool_is_played_on_seven_eight_and_nine_foot_tables(deploy: Deploy) -> None:
    replicas = await deploy()
    ada, bob = await register(replicas[0], "Ada"), await register(replicas[0], "Bob")
    for size in (7, 8, 9):
        on_table = POOL_SIZES[size]
        view = await ada.create("eightball", mode="practice", size=size)
        assert view["options"]["size"] == size and view["state"]["size"] == size
        assert view["state"]["balls"]["cue"] == [on_table.width / 2, on_table.length / 4]
    default = await ada.create("nineball", mode="practice")
    assert default["options"]["size"] == 9
    status, refused = await ada.call("POST", "/api/tables", {"game": "snooker", "size": 7})
    assert (status, refused["code"]) in REFUSED["bad_request"]
    status, refused = await ada.call("POST", "/api/tables", {"game": "nineball", "size": 6})
    assert (status, refused["code"]) in REFUSED["bad_request"]
    match = await ada.create("nineball", size=7)
    _, joined = await on(replicas, bob, 1).call(
        "POST", f"/api/tables/{match['id']}/join", expect=200
    )
    assert joined["state"]["size"] == 7
    tables = await (await replicas[0].get("/web/tables")).json()
    assert tables["nineball"]["sizes"]["7"]["l"] == pytest.approx(POOL_SIZES[7].length)


async def test_quick_match_pairs_only_players_who_asked_for_the_same_size(
    deploy: Deploy,
) -> None:
    replicas = await deploy()
    ada, bob, cy = [await register(replicas[0], name) for name in ("Ada", "Bob", "Cy")]
    _, first = await ada.call("POST", "/api/quick", {"game": "nineball", "size": 7}, 200)
    _, other = await bob.call("POST", "/api/quick", {"game": "nineball"}, 200)
    assert first["status"] == other["status"] == "waiting"
    _, paired = await on(replicas, cy, 1).call(
        "POST", "/api/quick", {"game": "nineball", "size": 7}, 200
    )
    assert paired["status"] == "paired"
    _, table = await cy.call("GET", f"/api/tables/{paired['table']}", expect=200)
    assert table["options"]["size"] == 7 and table["state"]["size"] == 7

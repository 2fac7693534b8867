"""Profiles: a decided match lands once in both players' histories with its ratings, how it
ended and its replays; bots are rated like anyone and listed with their levels."""

from __future__ import annotations

import asyncio

from aiohttp.test_utils import TestClient

from server.client.api_client import from_json
from server.game import refereeing
from server.protocol.models import BreakEntry, Source
from tests.service.conftest import WAIT_S, register, service_of
from tests.service.test_match import both_played, seated_match


async def test_a_resigned_match_is_in_both_profiles(server: TestClient) -> None:
    ada, bob, view = await seated_match(server)
    await both_played(server, ada, bob, view)
    _, over = await ada.call("POST", f"/api/tables/{view['id']}/resign", expect=200)
    assert over["ended"] == "resigned" and over["winner"] == 1
    profiles = {}
    for player in (ada, bob):
        response = await server.get(f"/api/players/{player.info['id']}/profile")
        assert response.status == 200
        profiles[player.info["name"]] = await response.json()
    lost, won = profiles["Ada"]["matches"], profiles["Bob"]["matches"]
    assert len(lost) == len(won) == 1
    assert (lost[0]["won"], won[0]["won"]) == (False, True)
    assert lost[0]["opponent"]["id"] == bob.info["id"] and lost[0]["ended"] == "resigned"
    assert won[0]["rating_after"] > won[0]["rating_before"] == 1500.0
    assert lost[0]["rating_after"] < lost[0]["rating_before"]
    assert profiles["Bob"]["ratings"]["nineball"]["games"] == 1
    assert profiles["Bob"]["ratings"]["nineball"]["provisional"] is True
    missing = await server.get("/api/players/p_0123456789abcdef/profile")
    assert missing.status == 404 and (await missing.json())["code"] == "not_found"


async def test_bots_are_rated_and_listed_by_level(server: TestClient) -> None:
    ada = await register(server, "Ada")
    table = await ada.create("eightball", mode="bot", bot="bot:2")
    await ada.call("POST", f"/api/tables/{table['id']}/resign", expect=200)  # before a shot
    before = {bot["id"]: bot for bot in (await (await server.get("/api/bots")).json())["bots"]}
    assert before["bot:2"]["ratings"] == {}
    table = await ada.create("eightball", mode="bot", bot="bot:2")
    foul = refereeing.timeout_input(from_json(refereeing.State, table["state"]))
    status, body = await ada.shoot(table["id"], table["version"], foul.model_dump(mode="json"))
    assert status == 202, body
    for _ in range(int(WAIT_S / 0.05)):  # the bot plays after Ada's foul
        view = await (await server.get(f"/api/tables/{table['id']}")).json()
        if view["version"] > body["version"]:
            break
        await asyncio.sleep(0.05)
    await ada.call("POST", f"/api/tables/{table['id']}/resign", expect=200)
    bots = await (await server.get("/api/bots")).json()
    levels = {bot["id"]: bot for bot in bots["bots"]}
    assert levels["bot:2"]["ratings"]["eightball"]["games"] == 1
    assert levels["bot:2"]["ratings"]["eightball"]["rating"] > 1500.0
    assert levels["bot:5"]["ratings"] == {}
    assert [bot["level"] for bot in bots["bots"]] == sorted(bot["level"] for bot in bots["bots"])
    assert all(bot["name"] and ":" not in bot["name"] for bot in bots["bots"])


async def test_a_profile_shows_only_the_breaks_its_player_made(server: TestClient) -> None:
    """The boards rank names, and a name passes to whoever registers it once it lapses:
    before, the name's next holder showed the breaks of the one before."""
    ada = await register(server, "Ada")
    storage = service_of(server).storage
    for who, score in (("p_" + "e" * 16, 7), (ada.info["id"], 3)):  # an earlier Ada's, hers
        entry = BreakEntry(
            game="nineball", score=score, name="Ada", player=who, source=Source.CLAIM, at=1.0
        )
        assert await storage.add_break(entry, f"{who}-{score}")
    path = f"/api/players/{ada.info['id']}/profile"
    # The 7 is not hers. (Nor is her 3 shown: the board's best under the name is the 7.)
    assert (await (await server.get(path)).json())["best_breaks"] == {}


async def test_a_private_match_on_a_profile_leads_nowhere(server: TestClient) -> None:
    """Profiles are public: before, a private match's table id on them led anyone to the
    table, and from it to the private rematch being played."""
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    table = await ada.create("nineball", private=True)
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    await both_played(server, ada, bob, view)
    await ada.call("POST", f"/api/tables/{table['id']}/resign", expect=200)
    await service_of(server).matches.idle()
    profile = await (await server.get(f"/api/players/{bob.info['id']}/profile")).json()
    (match,) = profile["matches"]
    assert match["won"] and match["table"] is None and match["replays"] == []

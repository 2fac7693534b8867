"""Players as the profile page finds them, on one SQLite server and on two Redis replicas: a
display name stands for the player holding it now, else its last holder (names that read the
same are one name); a profile carries the rating history of its graph, whether the player is
online and when it was last seen; three-cushion's default target asked for by its number is
the default (one quick-match pool). And the storage behind them, on both backends."""

from __future__ import annotations

import asyncio
import time
from urllib.parse import quote

from server.game.history import MatchResult
from server.game.identity import ONLINE, name_key
from server.game.profiles import RECENT, profile
from server.game.ratings import Rating
from server.protocol.ids import PROFILE_HISTORY
from server.protocol.models import Ending
from server.storage import Storage
from tests.service.conftest import ADA, BOB, Deploy, on, register, service_of
from tests.service.test_match import both_played


async def named(http, name: str) -> tuple[int, dict]:
    response = await http.get(f"/api/players/named/{quote(name)}")
    return response.status, await response.json()


async def test_a_name_stands_for_its_holder_then_its_last_holder(deploy: Deploy) -> None:
    replicas = await deploy()
    ada = await register(replicas[0], "Ada Lovelace")
    for asked in ("Ada Lovelace", "ada lovelace", "AdaLovelace", "AdaIovelace"):
        status, player = await named(replicas[-1], asked)
        assert status == 200 and player == ada.info, asked  # read alike: one name
    status, missing = await named(replicas[-1], "Nobody")
    assert status == 404 and missing["code"] == "not_found" and "Nobody" in missing["reason"]
    # Ada's claim lapses (she left): she still stands for her name until someone takes it.
    storage = service_of(replicas[0]).storage
    now = time.time()
    assert await storage.claim_name(name_key("Ada Lovelace"), ada.info["id"], now - 1, now)
    assert (await named(replicas[-1], "Ada Lovelace"))[1] == ada.info
    other = await register(replicas[-1], "ada lovelace")
    status, player = await named(replicas[0], "Ada Lovelace")
    assert status == 200 and player == other.info and player["name"] == "ada lovelace"
    # The earlier holder keeps her profile under her id.
    response = await replicas[0].get(f"/api/players/{ada.info['id']}/profile")
    profile = await response.json()
    assert response.status == 200 and profile["player"] == ada.info and not profile["online"]


async def test_a_malformed_name_is_refused_as_not_found(deploy: Deploy) -> None:
    replicas = await deploy()
    for path in ("/api/players/named/%3CAda%3E", "/api/players/named/%20Ada"):
        response = await replicas[0].get(path)
        assert response.status == 404 and (await response.json())["code"] == "not_found"


async def test_a_profile_has_its_rating_history_and_when_last_seen(deploy: Deploy) -> None:
    replicas = await deploy()
    ada = await register(replicas[0], "Ada")
    bob = on(replicas, await register(replicas[0], "Bob"), -1)
    before = time.time()
    for game, loser in (("nineball", ada), ("snooker", bob), ("nineball", ada)):
        table = await ada.create(game)
        _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
        await both_played(replicas[0], ada, bob, view)
        await loser.call("POST", f"/api/tables/{table['id']}/resign", expect=200)
    response = await replicas[-1].get(f"/api/players/{bob.info['id']}/profile")
    profile = await response.json()
    history, matches = profile["history"], profile["matches"]
    assert [p["game"] for p in history] == ["nineball", "snooker", "nineball"]  # oldest first
    assert [p["at"] for p in history] == sorted(p["at"] for p in history)
    # Each point is the rating after that match, as the matches (newest first) say.
    assert [p["rating"] for p in history] == [m["rating_after"] for m in reversed(matches)]
    assert history[0]["rating"] > 1500 > history[1]["rating"]
    assert history[2]["rating"] == profile["ratings"]["nineball"]["rating"]
    assert history[2]["deviation"] == profile["ratings"]["nineball"]["deviation"]
    assert profile["online"] is True
    assert before - 1 <= profile["last_seen"] <= time.time()


async def test_the_default_target_by_its_number_is_the_default(deploy: Deploy) -> None:
    replicas = await deploy()
    ada = await register(replicas[0], "Ada")
    bob = on(replicas, await register(replicas[0], "Bob"), -1)
    table = await ada.create("three_cushion", target=15)
    assert table["options"]["target"] == 0 and table["state"]["target"] == 15
    _, waiting = await ada.call("POST", "/api/quick", {"game": "three_cushion", "target": 15}, 200)
    assert waiting["status"] == "waiting"
    _, paired = await bob.call("POST", "/api/quick", {"game": "three_cushion"}, 200)
    assert paired["status"] == "paired"
    _, refused = await ada.call("POST", "/api/tables", {"game": "snooker", "target": 15}, 422)
    assert refused["code"] == "illegal_input"


async def test_name_holders_and_last_sign_of_life_are_kept(storage: Storage) -> None:
    key, now = name_key(ADA.name), time.time()
    assert await storage.name_holder(key) is None
    assert await storage.last_seen(ADA.id) is None
    await storage.add_player(ADA, now - 10)
    await storage.add_player(BOB, now - 10)
    assert await storage.last_seen(ADA.id) == now - 10
    # (Redis lapses claims on its own clock: a claim of half a second, really waited out.)
    assert await storage.claim_name(key, ADA.id, now + 0.5, now)
    assert await storage.name_holder(key) == (ADA.id, now + 0.5)
    assert await storage.last_seen(ADA.id) == now
    # Refused while Ada holds it: nothing changes; once lapsed, Bob's claim makes him the holder.
    assert not await storage.claim_name(key, BOB.id, now + ONLINE, now)
    assert await storage.name_holder(key) == (ADA.id, now + 0.5)
    assert await storage.last_seen(BOB.id) == now - 10
    await asyncio.sleep(0.6)
    assert await storage.name_holder(key) == (ADA.id, now + 0.5)  # lapsed, still her name
    later = time.time()
    assert await storage.claim_name(key, BOB.id, later + ONLINE, later)
    assert await storage.name_holder(key) == (BOB.id, later + ONLINE)
    assert await storage.last_seen(BOB.id) == later
    # An unrated player who expires has no last sign of life any more.
    assert await storage.expire_players(now - 1, 10) == []  # both seen since
    assert sorted(await storage.expire_players(later + 1, 10)) == [ADA.id, BOB.id]
    assert await storage.last_seen(ADA.id) is None
    assert await storage.get_player(ADA.id) is None


async def test_a_profile_graphs_a_bounded_number_of_matches(storage: Storage) -> None:
    await storage.add_player(ADA, 0.0)
    rating = Rating()
    for n in range(PROFILE_HISTORY + 3):
        after = rating.model_copy(update={"rating": 1500.0 + n, "games": n + 1})
        result = MatchResult(
            table=f"{n:020x}", game="snooker", at=1000.0 + n, seats=(ADA, BOB), winner=0,
            ended=Ending.RACKS, racks_won=(1, 0), before=(rating, rating), after=(after, rating),
        )  # fmt: skip
        assert await storage.add_result(result)
        rating = after
    seen = await profile(storage, ADA.id)
    assert len(seen.history) == PROFILE_HISTORY and len(seen.matches) == RECENT
    assert [p.rating for p in seen.history] == [1503.0 + n for n in range(PROFILE_HISTORY)]
    assert seen.matches[0].rating_after == 1500.0 + PROFILE_HISTORY + 2

"""Work a client can make the server do is bounded per holder: a practice table's shots, the
bots' searches (on workers of their own, one at a time per player)."""

from __future__ import annotations

import asyncio
import os
import time
from pathlib import Path
from typing import Any

from aiohttp.test_utils import TestClient

from server.client.api_client import from_json
from server.game import refereeing
from tests.service.conftest import register, service_of, watch
from tests.service.test_match import picked, seated_match

#: How long an answer may take here before the test calls it a stall.
ANSWER_S = 30.0
#: More requests than the practice bucket holds with what refills while they are sent.
PRACTICE_REQUESTS = 1000


def _held(release: str) -> None:
    """A worker's call that lasts until the file `release` exists."""
    while not os.path.exists(release):
        time.sleep(0.01)


def _foul(view: dict[str, Any]) -> dict[str, Any]:
    """The clock's dead-slow stroke for the table of `view`: a foul that hands over the turn."""
    state = from_json(refereeing.State, view["state"])
    return refereeing.timeout_input(state).model_dump(mode="json")


async def test_a_practising_players_shots_and_reracks_share_one_limit(server: TestClient) -> None:
    """Before: a player stored 190 practice shots a second, each rack's end a replay kept."""
    ada = await register(server, "Ada")
    view = await ada.create("nineball", mode="practice")
    path = f"/api/tables/{view['id']}"
    for _ in range(PRACTICE_REQUESTS):
        status, body = await ada.call("POST", f"{path}/rack", {})
        if status == 429:
            break
        assert status == 200, body
    assert (status, body["code"]) == (429, "rate_limited")
    before = await (await server.get(path)).json()
    status, body = await ada.shoot(view["id"], before["version"], picked(before))
    assert (status, body["code"]) == (429, "rate_limited")
    assert (await (await server.get(path)).json())["version"] == before["version"]
    bob = await register(server, "Bob")  # the limit is Ada's, not the server's
    other = await bob.create("nineball", mode="practice")
    status, _ = await bob.shoot(other["id"], other["version"], picked(other))
    assert status == 202


async def test_a_matchs_shot_does_not_wait_for_the_bots_workers(
    server: TestClient, tmp_path: Path
) -> None:
    """Every bot worker busy (as with players' bot tables searching), a match's shot is still
    played: before, the bots searched on the matches' workers, and one snooker table at level
    5 held another match's shot for 20 s."""
    bots = service_of(server).bots
    release = tmp_path / "release"
    held = [asyncio.create_task(bots._run(_held, str(release))) for _ in range(bots.workers)]
    try:
        ada, _, view = await seated_match(server)
        watcher = await watch(server, view["channel"])
        status, _ = await ada.shoot(view["id"], view["version"], picked(view))
        assert status == 202
        outcome = await asyncio.wait_for(watcher.next_kind("outcome"), ANSWER_S)
        assert outcome["version"] == view["version"] + 1
        assert not any(task.done() for task in held)
    finally:
        release.touch()
        await asyncio.gather(*held)


async def test_one_players_bot_tables_search_one_at_a_time(server: TestClient) -> None:
    """Ada's two bot tables wait on each other's search; Bob's does not wait on hers."""
    service = service_of(server)
    busy: list[str] = []
    most: dict[str, int] = {}
    both = asyncio.Event()

    holders = {"nineball": "Ada", "eightball": "Ada", "snooker": "Bob"}  # a game each

    async def search(state: refereeing.State, bot: str) -> refereeing.PlayerInput:
        holder = holders[state.game]
        busy.append(holder)
        most[holder] = max(most.get(holder, 0), busy.count(holder))
        if len(set(busy)) == 2:
            both.set()
        await asyncio.sleep(0.5)
        busy.remove(holder)
        return refereeing.timeout_input(state)

    service.bots.bot_input = search  # type: ignore[method-assign]
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    players = {"Ada": ada, "Bob": bob}
    tables = [
        (players[name], await players[name].create(game, mode="bot", bot="bot:5"))
        for game, name in holders.items()
    ]
    watchers = [await watch(server, view["channel"]) for _, view in tables]
    for player, view in tables:
        status, _ = await player.shoot(view["id"], view["version"], _foul(view))
        assert status == 202
    for watcher in watchers:
        await asyncio.wait_for(watcher.next_kind("outcome"), ANSWER_S)  # the player's foul
        bots_move = await asyncio.wait_for(watcher.next_kind("outcome"), ANSWER_S)
        assert bots_move["seat"] == 1
    assert most == {"Ada": 1, "Bob": 1} and both.is_set()
    await service.matches.idle()
    assert len(service.matches.context.bot_turns) == 0  # no lock kept for nobody


async def test_a_practice_shot_that_meets_a_conflict_is_counted_once(server: TestClient) -> None:
    """A shot whose compare-and-set meets another write to the table is looked at again (here
    it is then stale): one shot of the player's limit all the same. Before, each look took one."""
    ada = await register(server, "Ada")
    view = await ada.create("nineball", mode="practice")
    storage = service_of(server).matches.context.storage
    accept = storage.accept
    conflicts = 0

    async def accept_after_another_write(record):  # another replica wrote the table first
        nonlocal conflicts
        if not conflicts:
            conflicts += 1
            stored = await storage.get_table(record.id)
            assert await storage.update(stored.model_copy(update={"version": stored.version + 1}))
        return await accept(record)

    storage.accept = accept_after_another_write
    limiter = service_of(server).matches.context.practice
    before = limiter._buckets.get(ada.info["id"], (float(limiter.burst), 0.0))[0]
    status, body = await ada.shoot(view["id"], view["version"], picked(view))
    assert (status, body["code"], conflicts) == (409, "stale_version", 1)
    spent = before - limiter._buckets[ada.info["id"]][0]
    assert 0.5 < spent <= 1.0  # one token, less what refilled meanwhile

"""A replay's shots: every input's outcome, replayed from the record in the worker pool."""

from __future__ import annotations

import asyncio
import json
import time
from typing import Any

import pytest
from aiohttp.test_utils import TestClient

import physics
from rules.record import GameRecord, replay
from server.client.api_client import from_json
from server.game import refereeing, replays
from server.game.budget import WorkBudget
from server.game.replays import PAGES_AT_ONCE, ReplayShotsCache, shots_pages
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.ids import REPLAY_SHOTS_PAGE
from server.protocol.models import ReplayView
from server.storage import Storage
from tests.service.conftest import Player, Ticks, register, service_of, up_a_while, watch
from tests.service.test_leaderboard import _record
from tests.service.test_match import picked, seated_match


async def _shots(server: TestClient, replay_id: str) -> list[dict[str, Any]]:
    """Every shot of a replay, page after page."""
    shots: list[dict[str, Any]] = []
    page: int | None = 0
    while page is not None:
        response = await server.get(f"/api/replays/{replay_id}/shots?page={page}")
        body = await response.json()
        assert response.status == 200, body
        assert body["id"] == replay_id and body["page"] == page
        assert len(body["shots"]) <= REPLAY_SHOTS_PAGE
        shots += body["shots"]
        page = body["next"]
    return shots


def _final_state(record: dict[str, Any]) -> dict[str, Any]:
    return replay(GameRecord.model_validate(record)).final.model_dump(mode="json")


async def test_a_practice_racks_shots_are_its_live_outcomes(server: TestClient) -> None:
    ada = await register(server, "Ada")
    view = await ada.create("nineball", mode="practice")
    watcher = await watch(server, view["channel"])
    current, outcomes = view, []
    while current.get("replay") is None:
        status, _ = await ada.shoot(view["id"], current["version"], picked(current))
        assert status == 202
        current = await watcher.next_kind("outcome")
        outcomes.append(current)
    saved = await (await server.get(f"/api/replays/{current['replay']}")).json()
    shots = await _shots(server, current["replay"])
    assert [shot["input"] for shot in shots] == saved["record"]["inputs"]
    assert shots[-1]["state"] == _final_state(saved["record"])
    for shot, outcome in zip(shots, outcomes, strict=True):
        # The same wire form as the live outcome (whose last state is the next rack's).
        for part in ("input", "decision", "trajectory"):
            assert shot[part] == outcome[part], part
        if shot["decision"] is not None:
            assert shot["player"] == shot["decision"]["player"]
    for shot, outcome in zip(shots[:-1], outcomes[:-1], strict=True):
        assert shot["state"] == outcome["state"]
    assert await _shots(server, current["replay"]) == shots  # from the cache, the same


async def _play_shots(server: TestClient, players: dict[str, Player], view: dict, shots: int):
    """Play `shots` inputs on the table of `view`, each by the seat to act: the first option
    of a choice, else the shot clock's dead-slow stroke (a foul that ends no rack); the
    table's view after them."""
    for _ in range(shots):
        shooter = players[view["next"]["player"]]
        if view["next"]["options"]:
            action = {"kind": "choice", "option": view["next"]["options"][0]}
        else:
            state = from_json(refereeing.State, view["state"])
            action = refereeing.timeout_input(state).model_dump(mode="json")
        status, _ = await shooter.shoot(view["id"], view["version"], action)
        assert status == 202
        await service_of(server).matches.idle()
        view = await (await server.get(f"/api/tables/{view['id']}")).json()
        assert view["status"] == "playing" and view["rack"] == 1
    return view


async def test_a_rack_cut_short_by_a_resignation_or_a_claim_keeps_its_replay(
    server: TestClient,
) -> None:
    ada, bob, view = await seated_match(server)
    players = {ada.info["id"]: ada, bob.info["id"]: bob}
    watcher = await watch(server, view["channel"])
    before = await _play_shots(server, players, view, 2)
    _, over = await bob.call("POST", f"/api/tables/{view['id']}/resign", expect=200)
    assert (over["ended"], len(over["replays"])) == ("resigned", 1)
    # Whoever hears of the ending hears of the replay: it is in the view published with it.
    while (message := await watcher.next_kind("table"))["version"] < over["version"]:
        pass
    assert message["view"]["replays"] == over["replays"]
    saved = await (await server.get(f"/api/replays/{over['replays'][0]}")).json()
    inputs = await service_of(server).storage.rack_inputs(view["id"], 1)
    assert saved["record"]["inputs"] == [e.input.model_dump(mode="json") for e in inputs]
    assert saved["record"]["final"]["winner"] is None  # unfinished, and replayed as such
    shots = await _shots(server, over["replays"][0])
    assert len(shots) == 2 and shots[-1]["state"] == before["state"]
    assert not shots[-1]["state"]["over"]

    # A claim keeps the rack too; a match ended before any shot has nothing to replay.
    _, _, claimed = await seated_match(server, (ada, bob))
    await _play_shots(server, players, claimed, 1)
    up_a_while(server)
    await service_of(server).storage.heartbeat(claimed["id"], 1, time.time() - 1000)
    _, won = await ada.call("POST", f"/api/tables/{claimed['id']}/claim", expect=200)
    assert (won["ended"], len(won["replays"])) == ("claimed", 1)
    assert len(await _shots(server, won["replays"][0])) == 1
    _, _, idle = await seated_match(server, (ada, bob))
    _, over = await ada.call("POST", f"/api/tables/{idle['id']}/resign", expect=200)
    assert over["replays"] == []


async def test_an_ended_practice_keeps_its_last_rack_under_the_players_name(
    server: TestClient,
) -> None:
    ada = await register(server, "Ada")
    view = await ada.create("eightball", mode="practice")
    await _play_shots(server, {ada.info["id"]: ada}, view, 2)
    _, over = await ada.call("POST", f"/api/tables/{view['id']}/resign", expect=200)
    assert (over["status"], over["winner"], len(over["replays"])) == ("over", None, 1)
    saved = await (await server.get(f"/api/replays/{over['replays'][0]}")).json()
    assert saved["players"] == [ada.info, None] and saved["rack"] == 1
    assert len(await _shots(server, saved["id"])) == 2


async def test_a_claimed_breaks_shots_replay_its_record(server: TestClient) -> None:
    record, best = next((r, b) for r, b in map(_record, range(1, 20)) if b > 1)
    claim = {"game": "nineball", "record": record, "score": best}
    cy = await register(server, "Cy")
    _, verdict = await cy.call("POST", "/api/leaderboard/claims", claim, 201)
    shots = await _shots(server, verdict["replay"]["id"])
    assert [shot["input"] for shot in shots] == verdict["replay"]["record"]["inputs"]
    assert shots[-1]["state"] == _final_state(record)
    for shot in shots:
        assert (shot["trajectory"] is None) == ("strike" not in shot["input"])
    missing = await server.get("/api/replays/" + "0" * 24 + "/shots")
    assert (missing.status, (await missing.json())["code"]) == (404, "not_found")


class HeldPool:
    """A stand-in for the worker pool whose replays finish when the test lets them."""

    def __init__(self) -> None:
        self.release = asyncio.Event()
        self.calls: list[str] = []

    async def replay_shots(
        self, replay_id: str, record: GameRecord, first: int, count: int
    ) -> list[bytes]:
        self.calls.append(replay_id)
        await self.release.wait()
        return shots_pages(replay_id, record, first, count)


def _replay_view(replay_id: str, record: dict[str, Any]) -> ReplayView:
    return ReplayView(
        id=replay_id,
        url=replays.replay_url(replay_id),
        table=None,
        rack=1,
        game="nineball",
        players=[None, None],
        best=(0, 0),
        record=GameRecord.model_validate(record),
        created=0.0,
    )


async def test_replays_are_computed_one_at_a_time_and_kept(storage: Storage) -> None:
    record, _ = _record(2)
    first, second = "a" * 24, "b" * 24
    for replay_id in (first, second):
        await storage.add_replay(_replay_view(replay_id, record))
    pool = HeldPool()
    cache = ReplayShotsCache(storage, pool)  # type: ignore[arg-type]
    running = asyncio.ensure_future(cache.shots(first))
    while not pool.calls:
        await asyncio.sleep(0)
    same = asyncio.ensure_future(cache.shots(first))  # waits for the same computation
    with pytest.raises(ServiceError) as refused:
        await cache.shots(second)
    assert refused.value.code is ErrorCode.RATE_LIMITED
    pool.release.set()
    answer = await running
    assert await same == answer and pool.calls == [first]
    assert await cache.shots(first) == answer and pool.calls == [first]  # kept
    assert len(json.loads(answer)["shots"]) == len(record["inputs"])
    await cache.shots(second)
    assert pool.calls == [first, second]


class SizedPool:
    """A stand-in for the worker pool whose replays are `pages` pages of 100 bytes."""

    def __init__(self, pages: int) -> None:
        self.pages = pages
        self.calls: list[int] = []

    async def replay_shots(
        self, replay_id: str, record: GameRecord, first: int, count: int
    ) -> list[bytes]:
        self.calls.append(first)
        return [b"%03d" % page + b"x" * 97 for page in range(first, min(first + count, self.pages))]


async def test_a_long_replay_is_computed_a_few_pages_at_a_time_and_kept(
    storage: Storage, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A reader reading on computes the pages it reads, PAGES_AT_ONCE at a time, and reading
    them again finds them kept while the cache holds them; the cache counts each page once
    (before, every page was computed at once, and a replay longer than the cache evicted its
    own first pages)."""
    monkeypatch.setattr(replays, "REPLAY_SHOTS_PAGE", 1)  # a page an input
    monkeypatch.setattr(replays, "CACHE_BYTES", 600)  # 6 pages
    record, _ = _record(2)
    pages = len(record["inputs"])
    assert pages > 6  # more than the cache holds
    await storage.add_replay(_replay_view("e" * 24, record))
    pool = SizedPool(pages)
    cache = ReplayShotsCache(storage, pool)  # type: ignore[arg-type]
    for page in range(pages):
        assert (await cache.shots("e" * 24, page))[:3] == b"%03d" % page
    assert pool.calls == list(range(0, pages, PAGES_AT_ONCE))
    for page in range(pages - 1, pages - 5, -1):  # the last pages read are kept
        assert (await cache.shots("e" * 24, page))[:3] == b"%03d" % page
    assert len(pool.calls) == -(-pages // PAGES_AT_ONCE)
    assert cache._kept_bytes == sum(map(len, cache._kept.values())) <= 600


async def test_a_record_that_does_not_replay_is_refused(storage: Storage) -> None:
    record, _ = _record(2)
    record["engine"] = "0"  # stored by an older server
    await storage.add_replay(_replay_view("c" * 24, record))
    pool = HeldPool()
    pool.release.set()
    with pytest.raises(ServiceError) as refused:
        await ReplayShotsCache(storage, pool).shots("c" * 24)  # type: ignore[arg-type]
    assert (refused.value.code, refused.value.rule) == (ErrorCode.ILLEGAL_INPUT, "engine_version")


class AbandoningPool:
    """A stand-in for the worker pool whose engine abandons the record's first shot."""

    async def replay_shots(self, replay_id: str, record: GameRecord, *_: int) -> list[bytes]:
        raise physics.BudgetExceeded("input #1: the shot went past the engine's budget")


async def test_a_record_whose_shot_the_engine_abandons_is_refused_not_a_500(
    storage: Storage,
) -> None:
    record, _ = _record(2)
    await storage.add_replay(_replay_view("d" * 24, record))
    with pytest.raises(ServiceError) as refused:
        await ReplayShotsCache(storage, AbandoningPool()).shots("d" * 24)  # type: ignore[arg-type]
    assert refused.value.code is ErrorCode.ILLEGAL_INPUT and "input #1" in refused.value.reason


def test_a_window_of_pages_is_the_same_as_the_whole_replays(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Pages computed a few at a time (the record replayed only up to them, only their motions
    held) are the pages of the whole replay."""
    record = GameRecord.model_validate(_record(2)[0])
    monkeypatch.setattr(replays, "REPLAY_SHOTS_PAGE", 2)
    whole = shots_pages("a" * 24, record)
    assert len(whole) >= 3
    for first in range(len(whole)):
        assert shots_pages("a" * 24, record, first, 2) == whole[first : first + 2]


def test_a_long_replay_comes_in_pages_that_name_the_next(monkeypatch: pytest.MonkeyPatch) -> None:
    """Before: one answer held every shot (19.8 MB for a long snooker frame)."""
    record, _ = _record(2)
    monkeypatch.setattr(replays, "REPLAY_SHOTS_PAGE", 4)
    pages = [json.loads(page) for page in shots_pages("a" * 24, GameRecord.model_validate(record))]
    assert len(pages) == -(-len(record["inputs"]) // 4) > 1
    assert [page["page"] for page in pages] == list(range(len(pages)))
    assert [page["next"] for page in pages] == [*range(1, len(pages)), None]
    assert all(len(page["shots"]) <= 4 for page in pages)
    inputs = [shot["input"] for page in pages for shot in page["shots"]]
    played = GameRecord.model_validate(record).inputs
    assert inputs == [action.model_dump(mode="json") for action in played]


async def test_an_address_that_spent_its_worker_time_is_refused_before_work(
    storage: Storage,
) -> None:
    """Before: any unauthenticated request could make the server replay a long record again."""
    record, _ = _record(2)
    first, second = "a" * 24, "b" * 24
    for replay_id in (first, second):
        await storage.add_replay(_replay_view(replay_id, record))
    pool = HeldPool()
    pool.release.set()
    cache = ReplayShotsCache(storage, pool)  # type: ignore[arg-type]
    cache.budget = WorkBudget(0.5, "your replays", Ticks())
    await cache.shots(first, 0, "10.0.0.1")
    with pytest.raises(ServiceError) as refused:
        await cache.shots(second, 0, "10.0.0.1")
    assert refused.value.code is ErrorCode.RATE_LIMITED and pool.calls == [first]
    assert await cache.shots(first, 0, "10.0.0.1")  # kept: costs nothing
    await cache.shots(second, 0, "10.0.0.2")  # another address has its own minute
    assert pool.calls == [first, second]
    with pytest.raises(ServiceError) as missing:
        await cache.shots(second, 1, "10.0.0.2")
    assert missing.value.code is ErrorCode.NOT_FOUND

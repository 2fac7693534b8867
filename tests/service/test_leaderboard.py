"""Replays of finished racks, breaks entering the leaderboard, and verified claims."""

from __future__ import annotations

import json

from aiohttp.test_utils import TestClient

from rules.game import Setup
from rules.selfplay import selfplay
from server.client.api_client import from_json
from server.game import refereeing
from tests.service.conftest import register, watch
from tests.service.test_match import picked


async def test_a_finished_rack_has_a_replay_and_its_break_enters_the_leaderboard(
    server: TestClient,
) -> None:
    ada = await register(server, "Ada")
    view = await ada.create("nineball", mode="practice")
    watcher = await watch(server, view["channel"])
    board = await watch(server, "public-leaderboard")
    current, inputs = view, []
    while True:
        inputs.append(picked(current))
        status, _ = await ada.shoot(view["id"], current["version"], inputs[-1])
        assert status == 202
        current = await watcher.next_kind("outcome")
        if current["replay"] is not None:
            break
    assert len(current["replay"]) == 24  # 96 random bits
    saved = await (await server.get(f"/api/replays/{current['replay']}")).json()
    assert saved["url"] == f"/replay/{saved['id']}" and saved["players"][0]["name"] == "Ada"
    assert saved["record"]["inputs"] == inputs
    verified = refereeing.verify(json.dumps(saved["record"]).encode())  # it replays on its own
    assert verified.inputs == len(inputs) and tuple(saved["best"]) == verified.best
    best = verified.best
    top = await (await server.get("/api/leaderboard/nineball")).json()
    if max(best) > 0:
        assert top["breaks"][0]["score"] == max(best)
        assert top["breaks"][0]["source"] == "practice"
        assert (await board.next_kind("leaderboard"))["breaks"] == top["breaks"]
    else:
        assert top["breaks"] == []


def _record(seed: int) -> tuple[dict, int]:
    record, _ = selfplay(Setup(game="nineball", seed=seed), max_inputs=60)
    return json.loads(record.to_json()), max(refereeing.verify(record.to_json().encode()).best)


async def test_claims_are_replayed_and_refused_when_they_do_not_hold(server: TestClient) -> None:
    record, best = next((r, b) for r, b in map(_record, range(1, 20)) if b > 1)
    claim = {"game": "nineball", "record": record, "name": "Cy", "score": best}

    async def submit(body: dict) -> tuple[int, dict]:
        response = await server.post("/api/leaderboard/claims", json=body)
        return response.status, await response.json()

    status, verdict = await submit(claim | {"score": best + 1})
    assert (status, verdict["code"]) == (422, "claim_mismatch")
    status, verdict = await submit(claim | {"game": "snooker"})
    assert (status, verdict["code"]) == (422, "claim_mismatch")
    out_of_bounds = json.loads(json.dumps(record))
    out_of_bounds["inputs"][0]["strike"]["speed"] = 50
    status, verdict = await submit(claim | {"record": out_of_bounds})
    assert (status, verdict["code"]) == (400, "bad_request")
    other_engine = json.loads(json.dumps(record))
    other_engine["engine"] = "0"
    status, verdict = await submit(claim | {"record": other_engine})
    assert (status, verdict["code"]) == (422, "illegal_input")
    altered = json.loads(json.dumps(record))
    altered["inputs"][1]["strike"]["heading"] += 7.0
    status, verdict = await submit(claim | {"record": altered})
    # An altered shot is another game, which the record's digests give away.
    assert (status, verdict["code"], verdict["rule"]) == (422, "illegal_input", "replay_differs")
    board = (await (await server.get("/api/leaderboard/nineball")).json())["breaks"]
    assert board == []  # every refusal so far stored nothing

    status, verdict = await submit(claim)
    assert status == 201 and verdict["entry"]["score"] == best
    assert verdict["replay"]["record"] == from_json(refereeing.GameRecord, record).model_dump(
        mode="json"
    )
    status, again = await submit(claim)
    assert (status, again["code"]) == (409, "duplicate")
    mine = await (await server.get("/api/leaderboard/nineball/players/Cy")).json()
    assert mine["score"] == best and mine["source"] == "claim"
    assert (await server.get("/api/leaderboard/nineball/players/Nobody")).status == 404

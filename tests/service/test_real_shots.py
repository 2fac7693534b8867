"""The diagrams page's server work: recorded real shots (`/api/real-shots`) and the families of
shots (`/diagrams/rebounds` ...), computed in the background worker and bounded per client
(server/game/diagrams.py)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from aiohttp.test_utils import TestClient

from physics import ENGINE_VERSION
from physics.real_shots import fits, recordings
from server.game.budget import WorkBudget
from tests.service.conftest import Ticks, service_of

pytest.importorskip("scipy")

FIRST = fits()["shots"][0]


async def _json(server: TestClient, method: str, path: str, body=None, expect: int = 200):
    response = await server.request(method, path, json=body)
    payload = await response.json()
    assert response.status == expect, payload
    return payload


async def test_the_list_names_every_shipped_shot_with_its_fit(server: TestClient) -> None:
    listed = await _json(server, "GET", "/api/real-shots")
    assert [s["id"] for s in listed["shots"]] == sorted(recordings())
    assert listed["engine_version"] == ENGINE_VERSION
    rmse = [s["rmse_cm"] for s in listed["shots"]]
    assert listed["median_rmse_cm"] == pytest.approx(float(np.median(rmse)))
    assert listed["max_simulations"] > 1 and listed["max_seconds"] > 0


async def test_a_shot_answers_its_recorded_and_simulated_tracks(server: TestClient) -> None:
    fit = await _json(server, "GET", f"/api/real-shots/{FIRST['id']}")
    rec = recordings()[FIRST["id"]]
    assert fit["cue"] == rec.cue and (fit["simulations"], fit["stopped"]) == (1, "evaluated")
    assert fit["rmse_cm"] == pytest.approx(FIRST["rmse_cm"], rel=1e-9)
    for ball, track in rec.tracks.items():
        recorded = np.array(fit["recorded"][ball])
        assert np.allclose(recorded[:, 0], track.t, atol=1e-3)
        assert np.allclose(recorded[:, 1:], track.xy, atol=1e-4)
        simulated = np.array(fit["simulated"][ball])
        assert len(simulated) >= len(recorded) / 2 and np.all(np.diff(simulated[:, 0]) > 0)
        # The simulated ball starts where the recorded one does (the tracker's start).
        assert np.allclose(simulated[0, 1:], recorded[0, 1:], atol=0.01)
    again = await _json(server, "GET", f"/api/real-shots/{FIRST['id']}")
    assert again == fit


async def test_a_refit_stays_within_its_bound_and_improves_its_start(server: TestClient) -> None:
    """From a strike a degree off the shipped fit: the refit's answer is no worse than its
    start and it ran at most the simulations asked for."""
    start = {**FIRST["strike"], "heading": FIRST["strike"]["heading"] + 1.0}
    path = f"/api/real-shots/{FIRST['id']}/fit"
    evaluated = await _json(server, "POST", path, {"strike": start, "simulations": 1})
    assert (evaluated["simulations"], evaluated["stopped"]) == (1, "evaluated")
    assert evaluated["rmse_cm"] > FIRST["rmse_cm"]
    refit = await _json(server, "POST", path, {"strike": start, "simulations": 40})
    assert refit["simulations"] <= 40 and refit["stopped"] in ("simulations", "converged")
    assert refit["rmse_cm"] < evaluated["rmse_cm"]
    han = await _json(server, "POST", path, {"models": {"cushion": "han"}, "simulations": 1})
    assert han["models"]["cushion"] == "han" and han["rmse_cm"] != FIRST["rmse_cm"]


@pytest.mark.parametrize(
    "body",
    [
        {"simulations": 0},
        {"simulations": 10**6},
        {"strike": {**FIRST["strike"], "a": 0.9}},
        {"strike": {**FIRST["strike"], "speed": -1.0}},
        {"models": {"cushion": "stronge"}},
        {"constants": {"u_s": 1.0}},
    ],
)
async def test_a_bad_refit_is_refused_with_its_code(server: TestClient, body) -> None:
    response = await server.post(f"/api/real-shots/{FIRST['id']}/fit", json=body)
    assert response.status in (400, 422)
    assert (await response.json())["code"] in ("bad_request", "illegal_input")


async def test_an_unknown_shot_is_not_found(server: TestClient) -> None:
    for method, path in (("GET", "/api/real-shots/1"), ("POST", "/api/real-shots/1/fit")):
        body = await _json(server, method, path, {} if method == "POST" else None, expect=404)
        assert body["code"] == "not_found"


async def test_an_address_that_spent_its_worker_time_is_refused_before_work(
    server: TestClient,
) -> None:
    """Each answer costs its asker's address the worker time it took (here a second a read
    of the clock); once the minute's is spent, a refit is refused before its body is even
    read, and so is a family not yet computed, while a kept answer costs nothing."""
    work = service_of(server).diagrams
    work.budget = WorkBudget(0.5, "your diagrams", Ticks())
    path = f"/api/real-shots/{FIRST['id']}"
    kept = await _json(server, "GET", path)
    refused = await server.post(f"{path}/fit", data=b"not even json")
    assert refused.status == 429
    assert (await refused.json())["code"] == "rate_limited"
    assert await _json(server, "GET", path) == kept  # kept: costs nothing
    family = await server.get("/diagrams/throws?speed=2")
    assert family.status == 429 and (await family.json())["code"] == "rate_limited"


async def test_families_are_computed_in_the_worker_and_kept(server: TestClient) -> None:
    first = await server.get("/diagrams/rebounds?speed=1.5")
    assert first.status == 200
    data = json.loads(await first.read())
    names = [f["name"] for f in data["families"]]
    assert names == ["stun", "running", "check", "side", "slow_topspin", "hard_topspin"]
    # Its asker's worker time spent: the kept family still costs nothing.
    service_of(server).diagrams.budget = WorkBudget(0.5, "your diagrams", Ticks())
    await server.get("/api/real-shots/0")
    again = await server.get("/diagrams/rebounds?speed=1.5")
    assert again.status == 200 and await again.read() == await first.read()
    bad = await server.get("/diagrams/rebounds?speed=99")
    assert bad.status == 400 and (await bad.json())["code"] == "bad_request"

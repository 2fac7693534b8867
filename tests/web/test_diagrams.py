"""server/http/diagrams.py: the curves follow the constants asked for, and bad input computes
nothing."""

from __future__ import annotations

import pytest
from aiohttp.test_utils import TestClient

from server.http.diagrams import INPUTS, mount_diagrams


@pytest.fixture
async def client(serve):
    return await serve(mount_diagrams)


async def curve(client: TestClient, name: str, **query) -> dict:
    response = await client.get(f"/diagrams/{name}", params={k: str(v) for k, v in query.items()})
    assert response.status == 200, await response.text()
    return await response.json()


async def test_inputs_describe_every_field_with_its_bounds(client):
    response = await client.get("/diagrams/inputs")
    sliders = await response.json()
    assert sliders == INPUTS
    assert set(sliders) == {
        "throw", "cushion", "mathavan", "motion", "rebounds", "rebound_side", "throws",
    }  # fmt: skip
    for fields in sliders.values():
        for f in fields.values():
            assert f["min"] <= f["default"] <= f["max"] and f["label"]


async def test_more_ball_friction_throws_further(client):
    low = await curve(client, "throw", throw_b=0.05)
    high = await curve(client, "throw", throw_b=0.4)
    stun = next(c for c in low["curves"] if c["spin"] == "stun")["throw_deg"]
    stun_high = next(c for c in high["curves"] if c["spin"] == "stun")["throw_deg"]
    half_ball = low["cut_deg"].index(30)
    assert stun_high[half_ball] > stun[half_ball] > 0
    assert stun[0] == pytest.approx(0.0, abs=1e-9)  # a full-ball hit is not thrown


async def test_a_livelier_cushion_returns_more_speed(client):
    dead = await curve(client, "cushion", e_c=0.6)
    lively = await curve(client, "cushion", e_c=0.95)
    for a, b in zip(dead["curves"], lively["curves"], strict=True):
        assert (a["model"], a["spin"]) == (b["model"], b["spin"])
        assert b["speed_ratio"][0] > a["speed_ratio"][0]
    assert len(dead["curves"]) == 8 and len(dead["incidence_deg"]) == len(
        dead["curves"][0]["rebound_deg"]
    )


async def test_motion_is_the_struck_balls_segments(client):
    shot = await curve(client, "motion", speed=2.0, a=0.0, b=0.0)
    segments = shot["segments"]
    assert segments[0][:4] == [0.0, "stationary", 20.0, 1.0]  # at rest until struck at t = 0
    t, state, rx, ry, vx, vy = segments[1][:6]
    assert (t, rx, ry) == (0.0, 20.0, 1.0)
    assert vx == pytest.approx(0.0, abs=1e-12) and vy > 0 and state == "sliding"
    # At rest from the end of the shot (segment numbers are rounded to 7 digits on the wire).
    assert segments[-1][1] == "stationary"
    assert segments[-1][0] == pytest.approx(shot["duration"], rel=1e-6)
    slower = await curve(client, "motion", speed=2.0, a=0.0, b=0.0, u_r=0.03)
    assert slower["duration"] < shot["duration"]  # more rolling resistance stops it sooner


@pytest.mark.parametrize(
    "name, query",
    [
        ("throw", "speed=nan"),
        ("throw", "speed=inf"),
        ("throw", "speed=99"),
        ("throw", "throw_a=-1"),
        ("throw", "colour=red"),
        ("cushion", "height=3"),
        ("cushion", "e_c=abc"),
        ("motion", "a=0.45&b=0.45"),  # within each bound, but a miscue together
        ("motion", "u_s=0"),
    ],
)
async def test_bad_input_is_a_json_error(client, name, query):
    response = await client.get(f"/diagrams/{name}?{query}")
    assert response.status == 400
    body = await response.json()
    assert body["code"] == "bad_request" and body["reason"]


async def test_unknown_curve_is_not_found(client):
    response = await client.get("/diagrams/spin")
    assert response.status == 404
    assert (await response.json())["code"] == "not_found"


async def test_the_mathavan_figures_follow_the_speed_asked_for(client):
    slow = await curve(client, "mathavan", speed=0.5)
    fast = await curve(client, "mathavan", speed=2.0)
    assert [c["k"] for c in slow["curves"]] == [-1, 0, 1, 2]
    for a, b in zip(slow["curves"], fast["curves"], strict=True):
        # Scale-free: the angles agree and the speeds scale with the speed asked for.
        assert a["rebound_deg"] == pytest.approx(b["rebound_deg"], abs=0.05)
        assert [4 * s for s in a["speed"]] == pytest.approx(b["speed"], rel=2e-3)


async def test_a_family_needs_the_game_services_worker(client):
    """Mounted without the game service (as here), a family of shots computes nothing."""
    response = await client.get("/diagrams/rebounds")
    assert response.status == 503
    assert (await response.json())["code"] == "unavailable"

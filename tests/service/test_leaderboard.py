"""Replays of finished racks, breaks entering the leaderboard, and verified claims."""

from __future__ import annotations

import asyncio
import json

import pytest
from aiohttp.test_utils import TestClient

from rules.game import Setup
from rules.record import GameRecord, replay
from rules.selfplay import selfplay
from server.client.api_client import from_json
from server.game import refereeing, visits
from server.game.budget import WorkBudget
from server.game.leaderboard import TOP
from server.protocol.models import BreakEntry, Source
from tests.service.conftest import Player, Ticks, register, service_of, watch
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
        # The same break claimed from the rack's record is the break already entered.
        claim = {"game": "nineball", "record": saved["record"], "score": max(best)}
        status, refused = await ada.call("POST", "/api/leaderboard/claims", claim)
        assert (status, refused["code"]) == (409, "duplicate")
    else:
        assert top["breaks"] == []


def _record(seed: int) -> tuple[dict, int]:
    record, _ = selfplay(Setup(game="nineball", seed=seed), max_inputs=60)
    return json.loads(record.to_json()), max(refereeing.verify(record.to_json().encode()).best)


async def test_claims_are_replayed_and_refused_when_they_do_not_hold(server: TestClient) -> None:
    record, best = next((r, b) for r, b in map(_record, range(1, 20)) if b > 1)
    claim = {"game": "nineball", "record": record, "score": best}
    cy = await register(server, "Cy")

    async def submit(body: dict) -> tuple[int, dict]:
        return await cy.call("POST", "/api/leaderboard/claims", body)

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


# ----- one break, one entry; claims by players; cheap refusals first -------------------------
def _played(setup: Setup, max_inputs: int) -> tuple[GameRecord, list]:
    record, _ = selfplay(setup, max_inputs=max_inputs)
    played = replay(record)
    return record, [(step.action, step.state) for step in played.steps]


def _cut(record: GameRecord, steps: list, n: int) -> dict:
    """The record of the game's first `n` inputs, its digests recomputed (as anyone can)."""
    cut = GameRecord.begin(record.setup)
    for action, state in steps[:n]:
        cut = cut.extend(action, state)
    return json.loads(cut.to_json())


async def _claim(player: Player, record: dict, score: int, game: str = "nineball") -> tuple:
    body = {"game": game, "record": record, "score": score}
    status, answer = await player.call("POST", "/api/leaderboard/claims", body)
    return status, answer.get("code"), answer


def _best_visit(record: GameRecord, steps: list) -> visits.Visit:
    found = [v for v in visits.best_visits(replay(record).start, steps) if v is not None]
    return max(found, key=lambda v: steps[v.last][1].best[v.player])


async def test_a_break_is_one_entry_whatever_surrounds_it(server: TestClient) -> None:
    """A record cut after its best visit, or cut there with one input more, is the break
    already claimed (before: each was another entry of the same break)."""
    for seed in range(1, 40):
        record, steps = _played(Setup(game="nineball", seed=seed), 80)
        best = max(steps[-1][1].best)
        if best > 1 and _best_visit(record, steps).last + 2 < len(steps):
            break
    visit = _best_visit(record, steps)
    cy, dee = await register(server, "Cy"), await register(server, "Dee")
    status, _, first = await _claim(cy, json.loads(record.to_json()), best)
    assert status == 201 and first["entry"]["name"] == "Cy"
    for n in (visit.last + 1, visit.last + 2):
        status, code, _ = await _claim(dee, _cut(record, steps, n), best)
        assert (status, code) == (409, "duplicate"), n
    board = (await (await server.get("/api/leaderboard/nineball")).json())["breaks"]
    assert [entry["name"] for entry in board] == ["Cy"]


async def test_three_cushion_ignores_the_seed_and_claims_need_the_standard_rack(
    server: TestClient,
) -> None:
    """Three-cushion's start does not depend on its seed: the same inputs under another seed
    are the same break (before: 15 entries of one run). A rack gap is refused unreplayed."""
    games = (_played(Setup(game="three_cushion", seed=n), 60) for n in range(1, 30))
    record, steps = next((r, s) for r, s in games if max(s[-1][1].best) > 0)
    best = max(steps[-1][1].best)
    cy = await register(server, "Cy")
    data = json.loads(record.to_json())
    status, _, _ = await _claim(cy, data, best, "three_cushion")
    assert status == 201
    reseeded = data | {"setup": data["setup"] | {"seed": data["setup"]["seed"] + 1}}
    status, code, _ = await _claim(cy, reseeded, best, "three_cushion")
    assert (status, code) == (409, "duplicate")
    breaks = service_of(server).breaks
    replayed = breaks.replayed
    for setup in ({"gap": 0.001}, {"target": 40}):
        other = data | {"setup": data["setup"] | setup}
        status, code, answer = await _claim(cy, other, best, "three_cushion")
        assert (status, code) == (422, "claim_mismatch") and "standard" in answer["reason"]
    assert breaks.replayed == replayed  # refused before any replay


async def test_a_claim_is_made_by_a_player_under_its_own_name(server: TestClient) -> None:
    """Before: claims needed no token and carried a free name."""
    record, best = next((r, b) for r, b in map(_record, range(1, 20)) if b > 1)
    claim = {"game": "nineball", "record": record, "score": best}
    anonymous = await server.post("/api/leaderboard/claims", json=claim | {"name": "Ada"})
    assert (anonymous.status, (await anonymous.json())["code"]) == (401, "unauthorized")
    await register(server, "Ada")
    eve = await register(server, "Eve")
    status, refused = await eve.call("POST", "/api/leaderboard/claims", claim | {"name": "Ada"})
    assert (status, refused["code"]) == (403, "forbidden")
    _, verdict = await eve.call("POST", "/api/leaderboard/claims", claim, 201)
    assert verdict["entry"]["name"] == "Eve" and verdict["entry"]["player"] == eve.info["id"]
    assert verdict["entry"]["source"] == "claim"
    assert (await server.get("/api/leaderboard/nineball/players/Ada")).status == 404


async def test_repeated_claims_are_refused_without_a_replay(server: TestClient) -> None:
    """A claim of a record replayed before, duplicate or wrong, costs no replay; a holder out of
    worker time is refused before one (before: every claim replayed its whole record)."""
    (record, best), (other, other_best), (third, third_best) = [
        (r, b) for r, b in map(_record, range(1, 60)) if b > 1
    ][:3]
    cy, dee = await register(server, "Cy"), await register(server, "Dee")
    breaks = service_of(server).breaks
    assert (await _claim(cy, record, best + 1))[:2] == (422, "claim_mismatch")
    assert (await _claim(cy, record, best))[0] == 201
    replayed = breaks.replayed
    assert (await _claim(dee, record, best + 1))[:2] == (422, "claim_mismatch")
    assert (await _claim(dee, record, best))[:2] == (409, "duplicate")
    assert breaks.replayed == replayed
    # Parsing and replaying each take 1 s on this clock: one replay empties a holder's minute.
    breaks.budget = WorkBudget(1.5, "your claims", Ticks())
    assert (await _claim(dee, other, other_best + 1))[:2] == (422, "claim_mismatch")
    assert (await _claim(dee, third, third_best))[:2] == (429, "rate_limited")
    assert (await _claim(dee, other, other_best))[:2] == (429, "rate_limited")  # unread
    assert breaks.replayed == replayed + 1


async def test_claims_sent_at_once_are_parsed_within_their_holders_time(
    server: TestClient,
) -> None:
    """Each parse is charged before the next claim of its holder is parsed: before, claims
    whose bodies were all on their way passed the check made before their bodies came in, and
    one address's hundred 850 KB claims held the event loop for 12 s."""
    record, _ = _record(3)
    eve = await register(server, "Eve")
    breaks = service_of(server).breaks
    breaks.budget = WorkBudget(1.5, "your claims", Ticks())  # a parse costs 1 s on this clock
    sent = []
    for score in range(1, 9):  # every body half sent, so every claim waits for the rest of it
        body = json.dumps({"game": "eightball", "record": record, "score": score}).encode()
        reader, writer = await asyncio.open_connection(server.host, server.port)
        writer.write(
            b"POST /api/leaderboard/claims HTTP/1.1\r\nHost: x\r\nConnection: close\r\n"
            b"Content-Type: application/json\r\nAuthorization: "
            + eve.auth["Authorization"].encode()
            + b"\r\nContent-Length: %d\r\n\r\n" % len(body)
            + body[:100]
        )
        await writer.drain()
        sent.append((reader, writer, body[100:]))
    await asyncio.sleep(0.5)  # (only lets the requests reach their body: nothing is timed)
    for _, writer, rest in sent:
        writer.write(rest)
    codes = []
    for reader, writer, _ in sent:
        answer = await asyncio.wait_for(reader.read(), 30)
        codes.append(json.loads(answer.split(b"\r\n\r\n", 1)[1])["code"])
        writer.close()
    assert codes.count("claim_mismatch") <= 2 and codes.count("rate_limited") >= 6, codes


async def test_an_entry_below_a_full_top_is_neither_read_nor_announced(server: TestClient) -> None:
    """Breaks are never removed, so once this process has read a full top, an entry scoring
    below its lowest cannot be in it: nothing is read or published for it. One as high as
    the lowest may rank, and is announced."""
    service = service_of(server)
    for n in range(TOP):
        entry = BreakEntry(game="nineball", score=9, name=f"p{n}", source=Source.MATCH, at=n)
        assert await service.storage.add_break(entry, f"break:seeded-{n}")
    board = await watch(server, "public-leaderboard")
    breaks = service.breaks
    await breaks._announce("nineball", [3])  # the first read: announced, its lowest learnt
    await breaks._announce("nineball", [3])  # below the full top's lowest (9): skipped
    await breaks._announce("snooker", [50])
    first, second = [await board.next_kind("leaderboard") for _ in range(2)]
    assert (first["game"], len(first["breaks"])) == ("nineball", TOP)
    assert second["game"] == "snooker"
    await breaks._announce("nineball", [9])
    assert (await board.next_kind("leaderboard"))["game"] == "nineball"


async def test_claims_from_everyone_share_a_bounded_part_of_the_event_loop(
    server: TestClient,
) -> None:
    """Each holder's own time bounds its claims, not how many holders there are: claims from
    fresh players and addresses could otherwise keep the event loop parsing. Past the share of
    all claims, anyone's claim waits (429) before its body is parsed."""
    record, best = _record(3)
    breaks = service_of(server).breaks
    breaks.budget = WorkBudget(100.0, "your claims", Ticks())  # a parse costs 1 s on this clock
    breaks.parsing = WorkBudget(1.5, "claims from everyone", lambda: 0.0)  # nothing refills
    for more, name in enumerate(("Cy", "Dee"), 1):
        player = await register(server, name)
        assert (await _claim(player, record, best + more))[:2] == (422, "claim_mismatch")
    replayed = breaks.replayed
    eve = await register(server, "Eve")
    status, code, body = await _claim(eve, record, best)
    assert (status, code) == (429, "rate_limited"), body
    assert "everyone" in body["reason"]
    assert breaks.replayed == replayed


@pytest.mark.parametrize("private", [True, False])
async def test_a_private_tables_replays_do_not_name_it(server: TestClient, private: bool) -> None:
    """A rack's replay reaches the leaderboard and profiles with its breaks; a private table's
    must not lead there (before, a stranger read the private match and wrote to its chat)."""
    ada, bob = await register(server, "Ada"), await register(server, "Bob")
    table = await ada.create("nineball", private=private)
    _, view = await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    assert (await ada.shoot(view["id"], view["version"], picked(view)))[0] == 202
    await service_of(server).matches.idle()
    await bob.call("POST", f"/api/tables/{table['id']}/resign", expect=200)  # archives the rack
    over = await (await server.get(f"/api/tables/{table['id']}")).json()
    replay = await (await server.get(f"/api/replays/{over['replays'][0]}")).json()
    assert replay["table"] == (None if private else table["id"])


async def test_a_players_claims_must_beat_their_best(server: TestClient) -> None:
    """One player's claims climb the board: before, one break whose last shot was turned by a
    ten-thousandth of a degree, again and again, was a new break each time and filled it."""
    found = sorted(((b, r) for r, b in map(_record, range(1, 40)) if b > 1), key=lambda x: x[0])
    (low, lower), (high, higher) = found[0], found[-1]
    assert low < high
    cy = await register(server, "Cy")
    assert (await _claim(cy, higher, high))[0] == 201
    replayed = service_of(server).breaks.replayed
    status, code, body = await _claim(cy, lower, low)
    assert (status, code) == (409, "duplicate") and str(high) in body["reason"]
    assert service_of(server).breaks.replayed == replayed  # refused before any replay

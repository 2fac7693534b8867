"""Direct challenges over real sockets, on one SQLite server and on two Redis replicas: made,
seen at once on the player channel, accepted into a table for both (once, however many
accepts race), declined, cancelled, lapsed when a player leaves; and who is online."""

from __future__ import annotations

import asyncio
from typing import Any

import pytest

from server.game import lobby
from server.game.challenges import PAIR_LIMIT
from server.protocol.ids import player_channel
from server.storage import Storage
from tests.service.conftest import Deploy, on, register, service_of, watch


async def players(deploy: Deploy, **settings: Any) -> tuple[list, Any, Any]:
    replicas = await deploy(**settings)
    ada = await register(replicas[0], "Ada")
    bob = on(replicas, await register(replicas[0], "Bob"), -1)
    for player in (ada, bob):  # both on a page that shows challenges
        await player.call("GET", "/api/challenges", expect=200)
    return replicas, ada, bob


async def test_a_challenge_is_seen_at_once_and_accepted_into_one_table(deploy: Deploy) -> None:
    replicas, ada, bob = await players(deploy)
    inbox = await watch(replicas[-1], player_channel(bob.info["id"]))
    body = {"to": bob.info["id"], "game": "snooker", "reds": 6, "race_to": 2}
    _, made = await ada.call("POST", "/api/challenges", body, 201)
    heard = await inbox.next_kind("challenge")
    assert heard["challenge"]["id"] == made["id"] and heard["challenge"]["status"] == "pending"
    _, mine = await bob.call("GET", "/api/challenges", expect=200)
    assert [c["id"] for c in mine["challenges"]] == [made["id"]]
    path = f"/api/challenges/{made['id']}/accept"
    answers = await asyncio.gather(*(on(replicas, bob, n).call("POST", path) for n in range(6)))
    assert sorted(status for status, _ in answers) == [200] + [409] * 5
    accepted = next(body for status, body in answers if status == 200)
    table = accepted["table"]
    assert (await inbox.next_kind("paired"))["table"] == table
    _, view = await ada.call("GET", f"/api/tables/{table}", expect=200)
    assert view["status"] == "playing" and view["options"]["reds"] == 6
    assert [s["id"] for s in view["seats"]] == [ada.info["id"], bob.info["id"]]
    assert (await ada.call("GET", "/api/challenges", expect=200))[1]["challenges"] == []


async def test_decline_cancel_and_who_may_answer(deploy: Deploy) -> None:
    _, ada, bob = await players(deploy)
    body = {"to": bob.info["id"], "game": "nineball"}
    _, first = await ada.call("POST", "/api/challenges", body, 201)
    status, refused = await ada.call("POST", f"/api/challenges/{first['id']}/accept")
    assert status == 403 and refused["code"] == "forbidden"  # only the challenged accepts
    _, declined = await bob.call("POST", f"/api/challenges/{first['id']}/decline", expect=200)
    assert declined["status"] == "declined" and declined["table"] is None
    _, second = await ada.call("POST", "/api/challenges", body, 201)
    assert (await bob.call("POST", f"/api/challenges/{second['id']}/cancel"))[0] == 403
    _, cancelled = await ada.call("POST", f"/api/challenges/{second['id']}/cancel", expect=200)
    assert cancelled["status"] == "cancelled"
    status, late = await bob.call("POST", f"/api/challenges/{second['id']}/accept")
    assert status == 409 and late["code"] == "wrong_phase"
    for bad in (
        {"to": ada.info["id"], "game": "nineball"},
        {"to": "p_0123456789abcdef", "game": "nineball"},
    ):
        assert (await ada.call("POST", "/api/challenges", bad))[0] in (404, 422)


async def test_a_challenge_lapses_when_a_player_leaves(
    deploy: Deploy, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr("server.game.challenges.QUICK_LAPSE", 0.5)
    _, ada, bob = await players(deploy)
    _, made = await ada.call("POST", "/api/challenges", {"to": bob.info["id"], "game": "eightball"},
                             201)  # fmt: skip
    await asyncio.sleep(0.8)  # Bob closed his page; Ada's stays open
    _, mine = await ada.call("GET", "/api/challenges", expect=200)
    assert mine["challenges"] == []
    status, lapsed = await bob.call("POST", f"/api/challenges/{made['id']}/accept")
    assert status == 409 and "lapsed" in lapsed["reason"]


async def test_settling_a_challenge_happens_once(storage: Storage) -> None:
    from server.game.challenge_record import ChallengeRecord
    from server.protocol.models import ChallengeStatus, GameChoice
    from tests.service.conftest import ADA, BOB

    record = ChallengeRecord(
        id="c_0123456789abcdef", challenger=ADA, challenged=BOB,
        choice=GameChoice(game="nineball"), created=1.0,
    )  # fmt: skip
    await storage.add_challenge(record)
    assert [c.id for c in await storage.pending_challenges(BOB.id)] == [record.id]
    settled = [record.model_copy(update={"status": s}) for s in ChallengeStatus if s != "pending"]
    landed = await asyncio.gather(*(storage.settle_challenge(s) for s in settled))
    assert sorted(landed) == [False, False, False, True]  # once, whichever came first
    winner = settled[landed.index(True)]
    assert (await storage.get_challenge(record.id)).status is winner.status
    assert await storage.pending_challenges(ADA.id) == []


async def test_the_lobby_says_who_is_online_and_what_each_does(deploy: Deploy) -> None:
    replicas, ada, bob = await players(deploy)
    cy = await register(replicas[0], "Cy")
    table = await ada.create("nineball")
    await bob.call("POST", f"/api/tables/{table['id']}/join", expect=200)
    await cy.call("POST", "/api/quick", {"game": "snooker"}, 200)
    snapshot = await service_of(replicas[-1]).lobby.snapshot()
    doing = {entry.player.name: (entry.doing.value, entry.table) for entry in snapshot.online}
    assert doing == {
        "Ada": ("playing", table["id"]), "Bob": ("playing", table["id"]), "Cy": ("waiting", None)
    }  # fmt: skip
    assert snapshot.players_online == 3 and lobby.LISTED >= 3


async def test_a_player_is_challenged_only_while_there_and_not_in_a_loop(server) -> None:
    """Before, a challenge to a player who had left was made (and lapsed at the next look, so
    the limit of pending ones never held), and making and cancelling in a loop sent one
    player 29 alerts in 40 s."""
    ada, bob, cy = [await register(server, name) for name in ("Ada", "Bob", "Cy")]
    body = {"to": cy.info["id"], "game": "nineball"}
    status, refused = await ada.call("POST", "/api/challenges", body)
    assert (status, refused["code"]) == (409, "wrong_phase")  # Cy is not in the lobby
    await bob.call("GET", "/api/challenges", expect=200)  # Bob is
    body = {"to": bob.info["id"], "game": "nineball"}
    for _ in range(PAIR_LIMIT[1]):
        _, made = await ada.call("POST", "/api/challenges", body, 201)
        await ada.call("POST", f"/api/challenges/{made['id']}/cancel", expect=200)
    status, refused = await ada.call("POST", "/api/challenges", body)
    assert (status, refused["code"]) == (429, "rate_limited")
    await cy.call("GET", "/api/challenges", expect=200)  # the limit is Ada's towards Bob
    await ada.call("POST", "/api/challenges", {"to": cy.info["id"], "game": "nineball"}, 201)

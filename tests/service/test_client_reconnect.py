"""The API client (server/client/api_client.py) and `billiards play` / `watch` on a connection
that fails: a real server behind a real TCP proxy that cuts connections, refuses them for a
while, or loses the answer to a request the server carried out (tests/service/flaky_proxy.py).

The topology test (test_topology.py) kills a replica behind nginx; these hold each part of
the client's behaviour to account on its own, without nginx: the feed resumes after the last
message it delivered, a gap after a reconnect is a resync, an intent whose answer was lost is
resent under its shot id and played once, a proxy's error page is never read as JSON, the
client gives up with one line once its patience runs out, and `play`'s heartbeats get an input
that a dead replica had accepted played.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from typing import Any
from urllib.parse import parse_qs, urlsplit

import aiohttp
import pytest
from aiohttp.test_utils import TestClient

from server.client.api_client import Change, GameClient, Patience, Refused, Unreachable
from server.game import refereeing
from server.http.app import SERVICE_BUFFER
from server.protocol.models import (
    IntentDuplicate,
    OutcomeMessage,
    QuickStatus,
    TableList,
    TableView,
)
from server.relay.settings import RelaySettings
from tests.service.conftest import (
    SECRET,
    WAIT_S,
    Player,
    StartServer,
    register,
    service_of,
    watch,
)
from tests.service.flaky_proxy import FlakyProxy
from tests.service.test_cli import run
from tests.service.test_match import abandon_input
from tests.service.test_topology import Cli, match_over, outcomes, table_of


def base_url(server: TestClient) -> str:
    return str(server.make_url("")).rstrip("/")


@pytest.fixture
async def proxy(server: TestClient) -> AsyncIterator[FlakyProxy]:
    async with FlakyProxy(server.port) as flaky:
        yield flaky


@pytest.fixture
async def http() -> AsyncIterator[aiohttp.ClientSession]:
    async with aiohttp.ClientSession() as session:
        yield session


async def practice(
    http: aiohttp.ClientSession, proxy: FlakyProxy, server: TestClient
) -> tuple[GameClient, GameClient, TableView]:
    """A snooker practice table (a frame takes many shots) of a player who reads it through
    the proxy, and the same player's client straight to the server, to play while the proxy
    fails."""
    ada = GameClient(proxy.url, http)
    await ada.register("Ada")
    view = await ada.create("snooker", mode="practice")
    direct = GameClient(base_url(server), http)
    direct.token, direct.player = ada.token, ada.player
    return ada, direct, view


async def play_one(client: GameClient, table: str, at: Change) -> int:
    """Send the shot pickers' input for the table as `at` shows it; the version it will make."""
    action = refereeing.bot_input(at.state, "picker").model_dump(mode="json")
    return (await client.send(table, at.version, action)).version


async def next_change(feed: AsyncIterator[Change]) -> Change:
    return await asyncio.wait_for(anext(feed), WAIT_S)


def resumed_from(proxy: FlakyProxy, channel: str) -> list[str | None]:
    """The resume id of each subscription to `channel` the proxy passed on, in order."""
    targets = [r.split(" ", 1)[1] for r in proxy.requests if f"/sub/{channel}" in r]
    return [parse_qs(urlsplit(t).query).get("last_event_id", [None])[0] for t in targets]


# ----- the feed -------------------------------------------------------------------------------
async def test_a_cut_feed_resumes_after_the_last_message_it_delivered(
    server: TestClient, proxy: FlakyProxy, http: aiohttp.ClientSession
) -> None:
    ada, direct, view = await practice(http, proxy, server)
    ids = await watch(server, view.channel)  # the test's own reader, for the relay's ids
    feed = ada.follow(view)
    changes: list[Change] = []
    delivered: list[str] = []
    at: Change = view
    for _ in range(3):
        await play_one(direct, view.id, at)
        at = await next_change(feed)
        changes.append(at)
        await ids.next_kind("outcome")
        delivered.append(str(ids.last_id))
        assert proxy.cut() == 1  # the feed (the request above went straight to the server)
    assert all(isinstance(change, OutcomeMessage) for change in changes)  # no resync needed
    assert [c.version for c in changes] == [view.version + n for n in (1, 2, 3)]
    assert resumed_from(proxy, view.channel) == [None, *delivered[:2]]


async def test_a_gap_after_a_reconnect_is_a_resync_and_repeats_are_ignored(
    start_server: StartServer, http: aiohttp.ClientSession
) -> None:
    """The channel keeps two messages; four are published while the feed cannot reconnect,
    so its resume id has left the buffer: the relay says gap, the client fetches the table,
    and the two messages still buffered, older than that state, change nothing."""
    buffer = SERVICE_BUFFER.model_copy(update={"buffer_length": 2})
    server = await start_server(relay=RelaySettings(auth_secret=SECRET, buffer=buffer))
    async with FlakyProxy(server.port) as proxy:
        ada, direct, view = await practice(http, proxy, server)
        feed, beside = ada.follow(view), direct.follow(view)
        first = await play_one(direct, view.id, view)
        assert (await next_change(feed)).version == first
        at = await next_change(beside)
        await proxy.down()
        reconnecting = asyncio.ensure_future(next_change(feed))  # retries while refused
        for _ in range(4):
            await play_one(direct, view.id, at)
            at = await next_change(beside)
        await proxy.up()
        resync = await reconnecting
        after = await play_one(direct, view.id, at)
        following = await next_change(feed)
    assert isinstance(resync, TableView) and resync.version == at.version == first + 4
    assert isinstance(following, OutcomeMessage) and following.version == after == first + 5
    gets = [r for r in proxy.requests if r == f"GET /api/tables/{view.id}"]
    assert len(gets) == 1 and resumed_from(proxy, view.channel)[-1] is not None


async def test_a_feed_gives_up_once_the_server_stays_out_of_reach(
    server: TestClient, proxy: FlakyProxy, http: aiohttp.ClientSession
) -> None:
    ada, direct, view = await practice(http, proxy, server)
    ada.patience = Patience(give_up=0.5)
    feed = ada.follow(view)
    await play_one(direct, view.id, view)
    await next_change(feed)
    await proxy.down()
    with pytest.raises(Unreachable, match=r"no answer for 0\.5 s"):
        await next_change(feed)
    with pytest.raises(Unreachable, match=r"no answer for 0\.5 s"):
        await ada.table(view.id)


async def test_a_change_the_feed_never_carried_is_found_by_the_heartbeats(
    server: TestClient, http: aiohttp.ClientSession
) -> None:
    """A server that stored a change and died before publishing it: the feed says nothing,
    but the next heartbeat's answer carries the table's version, and the follower resyncs
    instead of waiting for ever."""
    ada = GameClient(base_url(server), http)
    await ada.register("Ada")
    view = await ada.create("snooker", mode="practice")
    feed = ada.follow(view)
    waiting = asyncio.ensure_future(next_change(feed))
    await asyncio.sleep(0.1)  # the follower is reading its feed
    storage = service_of(server).storage
    record = await storage.get_table(view.id)
    assert await storage.update(record.model_copy(update={"version": record.version + 1}))
    async with ada.heartbeats(view.id):
        change = await waiting
    assert isinstance(change, TableView) and change.version == view.version + 1


# ----- requests -------------------------------------------------------------------------------
@pytest.mark.parametrize("loss", [502, None], ids=["proxy-page", "no-answer"])
async def test_an_intent_whose_answer_was_lost_is_resent_under_its_shot_id_and_played_once(
    server: TestClient, proxy: FlakyProxy, http: aiohttp.ClientSession, loss: int | None
) -> None:
    ada, _, view = await practice(http, proxy, server)
    feed = ada.follow(view)
    intents = f"/api/tables/{view.id}/intents"
    proxy.lose_answer(intents, loss)
    action = refereeing.bot_input(view.state, "picker").model_dump(mode="json")
    ack = await ada.send(view.id, view.version, action)
    # The server had accepted and played it: the resend (the same shot id) gets its outcome.
    assert isinstance(ack, IntentDuplicate) and ack.version == view.version + 1
    assert [r for r in proxy.requests if r.startswith("POST")][-2:] == [f"POST {intents}"] * 2
    outcome = await next_change(feed)
    assert isinstance(outcome, OutcomeMessage) and ack.outcome is not None
    assert outcome.shot_id == ack.outcome.shot_id and outcome.version == ack.version
    assert (await ada.table(view.id)).version == view.version + 1  # played once


async def test_a_proxys_error_page_is_retried_or_refused_never_read_as_json(
    server: TestClient, proxy: FlakyProxy, http: aiohttp.ClientSession
) -> None:
    ada, _, view = await practice(http, proxy, server)
    path = f"/api/tables/{view.id}"
    for status in (502, 503, 504):  # the server behind could not answer: asked again
        proxy.lose_answer(path, status)
    assert (await ada.table(view.id)).id == view.id
    assert proxy.requests.count(f"GET {path}") == 4
    proxy.lose_answer(path, 413)  # any other page is a refusal, said in words, not retried
    with pytest.raises(Refused) as refused:
        await ada.table(view.id)
    assert (refused.value.status, refused.value.code) == (413, "http_413")
    assert refused.value.reason == "the server answered 413 Request Entity Too Large"
    assert proxy.requests.count(f"GET {path}") == 5


async def test_a_join_whose_answer_was_lost_takes_the_seat_once(
    server: TestClient, proxy: FlakyProxy, http: aiohttp.ClientSession
) -> None:
    host = GameClient(base_url(server), http)
    await host.register("Ada")
    table = await host.create("nineball")
    bob = GameClient(proxy.url, http)
    await bob.register("Bob")
    proxy.lose_answer(f"/api/tables/{table.id}/join", 502)
    view = await bob.join(table.id)  # the resend is `already_seated`: the seat is Bob's
    assert [seat.id for seat in view.seats if seat] == [host.player.id, bob.player.id]
    assert view.version == table.version + 1


async def test_a_quick_request_whose_answer_was_lost_is_not_sent_again(
    server: TestClient, proxy: FlakyProxy, http: aiohttp.ClientSession
) -> None:
    """Ada's request paired her with Bob, and its answer was lost: she asks where she stands
    instead of queueing again (a resend would queue her, and could pair her twice)."""
    bob = GameClient(base_url(server), http)
    await bob.register("Bob")
    assert (await bob.quick("nineball")).status == "waiting"
    ada = GameClient(proxy.url, http)
    await ada.register("Ada")
    proxy.lose_answer("/api/quick", None)
    status = await ada.quick("nineball")
    assert status.status == "paired" and status.table is not None
    assert [r for r in proxy.requests if "/api/quick" in r] == ["POST /api/quick", "GET /api/quick"]
    assert QuickStatus.model_validate_json(await bob.fetch("GET", "/api/quick")) == status


async def test_a_public_table_whose_answer_was_lost_is_found_not_created_again(
    server: TestClient, proxy: FlakyProxy, http: aiohttp.ClientSession
) -> None:
    ada = GameClient(proxy.url, http)
    await ada.register("Ada")
    proxy.lose_answer("/api/tables", 502)
    view = await ada.create("eightball")
    listed = TableList.model_validate_json(await ada.fetch("GET", "/api/tables")).tables
    assert [table.id for table in listed] == [view.id]
    assert proxy.requests.count("POST /api/tables") == 1


# ----- the command line -----------------------------------------------------------------------
async def test_play_and_watch_ride_out_cut_connections(
    server: TestClient, proxy: FlakyProxy
) -> None:
    """Every connection through the proxy is cut after each of the first outcomes (eight-ball:
    a rack cannot end on its break, so there are at least two); both players and a watcher
    (there before the match starts) see the whole rack, each version once, and exit 0."""
    url = proxy.url
    started: list[Cli] = []
    try:
        ada = Cli(await run("play", url, "eightball", "--create", "--name", "Ada"))
        started.append(ada)
        await ada.until(lambda lines: table_of(lines) is not None)
        table = str(table_of(ada.lines))
        started.append(watcher := Cli(await run("watch", url, table)))
        await watcher.until(lambda lines: len(lines) >= 1)
        started.append(Cli(await run("play", url, "eightball", "--join", table, "--name", "Bob")))
        feeds_cut = 0
        for cut in range(1, 4):
            await ada.until(lambda lines, cut=cut: len(outcomes(lines)) >= cut or match_over(lines))
            if match_over(ada.lines):
                break
            feeds_cut += proxy.cut()
        results = await asyncio.gather(*(cli.finish() for cli in started))
    finally:
        for cli in started:
            await cli.kill()
    assert feeds_cut > 0
    for code, lines, err in results:
        assert code == 0 and match_over(lines), (lines, err)
        versions = [int(line.split()[0][1:]) for line in lines if line.startswith("v")]
        assert versions == sorted(set(versions))  # each change once, in order
    assert results[0][1][-1] == results[1][1][-1] == results[2][1][-1]


async def test_play_exits_2_with_one_line_when_the_server_stays_away(
    proxy: FlakyProxy,
) -> None:
    player = Cli(await run("play", proxy.url, "snooker", "--practice", "--patience", "1"))
    try:
        await player.until(lambda lines: len(outcomes(lines)) >= 1)
        await proxy.down()
        code, lines, err = await player.finish()
    finally:
        await player.kill()
    assert code == 2 and not match_over(lines)
    assert err.startswith(f"cannot reach {proxy.url}: no answer for 1 s") and err.count("\n") == 1


async def test_plays_heartbeats_get_an_input_a_dead_replica_accepted_played(
    server: TestClient,
) -> None:
    """Bob's input was accepted by a replica that died before playing it. Nobody but Ada's
    `billiards play` touches the table afterwards (the test reads storage, not the API, as a
    request would itself make the server look at the table): its heartbeats do."""
    ada = Cli(await run("play", base_url(server), "nineball", "--create", "--name", "Ada"))
    try:
        await ada.until(lambda lines: table_of(lines) is not None)
        table = str(table_of(ada.lines))
        bob = await register(server, "Bob")
        await bob.call("POST", f"/api/tables/{table}/join", expect=200)
        view = await bobs_turn(bob, table)
        await abandon_input(service_of(server).storage, view, "lost-with-its-replica", seat=1)
        await ada.until(lambda lines: view["version"] + 1 in outcomes(lines))
    finally:
        await ada.kill()
    assert outcomes(ada.lines)[view["version"] + 1].split()[1] == "Bob:"
    seen = await service_of(server).storage.heartbeats(table)
    assert seen[0] is not None and seen[1] is None  # Ada's heartbeats; Bob sent none


async def bobs_turn(bob: Player, table: str) -> dict[str, Any]:
    """The table once Ada's `play` has played her visit and Bob is to act."""
    deadline = asyncio.get_running_loop().time() + WAIT_S
    while True:
        _, view = await bob.call("GET", f"/api/tables/{table}", expect=200)
        if view["next"] is not None and view["next"]["player"] == bob.info["id"]:
            return view
        assert asyncio.get_running_loop().time() < deadline, view["next"]
        await asyncio.sleep(0.05)

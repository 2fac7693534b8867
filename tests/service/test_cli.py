"""`billiards play`, `watch` and `submit` as processes against a running server."""

from __future__ import annotations

import asyncio
import sys
import time
from pathlib import Path

from aiohttp.test_utils import TestClient

from server.game import refereeing
from server.protocol.ids import PRESENCE_TIMEOUT
from tests.service.conftest import WAIT_S, StartServer, register, service_of, up_a_while

BILLIARDS = [sys.executable, "-m", "server.cli"]


async def run(*args: str) -> asyncio.subprocess.Process:
    return await asyncio.create_subprocess_exec(
        *BILLIARDS, *args, stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE
    )


async def finish(process: asyncio.subprocess.Process) -> tuple[int, list[str], str]:
    out, err = await asyncio.wait_for(process.communicate(), 4 * WAIT_S)
    return process.returncode, out.decode().splitlines(), err.decode()


async def test_two_command_line_players_play_a_match_and_a_watcher_sees_it(
    server: TestClient,
) -> None:
    url = str(server.make_url("")).rstrip("/")
    # A quick match on the 8 ft table: both ask for it, so they are paired with each other.
    ada = await run("play", url, "nineball", "--quick", "--size", "8", "--name", "Ada")
    bob = await run("play", url, "nineball", "--quick", "--size", "8", "--name", "Bob")
    (code_a, lines_a, err_a), (code_b, lines_b, err_b) = await asyncio.gather(
        finish(ada), finish(bob)
    )
    assert (code_a, code_b) == (0, 0), err_a + err_b
    assert "nineball (60 s shot clock, 8 ft table)" in lines_a[0]
    assert lines_a[0].split()[1] == lines_b[0].split()[1]
    assert lines_a[-1] == lines_b[-1] and "match over" in lines_a[-1]
    table = lines_a[0].split()[1].rstrip(":")
    code, lines, _ = await finish(await run("watch", url, f"{url}/t/{table}"))
    assert code == 0 and lines[0].startswith(f"v{lines_a[-1].split()[0][1:]}")


async def test_a_refusal_exits_2_with_one_line(server: TestClient) -> None:
    url = str(server.make_url("")).rstrip("/")
    code, _, err = await finish(await run("play", url, "nineball", "--join", "f" * 20))
    assert code == 2 and err.strip() == "refused: not_found: no such table"
    code, _, err = await finish(await run("watch", "http://127.0.0.1:1", "f" * 20))
    assert code == 2 and len(err.strip().splitlines()) == 1
    code, _, err = await finish(await run("play", url, "nineball", "--bot", "bot:99"))
    assert code == 2 and err.startswith("refused: unknown_chooser:") and err.count("\n") == 1


async def test_a_practice_table_starts_from_a_shared_position(server: TestClient) -> None:
    url = str(server.make_url("")).rstrip("/")
    balls = {"cue": [0.3, 0.4], "1": [0.5, 1.0], "9": [0.6, 1.3]}
    shared = await server.post(
        "/api/positions", json={"game": "nineball", "size": 7, "position": balls}
    )
    code = (await shared.json())["code"]
    cy = await run("play", url, "nineball", "--practice", "--position", code, "--name", "Cy")
    first = (await asyncio.wait_for(cy.stdout.readline(), WAIT_S)).decode()
    cy.kill()
    await cy.wait()
    assert "nineball (7 ft table, from a set-up position), you are Cy" in first
    view = await (await server.get(f"/api/tables/{first.split()[1].rstrip(':')}")).json()
    assert view["options"]["size"] == 7 and set(view["position"]) == set(balls)


async def test_options_given_where_they_mean_nothing_are_refused(server: TestClient) -> None:
    url = str(server.make_url("")).rstrip("/")
    code, _, err = await finish(await run("play", url, "nineball", "--position", "abc"))
    assert code == 2 and err.strip() == "refused: bad_arguments: --position goes with --practice"
    code, _, err = await finish(await run("play", url, "snooker", "--vs-bot", "--reds", "7"))
    assert code == 2 and "--reds: invalid choice: 7" in err
    code, _, err = await finish(await run("play", url, "nineball", "--create", "--race-to", "99"))
    assert code == 2 and err.startswith("refused: bad_request:") and "race_to" in err


async def test_submit_prints_the_verdict_or_the_reason(server: TestClient, tmp_path: Path) -> None:
    url = str(server.make_url("")).rstrip("/")
    record_path = tmp_path / "game.json"
    for seed in range(1, 30):
        code, _, err = await finish(
            await run("selfplay", "nineball", "--seed", str(seed), "--record", str(record_path))
        )
        assert code == 0, err
        best = max(refereeing.verify(record_path.read_bytes()).best)
        if best > 0:
            break
    cy = await register(server, "Cy")
    args = ("submit", url, str(record_path), "--token", cy.token)
    code, _, err = await finish(await run(*args, "--score", str(best + 1)))
    assert code == 2 and err.strip() == (
        f"refused: claim_mismatch: the record's best break is {best}, not {best + 1}"
    )
    code, lines, _ = await finish(await run(*args, "--score", str(best)))
    assert code == 0 and lines[0].startswith(f"accepted: nineball break of {best} by Cy")


async def test_play_claims_the_win_from_an_opponent_gone_past_the_grace(
    start_server: StartServer,
) -> None:
    server = await start_server(grace=0.0)
    url = str(server.make_url("")).rstrip("/")
    bob = await register(server, "Bob")
    table = await bob.create("nineball")  # Bob breaks, and is gone before his first shot:
    up_a_while(server)  # here when Ada joins, absent a second later
    last = time.time() - PRESENCE_TIMEOUT + 1.0
    await service_of(server).storage.heartbeat(table["id"], 0, last)
    ada = await run("play", url, "nineball", "--join", table["id"], "--name", "Ada")
    code, lines, err = await finish(ada)
    assert code == 0, err
    assert lines[-1].endswith("table over: Bob vs Ada -- match over, Ada wins"), lines

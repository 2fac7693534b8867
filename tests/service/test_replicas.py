"""One match served by two real server processes sharing one real Redis."""

from __future__ import annotations

import asyncio
import json
import os
import subprocess
import sys
import time
import uuid
from collections.abc import AsyncIterator, Iterator
from pathlib import Path
from typing import Any

import aiohttp
import pytest

from server.storage.redis import RedisStorage
from tests.redis_server import free_port
from tests.service.test_match import abandon_input, picked

SECRET = "replica-test-secret-0123456789"
START_TIMEOUT_S = 30.0


class Replica:
    """`billiards serve --redis URL` in its own process."""

    def __init__(self, redis_url: str, directory: Path) -> None:
        self.port = free_port()
        self.url = f"http://127.0.0.1:{self.port}"
        env = {**os.environ, "BILLIARDS_RELAY_SECRET": SECRET}
        command = [sys.executable, "-m", "server.cli", "serve", "--port", str(self.port)]
        command += ["--redis", redis_url, "--workers", "1", "--db", str(directory / "unused")]
        self.log = open(directory / f"replica-{self.port}.log", "wb")  # noqa: SIM115
        self.process = subprocess.Popen(command, env=env, stdout=self.log, stderr=self.log)

    async def wait_ready(self, http: aiohttp.ClientSession) -> None:
        deadline = time.monotonic() + START_TIMEOUT_S
        while time.monotonic() < deadline:
            assert self.process.poll() is None, "replica exited"
            try:
                async with http.get(f"{self.url}/api/tables") as response:
                    if response.status == 200:
                        return
            except aiohttp.ClientError:
                pass
            await asyncio.sleep(0.1)
        raise RuntimeError(f"replica on port {self.port} did not start")

    def stop(self) -> None:
        if self.process.poll() is not None:
            self.log.close()
            return
        self.process.terminate()
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self.log.close()


@pytest.fixture
def replicas(redis_url: str, tmp_path: Path) -> Iterator[list[Replica]]:
    started = [Replica(redis_url, tmp_path) for _ in range(2)]
    yield started
    for replica in started:
        replica.stop()


@pytest.fixture
async def http() -> AsyncIterator[aiohttp.ClientSession]:
    async with aiohttp.ClientSession() as session:
        yield session


async def call(
    http: aiohttp.ClientSession,
    method: str,
    url: str,
    token: str | None = None,
    body: Any = None,
) -> tuple[int, Any]:
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    async with http.request(method, url, json=body, headers=headers) as response:
        return response.status, await response.json()


async def seat_across(
    replicas: list[Replica], http: aiohttp.ClientSession
) -> tuple[str, str, dict, dict, dict]:
    """Ada on replica A creates a nine-ball table, Bob on replica B joins it."""
    for replica in replicas:
        await replica.wait_ready(http)
    a, b = (replica.url for replica in replicas)
    _, ada = await call(http, "POST", f"{a}/api/players", body={"name": "Ada"})
    _, bob = await call(http, "POST", f"{b}/api/players", body={"name": "Bob"})
    _, table = await call(http, "POST", f"{a}/api/tables", ada["token"], {"game": "nineball"})
    status, view = await call(http, "POST", f"{b}/api/tables/{table['id']}/join", bob["token"])
    assert status == 200 and view["status"] == "playing"
    return a, b, ada, bob, view


async def test_two_replicas_referee_each_shot_exactly_once(
    replicas: list[Replica], http: aiohttp.ClientSession
) -> None:
    a, b, ada, bob, view = await seat_across(replicas, http)
    status, _ = await call(http, "POST", f"{b}/api/players", body={"name": "ada"})
    assert status == 409  # one name space across replicas
    feeds = [
        await http.ws_connect(f"{url}/sub/{view['channel']}", protocols=("ws+meta.nchan",))
        for url in (a, b)
    ]
    tokens = {ada["player"]["id"]: ada["token"], bob["player"]["id"]: bob["token"]}
    for _ in range(6):
        token = tokens[view["next"]["player"]]
        action = picked(view)
        intents = [
            {"version": view["version"], "shot_id": uuid.uuid4().hex, "input": action}
            for _ in (a, b)
        ]
        answers = await asyncio.gather(
            *(
                call(http, "POST", f"{url}/api/tables/{view['id']}/intents", token, intent)
                for url, intent in zip((a, b), intents, strict=True)
            )
        )
        statuses = sorted(status for status, _ in answers)
        assert statuses == [202, 409], answers  # the same move sent to both: played once
        outcomes = []
        for feed in feeds:
            while True:
                frame = await asyncio.wait_for(feed.receive(), 30)
                message = frame.data.split("\n\n", 1)[1]
                if json.loads(message)["kind"] == "outcome":
                    outcomes.append(json.loads(message))
                    break
        assert outcomes[0] == outcomes[1]  # both replicas deliver the one outcome
        assert outcomes[0]["version"] == view["version"] + 1  # and nothing twice
        _, view = await call(http, "GET", f"{b}/api/tables/{view['id']}")
        assert view["last_outcome"]["shot_id"] in {i["shot_id"] for i in intents}
        if view["status"] != "playing":
            break


async def test_a_dead_replica_stalls_no_match(
    replicas: list[Replica], http: aiohttp.ClientSession, redis_url: str
) -> None:
    _, b, ada, bob, view = await seat_across(replicas, http)
    replicas[0].process.kill()  # replica A dies; B carries on alone

    # An input A had accepted but not played (stored as A would have stored it) is played by
    # B once the lease has run out, on the next request B serves for the table.
    storage = await RedisStorage.open(redis_url)
    try:
        await abandon_input(storage, view, "accepted-by-a")
    finally:
        await storage.close()
    feed = await http.ws_connect(f"{b}/sub/{view['channel']}", protocols=("ws+meta.nchan",))
    status, _ = await call(http, "POST", f"{b}/api/tables/{view['id']}/heartbeat", bob["token"])
    assert status == 200
    while True:
        frame = await asyncio.wait_for(feed.receive(), 30)
        message = json.loads(frame.data.split("\n\n", 1)[1])
        if message["kind"] == "outcome":
            break
    assert (message["shot_id"], message["version"]) == ("accepted-by-a", view["version"] + 1)
    _, after = await call(http, "GET", f"{b}/api/tables/{view['id']}")
    token = {ada["player"]["id"]: ada["token"], bob["player"]["id"]: bob["token"]}[
        after["next"]["player"]
    ]
    intent = {"version": after["version"], "shot_id": uuid.uuid4().hex, "input": picked(after)}
    status, ack = await call(http, "POST", f"{b}/api/tables/{view['id']}/intents", token, intent)
    assert (status, ack["version"]) == (202, after["version"] + 1)

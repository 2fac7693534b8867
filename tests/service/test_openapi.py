"""schemathesis over the served OpenAPI description: every operation, every check, no 5xx.

One setting differs from schemathesis's defaults: a request that fits the schema may still be
refused with `422 illegal_input`, because the referee judges what no schema can say (a tip
offset past the miscue circle, a shot out of turn at this point of the game), so 422 joins
the statuses that well-formed requests may get; and `413 body_too_large` counts as refusing
a malformed request (an over-long array is both).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest
import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.config import SchemathesisConfig

from server.http.openapi import openapi_document
from tests.redis_server import free_port

CONFIG = SchemathesisConfig.from_str(
    """
[checks.positive_data_acceptance]
expected-statuses = ["2xx", "3xx", "401", "403", "404", "409", "422", "429"]

[checks.negative_data_rejection]
expected-statuses = [
    "400", "401", "403", "404", "405", "406", "409", "413", "415", "422", "428", "429",
]
"""
)
schema = schemathesis.openapi.from_dict(openapi_document(), config=CONFIG)


def _get(url: str) -> bytes:
    with urllib.request.urlopen(url, timeout=5) as response:
        return response.read()


@pytest.fixture(scope="module")
def live(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, dict[str, str]]]:
    """A real `billiards serve` process, and the Authorization header of a registered player."""
    directory: Path = tmp_path_factory.mktemp("openapi")
    port = free_port()
    command = [sys.executable, "-m", "server.cli", "serve", "--port", str(port)]
    command += ["--db", str(directory / "game.sqlite3"), "--workers", "1"]
    log = open(directory / "server.log", "wb")  # noqa: SIM115
    process = subprocess.Popen(command, stdout=log, stderr=log, env=os.environ.copy())
    url = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + 30
    while True:
        try:
            _get(f"{url}/api/tables")
            break
        except OSError:
            assert process.poll() is None and time.monotonic() < deadline, "server did not start"
            time.sleep(0.1)
    request = urllib.request.Request(
        f"{url}/api/players",
        data=json.dumps({"name": "Fuzzer"}).encode(),
        headers={"Content-Type": "application/json"},
    )
    with urllib.request.urlopen(request, timeout=5) as response:
        token = json.loads(response.read())["token"]
    try:
        yield url, {"Authorization": f"Bearer {token}"}
    finally:
        process.terminate()
        process.wait(timeout=10)
        log.close()


def test_the_served_description_is_the_one_tested(live: tuple[str, dict[str, str]]) -> None:
    url, _ = live
    assert json.loads(_get(f"{url}/api/openapi.json")) == json.loads(json.dumps(openapi_document()))


@schema.parametrize()
@settings(max_examples=30, deadline=None, suppress_health_check=list(HealthCheck))
def test_every_operation_keeps_its_description(
    case: schemathesis.Case, live: tuple[str, dict[str, str]]
) -> None:
    url, auth = live
    case.call_and_validate(base_url=url, headers=auth)

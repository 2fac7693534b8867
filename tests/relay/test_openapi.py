"""The served OpenAPI description tells the truth: schemathesis finds no difference.

schemathesis (its command line, as a developer would run it) generates requests for every
operation from `/openapi.json` of a real relay process and runs every check on the answers:
status codes, content types, schemas, refusal of invalid input, acceptance of valid input,
authentication. The publisher token it sends is a server token, so publishes and deletes are
really carried out. A fixed seed keeps the run the same on every machine.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from server.relay.auth import TokenAuthority
from tests.relay.conftest import SECRET
from tests.relay.process import RelayProcess

CONFIG = Path(__file__).with_name("schemathesis.toml")
SCHEMATHESIS = Path(sys.executable).with_name("schemathesis")
SEED = "20261201"


def test_schemathesis_finds_the_description_and_the_behaviour_alike(tmp_path: Path) -> None:
    token = TokenAuthority(SECRET.encode(), "public-").issue("schemathesis", [], 3600, server=True)
    with RelayProcess(None, longpoll_timeout=0.05) as server:
        run = subprocess.run(
            [
                str(SCHEMATHESIS),
                "--config-file",
                str(CONFIG),
                "run",
                f"http://127.0.0.1:{server.port}/openapi.json",
                "--checks",
                "all",
                "--max-examples",
                "100",
                "--seed",
                SEED,
                "--workers",
                "1",
                "-H",
                f"Authorization: Bearer {token}",
            ],
            capture_output=True,
            text=True,
            timeout=600,
            cwd=tmp_path,  # schemathesis keeps a cache of its findings in the working directory
        )
    report = run.stdout + run.stderr
    assert run.returncode == 0, report[-6000:]
    assert "Selected: 5/5" in report and "Tested: 5" in report

"""A server process run under valgrind's callgrind, whose instruction counters the benches
zero and dump around a window of load (bench/relay_instructions.py,
bench/match_instructions.py): a count of the work done that the machine's speed does not
sway, where CPU time on a shared machine swings by a third between runs of the same code.

Only the process started is counted: callgrind does not follow a program it starts (the game
service's simulation workers, started by a fork server that is a new program, run at full
speed, uncounted).
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

_TOTALS = re.compile(r"^(?:summary|totals):\s+(\d+)", re.MULTILINE)


def available() -> bool:
    return shutil.which("valgrind") is not None and shutil.which("callgrind_control") is not None


class Callgrind:
    """`command` running under callgrind, its counts dumped into `directory`."""

    def __init__(self, command: list[str], directory: Path, env: dict[str, str] | None = None):
        self.directory = directory
        self.process = subprocess.Popen(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={directory}/cg.%p", *command],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=env,
        )
        self.dumps = 0

    def _control(self, flag: str) -> None:
        subprocess.run(
            ["callgrind_control", flag, str(self.process.pid)], check=True, capture_output=True
        )

    def zero(self) -> None:
        self._control("-z")

    def dump(self) -> int:
        """Dump the counters since the last zero; the instructions counted."""
        self._control("-d")
        self.dumps += 1
        text = self.last_dump.read_text()
        found = _TOTALS.search(text)
        if found is None:
            raise RuntimeError("callgrind's dump has no totals")
        return int(found[1])

    @property
    def last_dump(self) -> Path:
        return self.directory / f"cg.{self.process.pid}.{self.dumps}"

    def stop(self) -> None:
        self.process.terminate()
        self.process.wait()

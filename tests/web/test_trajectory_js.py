"""web/src/lib/trajectory.js, run by Node: the browser's evaluation of a shot's segments gives
the engine's positions, and its rotation turns a rolling ball by the distance it rolled."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
from pathlib import Path

import pytest

import physics
from physics.examples import nineball_break, snooker_break_off

MODULE = Path(__file__).resolve().parents[2] / "web" / "src" / "lib" / "trajectory.js"

#: Reads {segments: {ball: [...]}, times: [...]} on stdin; prints each ball's positions, and the
#: rotation angle and axis between each pair of consecutive times.
SCRIPT = """
import { positionAt, rotationBetween } from %s;
let text = "";
for await (const chunk of process.stdin) text += chunk;
const { balls, times } = JSON.parse(text);
const out = {};
for (const [id, segments] of Object.entries(balls)) {
  out[id] = {
    positions: times.map((t) => positionAt(segments, t)),
    turns: times.slice(1).map((t, i) => rotationBetween(segments, times[i], t)),
  };
}
console.log(JSON.stringify(out));
"""


def wire(shot: physics.Shot) -> dict[str, list[list]]:
    """The segments as docs/protocol.md puts them on the wire."""
    return {
        ball: [[s.t, s.state, *s.r, *s.v, *s.a, *s.w, *s.dw] for s in segments]
        for ball, segments in shot.trajectories.items()
    }


def run_js(balls: dict, times: list[float]) -> dict:
    node = shutil.which("node")
    assert node, "node is missing: `bash dev.sh test` installs Debian's npm (and node)"
    result = subprocess.run(
        [node, "--input-type=module", "-e", SCRIPT % json.dumps(MODULE.as_uri())],
        input=json.dumps({"balls": balls, "times": times}),
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(result.stdout)


@pytest.mark.parametrize("scene", [nineball_break(), snooker_break_off()], ids=["nine", "snooker"])
def test_positions_are_the_engines(scene):
    shot = physics.simulate(scene)
    times = [shot.duration * k / 200 for k in range(201)]
    js = run_js(wire(shot), times)
    for ball in shot.trajectories:
        for t, got in zip(times, js[ball]["positions"], strict=True):
            want = shot.position(ball, t)
            if want is None:  # pocketed: the client keeps the capture point for its drop
                want = shot.trajectories[ball][-1].r
            assert got == pytest.approx(want, abs=1e-12), (ball, t)
    for ball, final in shot.final.items():
        if final.pos is not None:
            assert js[ball]["positions"][-1] == pytest.approx(final.pos, abs=1e-12)


def test_a_rolling_ball_turns_by_the_distance_it_rolls():
    R = 0.028575
    scene = {
        "table": {"preset": "three_cushion", "w": 40.0, "l": 40.0},
        "params": {"R": R},
        "balls": {"cue": [20.0, 1.0]},
        "initial": {"cue": {"v": [0.0, 1.5], "w": [-1.5 / R, 0.0, 0.0]}},
    }
    shot = physics.simulate(scene)
    rolling = next(s for s in shot.trajectories["cue"] if s.state == "rolling")
    t0, t1 = rolling.t + 0.1, rolling.t + 0.15  # under half a turn: the angle is unambiguous
    js = run_js(wire(shot), [t0, t1])["cue"]
    (x0, y0), (x1, y1) = js["positions"]
    qx, qy, qz, qw = js["turns"][0]
    angle = 2 * math.atan2(math.hypot(qx, qy, qz), qw)
    assert angle == pytest.approx(math.hypot(x1 - x0, y1 - y0) / R, rel=1e-6)
    # Rolling along +y turns the ball about -x (the engine's frame, z up).
    assert qx < 0 and abs(qy) < 1e-9 and abs(qz) < 1e-9

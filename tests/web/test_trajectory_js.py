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


#: Reads {balls, events} on stdin; prints eventSpeed of each event.
SPEEDS = """
import { eventSpeed } from %s;
let text = "";
for await (const chunk of process.stdin) text += chunk;
const { balls, events } = JSON.parse(text);
console.log(JSON.stringify(events.map((e) => eventSpeed(balls, e))));
"""


def run_js(balls: dict, times: list[float]) -> dict:
    return node(SCRIPT, {"balls": balls, "times": times})


def node(script: str, payload: dict):
    """What `script` (an ES module importing trajectory.js as %s) prints for `payload`."""
    node = shutil.which("node")
    assert node, "node is missing: `bash dev.sh test` installs Debian's npm (and node)"
    result = subprocess.run(
        [node, "--input-type=module", "-e", script % json.dumps(MODULE.as_uri())],
        input=json.dumps(payload),
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


def test_event_speeds_are_the_balls_speeds_at_the_event():
    """eventSpeed (the sounds' loudness): the cue ball's speed after the strike, two balls'
    relative speed before their contact, a ball's speed before a cushion or a pocket; checked
    against the engine's positions by finite differences, away from other events."""
    shot = physics.simulate(nineball_break())
    events = [e.model_dump() for e in shot.events]
    got = node(SPEEDS, {"balls": wire(shot), "events": events})
    h = 1e-6

    def velocity(ball: str, t: float) -> tuple[float, float]:
        (x0, y0), (x1, y1) = shot.position(ball, t - h), shot.position(ball, t + h)
        return ((x1 - x0) / (2 * h), (y1 - y0) / (2 * h))

    def alone(e, gap: float = 1e-4) -> bool:
        return not any(
            o is not e and abs(o.t - e.t) < gap and set(o.balls) & set(e.balls) for o in shot.events
        )

    checked = set()
    for e, speed in zip(shot.events, got, strict=True):
        if e.type == "strike":
            want = math.hypot(*velocity(e.balls[0], e.t + 1e-4))
        elif e.type in ("ball_ball", "ball_cushion", "ball_pocket") and alone(e):
            v = velocity(e.balls[0], e.t - 1e-4)
            w = velocity(e.balls[1], e.t - 1e-4) if e.type == "ball_ball" else (0.0, 0.0)
            want = math.hypot(v[0] - w[0], v[1] - w[1])
        else:
            continue
        assert speed == pytest.approx(want, rel=0.02, abs=0.01), e
        checked.add(e.type)
    assert {"strike", "ball_ball", "ball_cushion"} <= checked

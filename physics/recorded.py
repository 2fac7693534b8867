"""Recorded shots from a real carom table: their format, their frame, and a first guess.

A recording is a JSON list of shots `{"id": N, "balls": {name: {"t": [...], "x": [...],
"y": [...]}}}`: each ball's tracked centre over time, sampled separately per ball, in the
recording's own frame (origin at the table's centre, x along the length). docs/physics.md
("Recorded shots") gives the evidence for the frame and scale used here: the recording's
units are a UMB match table scaled up by `SCALE`, so a recorded length divided by `SCALE`
is metres on the engine's `three_cushion` table.

The first guess of the strike (`kinematic_guess`) comes from the cue ball's first moving
samples, before anything can have deflected it: its direction and speed, and when it left.
"""

from __future__ import annotations

import gzip
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from physics.params import CAROM, Params
from physics.tables import THREE_CUSHION

#: Recorded units per metre of a match table: the recording's ball-centre limits are
#: 45.18 R by 22.09 R with R = 0.03275, a match table's the same multiples of 0.03075 m.
SCALE = 0.03275 / 0.03075

#: How far (recorded units) a ball must be from its first sample to count as moving: the
#: tracker's positions are rounded to 1e-3.
MOVED = 0.004

#: How many of the cue ball's first moving samples the kinematic guess uses (at 50 Hz, the
#: first 0.1 s: less than a ball at 1 m/s needs to cross a fifth of the table).
FIRST_SAMPLES = 5


@dataclass(frozen=True)
class Track:
    """One ball's recorded samples: times (s) and positions in table metres (engine frame)."""

    t: np.ndarray
    xy: np.ndarray  # shape (n, 2)


@dataclass(frozen=True)
class Recording:
    """One recorded shot in the engine's frame: the cue ball's name and every ball's track."""

    id: int
    cue: str
    tracks: dict[str, Track]

    def start(self) -> dict[str, tuple[float, float]]:
        """Each ball's first recorded position."""
        return {k: (float(tr.xy[0, 0]), float(tr.xy[0, 1])) for k, tr in self.tracks.items()}


def to_table(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Recorded (x along the length, y across, origin at the centre) to the engine's frame
    (x across the width, y along the length, origin at a corner), in metres: a quarter turn,
    so that handedness (and the sign of side spin) is kept."""
    w, l = THREE_CUSHION.w, THREE_CUSHION.l
    return np.column_stack((w / 2 - np.asarray(y) / SCALE, l / 2 + np.asarray(x) / SCALE))


def from_table(xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The engine's frame back to the recording's: the inverse of `to_table`."""
    w, l = THREE_CUSHION.w, THREE_CUSHION.l
    xy = np.asarray(xy, dtype=float)
    return (xy[:, 1] - l / 2) * SCALE, (w / 2 - xy[:, 0]) * SCALE


def parse(shot: dict) -> Recording:
    """One shot of the recording format; the cue ball is the one whose second sample comes
    first (the ball that moves first)."""
    tracks = {}
    for name, b in shot["balls"].items():
        t = np.asarray(b["t"], dtype=float)
        tracks[str(name)] = Track(t, to_table(b["x"], b["y"]))
    cue = min(tracks, key=lambda k: (tracks[k].t[1] if len(tracks[k].t) > 1 else math.inf, k))
    return Recording(int(shot["id"]), cue, tracks)


def load(path: str | Path) -> list[Recording]:
    """Every shot of a recording file (gzip-compressed when its name ends in .gz)."""
    data = Path(path).read_bytes()
    if Path(path).suffix == ".gz":
        data = gzip.decompress(data)
    return [parse(s) for s in json.loads(data)]


@dataclass(frozen=True)
class Guess:
    """What the cue ball's first samples say: when it left (s), its heading (degrees from
    +x) and its speed (m/s) just after the strike."""

    t0: float
    heading: float
    speed: float


def kinematic_guess(rec: Recording) -> Guess:
    """The cue ball's straight start: a line (position and velocity) fitted to its first
    moving samples, its heading and speed, and the time the line passes the start position.

    The sliding ball decelerates by u_s g (about 2 m/s^2) over these 0.1 s, so the speed is
    that of the middle of the fit; the least-squares strike fit takes it from there.
    """
    tr = rec.tracks[rec.cue]
    moved = np.hypot(*(tr.xy - tr.xy[0]).T) > MOVED / SCALE
    first = int(np.argmax(moved)) if moved.any() else 1
    t = tr.t[first : first + FIRST_SAMPLES]
    xy = tr.xy[first : first + FIRST_SAMPLES]
    if len(t) < 2:
        return Guess(0.0, 90.0, 1.0)
    (vx, x0), (vy, y0) = np.polyfit(t, xy[:, 0], 1), np.polyfit(t, xy[:, 1], 1)
    speed = max(math.hypot(vx, vy), 0.05)
    # When the fitted line is nearest the start position: the moment of the strike.
    sx, sy = tr.xy[0]
    t0 = ((sx - x0) * vx + (sy - y0) * vy) / (speed * speed)
    t0 = min(max(t0, 0.0), float(t[0]))
    return Guess(t0, math.degrees(math.atan2(vy, vx)), speed)


def cue_speed(ball_speed: float, params: Params = CAROM) -> float:
    """The cue speed that sends the ball off at `ball_speed` from a centre hit
    (physics.cue: v = 2 V / (1 + m / m_cue))."""
    return ball_speed * (1.0 + params.m / params.m_cue) / 2.0

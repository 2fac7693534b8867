"""Alterations a hostile client might make to a genuine record, to try a verifier with.

Each alteration keeps the record well-formed and keeps what it claims (digests stay aligned
with the inputs they follow, the final result is untouched unless that is the alteration), so
only replaying can tell: `rules.record.replay` must refuse every one. The tests and
bench/records.py try them on self-played games.
"""

from __future__ import annotations

import random
from collections.abc import Callable

from physics.cue import MAX_SPEED
from rules.inputs import Shot
from rules.record import Final, GameRecord

Alteration = Callable[[GameRecord, random.Random], GameRecord | None]


def _shots(record: GameRecord) -> list[int]:
    return [k for k, a in enumerate(record.inputs) if isinstance(a, Shot)]


def _with_input(record: GameRecord, k: int, action) -> GameRecord:
    inputs = list(record.inputs)
    inputs[k] = action
    return record.model_copy(update={"inputs": tuple(inputs)})


def _nudge_strike(record: GameRecord, k: int, **delta: float) -> GameRecord:
    shot = record.inputs[k]
    s = shot.strike
    moved = {f: getattr(s, f) + d for f, d in delta.items()}
    strike = s.model_validate({**s.model_dump(), **moved})
    return _with_input(record, k, shot.model_copy(update={"strike": strike}))


def heading_last(record: GameRecord, rng: random.Random) -> GameRecord | None:
    """The last shot's heading changed by 0.01 degree."""
    shots = _shots(record)
    return _nudge_strike(record, shots[-1], heading=0.01) if shots else None


def heading_any(record: GameRecord, rng: random.Random) -> GameRecord | None:
    """A random shot's heading changed by 0.01 degree either way."""
    shots = _shots(record)
    if not shots:
        return None
    return _nudge_strike(record, rng.choice(shots), heading=rng.choice((-0.01, 0.01)))


def speed_any(record: GameRecord, rng: random.Random) -> GameRecord | None:
    """A random shot's speed changed by 1 mm/s (kept within the bounds)."""
    shots = [k for k in _shots(record) if record.inputs[k].strike.speed > 0.002]
    if not shots:
        return None
    k = rng.choice(shots)
    up = record.inputs[k].strike.speed + 0.001 <= MAX_SPEED and rng.random() < 0.5
    return _nudge_strike(record, k, speed=0.001 if up else -0.001)


def place_any(record: GameRecord, rng: random.Random) -> GameRecord | None:
    """A placed cue ball moved by 0.1 mm along one axis."""
    placed = [k for k in _shots(record) if record.inputs[k].place is not None]
    if not placed:
        return None
    k = rng.choice(placed)
    shot = record.inputs[k]
    axis, step = rng.choice((0, 1)), rng.choice((-1e-4, 1e-4))
    place = list(shot.place)
    place[axis] += step
    return _with_input(record, k, Shot.model_validate({**shot.model_dump(), "place": place}))


def _reorder(record: GameRecord, order: list[int]) -> GameRecord:
    inputs = tuple(record.inputs[k] for k in order)
    digests = tuple(record.digests[k] for k in order)
    return record.model_copy(update={"inputs": inputs, "digests": digests})


def drop_one(record: GameRecord, rng: random.Random) -> GameRecord | None:
    """One input (and its digest) left out."""
    n = len(record.inputs)
    if n < 2:
        return None
    gone = rng.randrange(n)
    return _reorder(record, [k for k in range(n) if k != gone])


def swap_two(record: GameRecord, rng: random.Random) -> GameRecord | None:
    """Two different inputs (and their digests) swapped."""
    n = len(record.inputs)
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    pairs = [(i, j) for i, j in pairs if record.inputs[i] != record.inputs[j]]
    if not pairs:
        return None
    i, j = rng.choice(pairs)
    order = list(range(n))
    order[i], order[j] = j, i
    return _reorder(record, order)


def result_claimed(record: GameRecord, rng: random.Random) -> GameRecord | None:
    """The final scores swapped and the winner changed, inputs untouched."""
    f = record.final
    winner = None if f.winner is None else 1 - f.winner
    claimed = Final(scores=(f.scores[1], f.scores[0]), winner=winner, digest=f.digest)
    if claimed == f:
        return None
    return record.model_copy(update={"final": claimed})


ALTERATIONS: dict[str, Alteration] = {
    "heading of the last shot +0.01 deg": heading_last,
    "heading of a shot +-0.01 deg": heading_any,
    "speed of a shot +-1 mm/s": speed_any,
    "placement moved 0.1 mm": place_any,
    "one input dropped": drop_one,
    "two inputs swapped": swap_two,
    "final result changed": result_claimed,
}

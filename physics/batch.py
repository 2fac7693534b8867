"""Many shots at once over every core: the bot's candidate shots, a server's queue.

The engine holds the GIL while it runs, so the batch goes to worker processes: one pool per
worker count, started on first use (with "spawn", safe beside threads and event loops) and
kept for the next batch, since starting a worker (importing the package) costs far more than a
shot. Each worker runs the same engine as the caller (the kernel or, under
BILLIARDS_PURE_PYTHON, the pure-Python engine: the variable is inherited).

What crosses between the processes is kept to what the other side needs, since a short shot
costs the kernel about a tenth of a millisecond and pickling a Scene, or a Shot's records,
costs a fifth of that again on each side (a parent that did this for every shot would hold
the batch to one core). The batch goes in chunks of at most CHUNK scenes, each sent as one
bytes object that holds each distinct table (its numbers, the balls' and cloth's constants,
the models) once and then only each scene's own numbers (`_pack`); each comes back as one
bytes object of the shots' records, the trajectories left out when the caller does not want
them, and the Shots are built from those only when read (`Shots`).
"""

from __future__ import annotations

import atexit
import multiprocessing
import os
import pickle
from collections.abc import Sequence
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Any, overload

from physics import records
from physics.engine import Simulation
from physics.scene import Motion, Scene, Strike, parse_scene
from physics.trajectory import Shot

#: The most scenes in one chunk. The workers take chunks as they become free, so a batch ends
#: evenly when each worker gets several (at most a chunk's time apart); a chunk's round trip
#: costs about as much as one short shot, so 64 of them make it a few per cent.
CHUNK = 64

_pools: dict[int, ProcessPoolExecutor] = {}


def _pool(workers: int) -> ProcessPoolExecutor:
    if workers not in _pools:
        context = multiprocessing.get_context("spawn")
        _pools[workers] = ProcessPoolExecutor(workers, mp_context=context)
    return _pools[workers]


@atexit.register
def _shutdown() -> None:
    for pool in _pools.values():
        pool.shutdown(cancel_futures=True)
    _pools.clear()


def simulate_many(
    scenes: Sequence[Scene | dict[str, Any]],
    workers: int | None = None,
    *,
    trajectories: bool = True,
) -> Shots:
    """Simulate every scene, in order, on `workers` processes (None: one per core).

    The results are those of `simulate` one by one, in the order of `scenes` (as `Shots`, a
    sequence); the first scene that fails (SceneError, BudgetExceeded) raises, as it would
    alone. With one worker, or one scene, the shots run in this process. With
    `trajectories=False` each Shot comes without its trajectories (an empty dict): its events
    and final positions, all that a referee reads of a shot, come back at a fifth of the cost.
    """
    if workers is None:
        workers = os.cpu_count() or 1
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    n = len(scenes)
    if workers == 1 or n <= 1:
        return Shots([_records(scenes, trajectories)], max(1, n), n)
    size = min(CHUNK, max(1, -(-n // (4 * workers))))  # at least four chunks per worker
    pool = _pool(workers)
    futures: list[Future[bytes]] = []
    try:
        with records.PausedCollector():
            for k in range(0, n, size):  # each sent as soon as packed: the workers start at once
                futures.append(
                    pool.submit(_simulate_chunk, _pack(scenes[k : k + size]), trajectories)
                )
        parts: list[bytes | list[records.ShotRecord]] = [f.result() for f in futures]
    finally:
        for f in futures:
            f.cancel()  # after a failure, the chunks not started yet (no-op for those done)
    return Shots(parts, size, n)


class Shots(Sequence[Shot]):
    """A batch's shots, in order, each built from its records when first read.

    Building a Shot's models costs the process that reads it a third of what simulating it
    cost; done for every shot as it arrived from the workers, that work in the calling process
    would hold the whole batch to little more than one core. Once read, a shot is kept.
    """

    def __init__(self, parts: list[bytes | list[records.ShotRecord]], size: int, n: int) -> None:
        # Lists of `size` shot records (the last may be shorter), pickled when from a worker.
        self._parts = parts
        self._size = size
        self._shots: list[Shot | None] = [None] * n

    def __len__(self) -> int:
        return len(self._shots)

    @overload
    def __getitem__(self, k: int) -> Shot: ...
    @overload
    def __getitem__(self, k: slice) -> list[Shot]: ...

    def __getitem__(self, k: int | slice) -> Shot | list[Shot]:
        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self)))]
        shot = self._shots[k]  # raises IndexError as a list does
        if shot is None:
            k %= len(self._shots)
            part, at = divmod(k, self._size)
            with records.PausedCollector():
                if isinstance(self._parts[part], bytes):
                    self._parts[part] = pickle.loads(self._parts[part])
                shot = self._shots[k] = records.shot(*self._parts[part][at])
        return shot


def _records(
    scenes: Sequence[Scene | dict[str, Any]], trajectories: bool
) -> list[records.ShotRecord]:
    """The shots of `scenes` as records, no models built (simulate's checks, in order).

    Without trajectories, each record has an empty dict in their place. The records of shots
    on the same table share one ModelsUsed (equal ones, kept as the first), which pickles
    once per chunk instead of once per shot.
    """
    shared: dict[Any, Any] = {}
    out = []
    with records.PausedCollector():
        for s in scenes:
            r = Simulation(s if isinstance(s, Scene) else parse_scene(s)).run_records()
            models = shared.setdefault(r[4], r[4])
            out.append((r[0], r[1] if trajectories else {}, r[2], r[3], models))
    return out


def _simulate_chunk(packed: bytes, trajectories: bool) -> bytes:
    """A worker's chunk of a batch: its shots' records, pickled (the collector paused)."""
    with records.PausedCollector():
        return pickle.dumps(_records(_unpack(packed), trajectories), pickle.HIGHEST_PROTOCOL)


def _pack(scenes: Sequence[Scene | dict[str, Any]]) -> bytes:
    """Scenes as one bytes object: each distinct table once, then each scene's own numbers.

    A table is the triple (TableSpec, Params, Models), which pickles as its numbers (found
    by identity first: the scenes of one preset share their objects); a scene is the index of
    its table, its ball names and positions, and the field values of its strike, the
    strike's motion and its initial motions (None where absent). A scene document (a dict)
    goes as it is, to be parsed and checked in the worker.
    """
    by_id: dict[tuple[int, int, int], int] = {}
    tables: dict[tuple[Any, ...], int] = {}
    items: list[tuple[Any, ...] | dict[str, Any]] = []
    for s in scenes:
        if not isinstance(s, Scene):
            items.append(s)
            continue
        ids = (id(s.geometry), id(s.params), id(s.models))  # the scenes keep them alive
        table = by_id.get(ids)
        if table is None:
            key = (s.geometry.spec, s.params, s.models)
            table = by_id[ids] = tables.setdefault(key, len(tables))
        st, sm = s.strike, s.strike_motion
        items.append(
            (
                table,
                tuple(s.positions),
                tuple(s.positions.values()),
                None if st is None else st.__dict__,
                None if sm is None else sm.__dict__,
                tuple([(name, m.__dict__) for name, m in s.initial.items()]),
            )
        )
    return pickle.dumps((list(tables), items), pickle.HIGHEST_PROTOCOL)


def _unpack(packed: bytes) -> list[Scene | dict[str, Any]]:
    """The scenes of `_pack`, equal to those packed (their models built with every field set,
    as `records.trusted` builds them: the values come from validated scenes)."""
    table_list, items = pickle.loads(packed)
    tables = [(spec.geometry(), params, models) for spec, params, models in table_list]
    scenes: list[Scene | dict[str, Any]] = []
    for item in items:
        if isinstance(item, dict):
            scenes.append(item)
            continue
        table, names, positions, st, sm, initial = item
        geometry, params, models = tables[table]
        scenes.append(
            Scene(
                geometry,
                params,
                models,
                dict(zip(names, positions, strict=True)),
                {name: records.trusted(Motion, m, set(_MOTION_FIELDS)) for name, m in initial},
                None if st is None else records.trusted(Strike, st, set(_STRIKE_FIELDS)),
                None if sm is None else records.trusted(Motion, sm, set(_MOTION_FIELDS)),
            )
        )
    return scenes


_STRIKE_FIELDS = frozenset(Strike.model_fields)
_MOTION_FIELDS = frozenset(Motion.model_fields)

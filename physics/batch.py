"""Many shots at once over every core: the bot's candidate shots, a server's queue.

The engine holds the GIL while it runs, so the batch goes to worker processes: one pool per
worker count, started on first use (with "spawn", safe beside threads and event loops) and
kept for the next batch, since starting a worker (importing the package) costs far more than a
shot. Each worker runs the same engine as the caller (the kernel or, under
BILLIARDS_PURE_PYTHON, the pure-Python engine: the variable is inherited).
"""

from __future__ import annotations

import atexit
import multiprocessing
import os
import pickle
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import Any, overload

from physics import records
from physics.engine import Simulation
from physics.scene import Scene, parse_scene
from physics.trajectory import Shot

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


def simulate_many(scenes: Sequence[Scene | dict[str, Any]], workers: int | None = None) -> Shots:
    """Simulate every scene, in order, on `workers` processes (None: one per core).

    The results are those of `simulate` one by one, in the order of `scenes` (as `Shots`, a
    sequence); the first scene that fails (SceneError, BudgetExceeded) raises, as it would
    alone. With one worker, or one scene, the shots run in this process.
    """
    if workers is None:
        workers = os.cpu_count() or 1
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    if workers == 1 or len(scenes) <= 1:
        return Shots([_records(scenes)], max(1, len(scenes)), len(scenes))
    size = max(1, len(scenes) // (4 * workers))
    chunks = [scenes[k : k + size] for k in range(0, len(scenes), size)]
    return Shots(list(_pool(workers).map(_simulate_chunk, chunks)), size, len(scenes))


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


def _records(scenes: Sequence[Scene | dict[str, Any]]) -> list[records.ShotRecord]:
    """The shots of `scenes` as records, no models built (simulate's checks, in order)."""
    with records.PausedCollector():
        return [
            Simulation(s if isinstance(s, Scene) else parse_scene(s)).run_records() for s in scenes
        ]


def _simulate_chunk(scenes: Sequence[Scene | dict[str, Any]]) -> bytes:
    """A worker's part of a batch: its shots' records, pickled (the collector paused)."""
    with records.PausedCollector():
        return pickle.dumps(_records(scenes), pickle.HIGHEST_PROTOCOL)

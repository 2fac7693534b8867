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
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from typing import Any

from physics.scene import Scene
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


def simulate_many(
    scenes: Sequence[Scene | dict[str, Any]], workers: int | None = None
) -> list[Shot]:
    """Simulate every scene, in order, on `workers` processes (None: one per core).

    The results are those of `simulate` one by one, in the order of `scenes`; the first scene
    that fails (SceneError, BudgetExceeded) raises, as it would alone. With one worker, or one
    scene, the shots run in this process.
    """
    from physics import simulate  # the package imports this module

    if workers is None:
        workers = os.cpu_count() or 1
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    if workers == 1 or len(scenes) <= 1:
        return [simulate(scene) for scene in scenes]
    chunk = max(1, len(scenes) // (4 * workers))
    return list(_pool(workers).map(simulate, scenes, chunksize=chunk))

"""The other engine, in a worker process: the compiled kernel and the pure-Python engine
cannot share one interpreter (a module is imported once), so a test compares what this process
computes with what a spawned worker running the other path computes for the same scene."""

from __future__ import annotations

import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from typing import Any

from physics import SimulationError, kernel, parse_scene
from physics.engine import Simulation
from physics.scene import SceneError

#: What a scene comes to: ("shot", msgpack of the whole Shot, contacts checked, quartics
#: solved, cushion steps) or ("error", exception type, message). Every field must match.
Outcome = tuple[Any, ...]


def outcome(scene: dict[str, Any]) -> Outcome:
    """Simulate on this process's engine; everything the shot produced, or its failure."""
    try:
        sim = Simulation(parse_scene(scene))
        shot = sim.run()
    except (SceneError, SimulationError) as exc:
        return ("error", type(exc).__name__, str(exc))
    return (
        "shot",
        shot.to_msgpack(),
        sim.contacts_checked,
        sim.quartics_solved,
        *sim.cushion_steps,
    )


def engine_name() -> str:
    return "compiled" if kernel.compiled() else "python"


@contextmanager
def other_engine():
    """A one-worker pool running the path this process does not: its `outcome` and name."""
    before = os.environ.get(kernel.PURE_ENV)
    os.environ[kernel.PURE_ENV] = "0" if kernel.pure_requested() else "1"
    pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"))
    try:
        pool.submit(engine_name).result()  # started while the variable is set
    finally:
        if before is None:
            del os.environ[kernel.PURE_ENV]
        else:
            os.environ[kernel.PURE_ENV] = before
    try:
        yield pool
    finally:
        pool.shutdown()

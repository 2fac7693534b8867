"""Event-based billiards physics: a scene in, the events and exact trajectories of a shot out.

`simulate_scene(scene_dict)` is the whole engine behind `billiards simulate`; `simulate`
returns the full `Shot` (with per-ball piecewise-polynomial trajectories) for callers that want
more than the summary; `simulate_many` runs a batch of scenes over every core.
"""

from __future__ import annotations

from typing import Any

from physics import kernel

if kernel.pure_requested():
    kernel.use_source()

from physics.batch import simulate_many
from physics.engine import BudgetExceeded, Simulation, SimulationError
from physics.scene import Scene, SceneError, parse_scene, scene_from_json
from physics.trajectory import Shot

#: Bumped whenever a change to the engine changes the outcome of any shot. A game record or a
#: leaderboard claim names the version it was played with; another version cannot replay it.
ENGINE_VERSION = "4"

__all__ = [
    "ENGINE_VERSION",
    "BudgetExceeded",
    "Scene",
    "SceneError",
    "Shot",
    "SimulationError",
    "parse_scene",
    "scene_from_json",
    "simulate",
    "simulate_many",
    "simulate_scene",
]


def simulate(scene: Scene | dict[str, Any]) -> Shot:
    """Simulate one shot until every ball is at rest or pocketed."""
    if not isinstance(scene, Scene):
        scene = parse_scene(scene)
    return Simulation(scene).run()


def simulate_scene(scene: dict[str, Any]) -> dict[str, Any]:
    """Simulate a scene dictionary and return the JSON-ready summary (events, final, duration)."""
    return simulate(scene).summary()

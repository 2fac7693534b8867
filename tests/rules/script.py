"""Scripted shots: an engine stand-in that replays a hand-written event list.

Each rule test sets up a position, describes what the shot did as events (the engine's output
format), and asserts the referee's decision. Balls not pocketed stay where they were unless
`moved` says otherwise.
"""

from __future__ import annotations

from rules.game import REFEREES, play
from rules.inputs import Shot, Strike
from rules.state import Decision, State


def hit(a: str, b: str) -> dict:
    return {"type": "ball_ball", "balls": [a, b]}


def rail(ball: str, cushion: str = "left_top") -> dict:
    return {"type": "ball_cushion", "balls": [ball], "cushion": cushion}


def jaw(ball: str, pocket: str = "top_left") -> dict:
    return {"type": "ball_jaw", "balls": [ball], "cushion": f"{pocket}_x", "pocket": pocket}


def pot(ball: str, pocket: str = "top_left") -> dict:
    return {"type": "ball_pocket", "balls": [ball], "pocket": pocket}


def scripted(events: list[dict], moved: dict | None = None):
    """A `simulate` function that returns `events` (timed in order) for any scene."""

    def simulate(scene: dict) -> dict:
        final = {
            b: {"pos": list(p), "state": "stationary", "pocket": None}
            for b, p in scene["balls"].items()
        }
        timed = [{"t": 0.0, "type": "strike", "balls": [scene["strike"]["ball"]]}]
        for i, ev in enumerate(events):
            timed.append({"t": 0.1 * (i + 1), **ev})
            if ev["type"] == "ball_pocket":
                for b in ev["balls"]:
                    final[b] = {"pos": None, "state": "pocketed", "pocket": ev["pocket"]}
        for b, p in (moved or {}).items():
            final[b]["pos"] = list(p)
        return {"events": timed, "final": final, "duration": 0.1 * (len(events) + 1)}

    return simulate


def shoot(
    state: State, *events: dict, moved: dict | None = None, **shot_fields
) -> tuple[State, Decision]:
    """Play a scripted shot by the player to move (struck with their own cue ball)."""
    cue = REFEREES[state.game].cue_ball(state)
    shot = Shot(strike=Strike(ball=cue, speed=2.0, heading=90.0), **shot_fields)
    new, decision = play(state, shot, scripted(list(events), moved))
    assert decision is not None
    return new, decision

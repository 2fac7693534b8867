"""Scripted shots: an engine stand-in that replays a hand-written event list.

Each rule test sets up a position, describes what the shot did as events, and asserts the
referee's decision. The stand-in takes the engine's validated scene and returns the engine's
typed `physics.Shot`, as the real engine does. Balls not pocketed stay where they were unless
`moved` says otherwise.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import pytest

import physics
from physics.trajectory import BallFinal, Event, ModelsUsed
from rules.codes import FoulCode, NoteCode, Refusal, RuleError
from rules.game import play
from rules.inputs import Shot, Strike
from rules.referee import referee
from rules.state import Decision, Foul, Note, State


def hit(a: str, b: str) -> dict:
    return {"type": "ball_ball", "balls": (a, b)}


def rail(ball: str, cushion: str = "left_top") -> dict:
    return {"type": "ball_cushion", "balls": (ball,), "cushion": cushion}


def jaw(ball: str, pocket: str = "top_left") -> dict:
    return {"type": "ball_jaw", "balls": (ball,), "cushion": f"{pocket}_x", "pocket": pocket}


def pot(ball: str, pocket: str = "top_left") -> dict:
    return {"type": "ball_pocket", "balls": (ball,), "pocket": pocket}


def scripted(events: list[dict], moved: dict | None = None):
    """A `simulate` function that returns `events` (timed in order) for any scene."""

    def simulate(scene: physics.Scene) -> physics.Shot:
        final = {b: BallFinal(pos=p, state="stationary") for b, p in scene.positions.items()}
        timed = [Event(t=0.0, type="strike", balls=(scene.strike.ball,))]
        for i, ev in enumerate(events):
            timed.append(Event(t=0.1 * (i + 1), **ev))
            if ev["type"] == "ball_pocket":
                for b in ev["balls"]:
                    final[b] = BallFinal(state="pocketed", pocket=ev["pocket"])
        for b, p in (moved or {}).items():
            final[b] = BallFinal(pos=p, state="stationary")
        return physics.Shot(
            events=timed,
            trajectories={},
            final=final,
            duration=0.1 * (len(events) + 1),
            models=ModelsUsed(),
        )

    return simulate


def shoot(
    state: State, *events: dict, moved: dict | None = None, **shot_fields
) -> tuple[State, Decision]:
    """Play a scripted shot by the player to move (struck with their own cue ball)."""
    cue = referee(state.game).cue_ball(state)
    shot = Shot(strike=Strike(ball=cue, speed=2.0, heading=90.0), **shot_fields)
    outcome = play(state, shot, scripted(list(events), moved))
    assert outcome.decision is not None
    return outcome.state, outcome.decision


def codes(said: tuple[Foul, ...] | tuple[Note, ...]) -> tuple[FoulCode | NoteCode, ...]:
    """The codes of a decision's fouls or notes, in order: what the tests assert."""
    return tuple(s.code for s in said)


@contextmanager
def refused(code: Refusal) -> Iterator[None]:
    """Expect a RuleError with `code` (the code is what is asserted, not the words)."""
    with pytest.raises(RuleError) as caught:
        yield
    assert caught.value.code == code, caught.value

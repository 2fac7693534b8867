"""A game as data: its setup and the players' inputs, and the replay that rebuilds every state.

The engine is deterministic and the referees are pure, so a record of a few hundred bytes per
shot stands for the whole game: the match server and the leaderboard verify a claimed result
or break by replaying the record and reading the states, never by trusting a client.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field

from physics import ENGINE_VERSION
from rules.game import Setup, Simulate, default_simulate, play, start
from rules.inputs import PlayerInput
from rules.state import Decision, RuleError, State

#: More inputs than any real game needs: a record this long is refused, not replayed.
MAX_INPUTS = 5000


class GameRecord(BaseModel):
    """Rule set, rack seed and options (`setup`), then every input in the order played."""

    model_config = ConfigDict(extra="forbid")

    setup: Setup
    inputs: Annotated[list[PlayerInput], Field(max_length=MAX_INPUTS)] = []

    def to_json(self) -> str:
        """Compact JSON: fields at their defaults are left out."""
        return self.model_dump_json(exclude_defaults=True)

    @classmethod
    def from_json(cls, text: str | bytes) -> GameRecord:
        return cls.model_validate_json(text)


class Step(BaseModel):
    """One input, the referee's decision if it was a shot, and the state it led to."""

    model_config = ConfigDict(frozen=True)

    action: PlayerInput
    decision: Decision | None
    state: State


class Replay(BaseModel):
    start: State
    steps: list[Step]

    @property
    def final(self) -> State:
        return self.steps[-1].state if self.steps else self.start


def replay(record: GameRecord, simulate: Simulate = default_simulate) -> Replay:
    """Play the record's inputs from its rack; raises RuleError at the first illegal input,
    or at once for a record played under another engine version (it would not replay)."""
    if record.setup.engine != ENGINE_VERSION:
        raise RuleError(
            f"record played with engine {record.setup.engine}, this is engine {ENGINE_VERSION}"
        )
    state = first = start(record.setup)
    steps = []
    for action in record.inputs:
        state, decision = play(state, action, simulate)
        steps.append(Step(action=action, decision=decision, state=state))
    return Replay(start=first, steps=steps)

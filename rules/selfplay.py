"""Self-play: two copies of the simple picker play a game to its end (or a cap on inputs)."""

from __future__ import annotations

import physics
from rules.game import Setup, Simulate, play, start
from rules.pickers import pick
from rules.record import GameRecord, Replay, Step


def selfplay(
    setup: Setup, max_inputs: int = 400, simulate: Simulate = physics.simulate
) -> tuple[GameRecord, Replay]:
    """Play until the game is over or `max_inputs` inputs were made; the record and its steps."""
    state = first = start(setup)
    record = GameRecord.begin(setup, first)
    steps = []
    while not state.over and len(steps) < max_inputs:
        action = pick(state, simulate)
        outcome = play(state, action, simulate)
        state = outcome.state
        record = record.extend(action, state)
        steps.append(Step(action=action, decision=outcome.decision, state=state))
    return record, Replay(start=first, steps=steps)

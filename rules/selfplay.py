"""Self-play: two copies of the simple picker play a game to its end (or a cap on inputs)."""

from __future__ import annotations

from rules.game import Setup, Simulate, default_simulate, play, start
from rules.pickers import pick
from rules.record import GameRecord, Replay, Step


def selfplay(
    setup: Setup, max_inputs: int = 400, simulate: Simulate = default_simulate
) -> tuple[GameRecord, Replay]:
    """Play until the game is over or `max_inputs` inputs were made; the record and its steps."""
    state = first = start(setup)
    inputs, steps = [], []
    while not state.over and len(inputs) < max_inputs:
        action = pick(state, simulate)
        state, decision = play(state, action, simulate)
        inputs.append(action)
        steps.append(Step(action=action, decision=decision, state=state))
    return GameRecord(setup=setup, inputs=inputs), Replay(start=first, steps=steps)

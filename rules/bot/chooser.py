"""Choosers: whatever picks a player's next input, behind one small interface.

A `Chooser` takes the state and returns the input for the player to act, canonical and
accepted by the referee's `check`, exactly as a person's client would send it; the arena, the
game service's bot seats and `billiards play --bot` all take one, built from a name by
`chooser`:

- "picker": the simple shot pickers (rules.pickers), no search;
- "bot:N": the searching bot at level N (rules.bot.levels); "bot": the strongest level;
- "mcts": the search baseline of the course and contest agents (rules.bot.mcts).

A bot is deterministic for its seed: the same seed and state give the same input (the search
and the level's own execution noise are both drawn from streams keyed by the seed and the
state). `close` releases worker processes, if the chooser has any.

A chooser does no I/O and never touches an event loop: the game service calls `choose` in
one of its worker processes (a `Bot` is cheap to keep per process and per level; with
`workers` > 1 it starts worker processes of its own, which a worker process may do), and a
client such as `billiards play --bot` calls it between two messages.
"""

from __future__ import annotations

import math
from typing import Protocol, runtime_checkable

import physics
from rules.bot.levels import STRONGEST, Level, level
from rules.bot.mcts import Mcts
from rules.bot.noise import draws, perturb, tournament
from rules.bot.search import Evaluator, InProcess, Report, Workers, search, state_key
from rules.bot.value import choice_values
from rules.game import Simulate
from rules.inputs import OPTIONS, Choice, PlayerInput
from rules.pickers import pick
from rules.referee import table_of
from rules.state import State


@runtime_checkable
class Chooser(Protocol):
    name: str

    def choose(self, state: State) -> PlayerInput: ...

    def close(self) -> None: ...


class Picker:
    """The simple shot pickers as a chooser."""

    def __init__(self, simulate: Simulate = physics.simulate) -> None:
        self.name = "picker"
        self.simulate = simulate

    def choose(self, state: State) -> PlayerInput:
        return pick(state, self.simulate)

    def close(self) -> None:
        pass


class Bot:
    """The searching bot at `level`, seeded.

    expect: the execution noise (a factor of the tournament noise) the bot expects the table to
    add to its own hand; it plans under both together. workers: the worker processes its
    search uses (1: none, it searches in this process with `simulate`). `last` holds the
    report of the latest search.
    """

    def __init__(
        self,
        level: Level = STRONGEST,
        seed: int = 0,
        *,
        expect: float = 1.0,
        workers: int = 1,
        simulate: Simulate = physics.simulate,
    ) -> None:
        self.name = f"bot:{level.number}"
        self.level = level
        self.seed = seed
        self.hand = tournament(level.hand)
        self.plan = tournament(math.hypot(level.hand, expect))
        self.simulate = simulate
        self.evaluator: Evaluator = Workers(workers) if workers > 1 else InProcess(simulate)
        self.last: Report | None = None

    def choose(self, state: State) -> PlayerInput:
        if state.pending:
            values = choice_values(state, self.plan, self.level.rival)
            best = max((o for o in OPTIONS if o in values), key=lambda o: values[o])
            return Choice(option=best)
        shot, self.last = search(
            state, self.level, self.seed, self.plan, self.evaluator, self.simulate
        )
        draw = draws(self.seed, 1, "hand", state_key(state))[0]
        return perturb(shot, self.hand, draw, table_of(state).R)

    def close(self) -> None:
        self.evaluator.close()


def chooser(name: str, seed: int = 0, *, expect: float = 1.0, workers: int = 1) -> Chooser:
    """The chooser called `name` ("picker", "bot" or "bot:N"), seeded with `seed`.

    expect: the execution noise factor a searching chooser plans under. Raises ValueError for
    any other name."""
    if name == "picker":
        return Picker()
    if name == "mcts":
        return Mcts(seed, noise=expect)
    if name == "bot":
        return Bot(STRONGEST, seed, expect=expect, workers=workers)
    kind, _, number = name.partition(":")
    if kind == "bot" and number.isdigit():
        return Bot(level(int(number)), seed, expect=expect, workers=workers)
    raise ValueError(f"unknown chooser {name!r}: picker, mcts, bot or bot:N")

"""A search baseline built the way course and contest agents build one: UCB over a fixed set of
discretised shots, each tried by playouts under the table's noise.

Published search baselines for computer pool (the Monte Carlo tree search agents of the
pooltool-based university contests, and before them the sampling agents of the computational
pool tournaments) share one shape, which `Mcts` follows so that beating it says what beating
the pickers cannot (the pickers aim once and never simulate):

- **A discretised set of shots.** Ghost-ball pots at the likeliest legal balls and pockets,
  from where the cue ball lies or from a few ball-in-hand places, at three speeds and centre
  ball; banks and combinations; contacts at the nearest legal balls when no pot is on; the
  break from the head string. The set comes from the bot's own candidate generator
  (`rules.bot.candidates`) with `BASELINE_STROKES`, cut to the first `ACTIONS` in its
  likeliest-first order.
- **`PLAYOUTS` playouts per decision.** Each plays one action once through the engine and the
  referee under the execution noise the arena applies (a fresh error draw per playout) and
  scores the result with an immediate `reward` in [0, 1]: the game won or lost, a foul, the
  turn kept, balls or points scored.
- **UCB1 at the root.** Every action is tried once in order, then each playout goes to the
  action with the highest mean reward plus `EXPLORATION` * sqrt(ln N / n); the most-tried
  action is played (ties: the higher mean, then the earlier action).

It looks one shot ahead and values only what that shot did: no position play, and no safety
beyond "the opponent did not get ball in hand", which is what the bot's search adds
(rules.bot.search, rules.bot.value). Choices after a push-out or a foul are the pickers'.
Deterministic for its seed and the position, like the bot.
"""

from __future__ import annotations

import math
import time

import physics
from rules.bot.candidates import Strokes, candidates
from rules.bot.levels import Level
from rules.bot.noise import Draw, draws, tournament
from rules.bot.search import Report, played_under, state_key
from rules.game import Outcome, Simulate
from rules.inputs import PlayerInput, Shot
from rules.pickers import pick
from rules.racks import Game
from rules.state import State

#: Playouts per decision, as in the contest baselines.
PLAYOUTS = 50
#: The discrete shots considered (the likeliest first).
ACTIONS = 24
#: UCB1's exploration constant for rewards in [0, 1].
EXPLORATION = math.sqrt(2)
#: How pots and contacts are discretised: three speeds, centre ball; contacts soft and firm.
BASELINE_STROKES = Strokes((0.8, 1.0, 1.3), ((0.0, 0.0),), ((1.5, 0.0), (3.0, 0.0)))
#: The candidate generator's knobs: the five likeliest straight pots; the screen sizes
#: three-cushion's fan of headings.
BASELINE_LEVEL = Level(0, 0.0, 5, ACTIONS, 0, 0, 0, 0)


def reward(before: State, outcome: Outcome) -> float:
    """An immediate reward in [0, 1] for the shot that led from `before` to `outcome`: 1 won,
    0 lost, 0.1 a foul, else 0.3, plus 0.3 when the player keeps the table and 0.1 per ball
    (pool) or point scored, up to 0.9."""
    me = before.turn
    state = outcome.state
    if state.over:
        return 1.0 if state.winner == me else 0.0
    decision = outcome.decision
    if decision is None or decision.fouls:
        return 0.1
    if before.game in (Game.NINEBALL, Game.EIGHTBALL):
        scored = len(decision.pocketed)
    else:
        scored = state.scores[me] - before.scores[me]
    kept = 0.3 if state.turn == me else 0.0
    return min(0.9, 0.3 + kept + 0.1 * scored)


def _ucb(total: float, tries: int, playouts: int) -> float:
    return total / tries + EXPLORATION * math.sqrt(math.log(playouts) / tries)


class Mcts:
    """The baseline as a chooser (rules.bot.chooser.Chooser), seeded."""

    def __init__(self, seed: int = 0, *, noise: float = 1.0, simulate: Simulate = physics.simulate):
        self.name = "mcts"
        self.seed = seed
        self.noise = tournament(noise)
        self.simulate = simulate
        self.last: Report | None = None

    def _playout(self, state: State, shot: Shot, draw: Draw) -> float:
        outcome = played_under(state, shot, self.noise, draw, self.simulate)
        return 0.0 if outcome is None else reward(state, outcome)

    def search(self, state: State) -> PlayerInput:
        """The most-tried of the discrete shots after PLAYOUTS playouts chosen by UCB1."""
        start = time.monotonic()
        found = candidates(state, BASELINE_LEVEL, BASELINE_STROKES)
        cands = found[:ACTIONS]
        if not cands:
            return pick(state, self.simulate)
        stream = draws(self.seed, PLAYOUTS, "mcts", state_key(state))
        tries = [0] * len(cands)
        totals = [0.0] * len(cands)
        for n, draw in enumerate(stream):
            if n < len(cands):
                i = n
            else:
                i = max(range(len(cands)), key=lambda k: _ucb(totals[k], tries[k], n))
            tries[i] += 1
            totals[i] += self._playout(state, cands[i].shot, draw)
        mean = [t / max(k, 1) for t, k in zip(totals, tries, strict=True)]
        best = max(range(len(cands)), key=lambda k: (tries[k], mean[k], -k))
        seconds = time.monotonic() - start
        self.last = Report(
            len(found), len(cands), PLAYOUTS, 1, False, seconds, cands[best].kind, mean[best]
        )
        return cands[best].shot

    def choose(self, state: State) -> PlayerInput:
        if state.pending:
            return pick(state, self.simulate)
        return self.search(state)

    def close(self) -> None:
        pass

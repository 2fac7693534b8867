"""Whole games between two choosers under the same execution noise, and what they show.

`arena` plays `games` games of one rule set between choosers "a" and "b", alternating the
break (a breaks the even-numbered games), each game racked from seed + its number. Every shot
a chooser sends is checked by the referee as it is (a refusal is a bug and stops the arena),
then perturbed by the arena's noise (rules.bot.noise, drawn from the arena's seed, the game and
the input number) and played: the noise belongs to the table, not to the player, so both sides
suffer it alike, and the whole arena is reproducible from its seed.

Per side it counts wins (with a 95% Wilson interval), visits (a player's turn at the table,
from coming to the table to leaving it) and what they scored (object balls legally pocketed
in pool, points in snooker and three-cushion), run-outs (games whose winner had a single
visit, the break included when they broke), the highest visit, each decision's time and, for
a searching bot, the simulations each shot's search ran (the cost that does not depend on the
machine: a faster engine divides the time, not this).
"""

from __future__ import annotations

import math
import statistics
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field

from rules.bot.chooser import Chooser
from rules.bot.losses import Loss, Turn, classify
from rules.bot.noise import Noise, draws, perturb
from rules.bot.search import Report
from rules.codes import RuleError
from rules.game import Setup, check, play, start
from rules.inputs import Shot
from rules.racks import Game
from rules.referee import table_of
from rules.state import Decision, State

#: Normal quantile of a two-sided 95% interval.
Z95 = 1.959963984540054


def wilson(wins: int, n: int) -> tuple[float, float]:
    """The 95% Wilson score interval of a win rate of wins out of n (0..1 when n is 0)."""
    if n == 0:
        return (0.0, 1.0)
    p = wins / n
    centre = p + Z95 * Z95 / (2 * n)
    spread = Z95 * math.sqrt(p * (1 - p) / n + Z95 * Z95 / (4 * n * n))
    den = 1 + Z95 * Z95 / n
    return ((centre - spread) / den, (centre + spread) / den)


@dataclass(slots=True)
class Side:
    """What one chooser did over the arena."""

    name: str
    wins: int = 0
    visits: int = 0
    scored: int = 0
    run_outs: int = 0
    highest: int = 0
    times: list[float] = field(default_factory=list)
    simulations: list[int] = field(default_factory=list)
    losses: Counter[str] = field(default_factory=Counter)

    def summary(self, games: int) -> dict:
        times = sorted(self.times)
        p95 = times[min(len(times) - 1, math.ceil(0.95 * len(times)) - 1)] if times else 0.0
        lo, hi = wilson(self.wins, games)
        return {
            "name": self.name,
            "wins": self.wins,
            "ci95": [round(lo, 4), round(hi, 4)],
            "per_visit": round(self.scored / self.visits, 4) if self.visits else 0.0,
            "run_outs": self.run_outs,
            "highest": self.highest,
            "decision_mean_s": round(statistics.fmean(times), 4) if times else 0.0,
            "decision_median_s": round(statistics.median(times), 4) if times else 0.0,
            "decision_p95_s": round(p95, 4),
            "decisions": len(times),
            "simulations_mean": round(statistics.fmean(self.simulations), 1)
            if self.simulations
            else 0.0,
            "losses": dict(self.losses.most_common()),
        }


def scored_by(state: State, decision: Decision) -> int:
    """What a shot scored for its player: object balls legally pocketed (pool), or points."""
    if decision.fouls:
        return 0
    if state.game in (Game.NINEBALL, Game.EIGHTBALL):
        return len(decision.pocketed)
    return decision.points[decision.player]


@dataclass(slots=True)
class _Visit:
    seat: int
    scored: int = 0


@dataclass(slots=True)
class GameResult:
    winner: int | None  # the seat that won, None when the game hit the input cap
    inputs: int
    loss: Loss | None = None  # why the loser lost, when the game ended


def play_game(
    setup: Setup,
    seats: tuple[Side, Side],
    choosers: tuple[Chooser, Chooser],
    noise: Noise,
    seed: int,
    number: int,
    max_inputs: int,
    clock: Callable[[], float] = time.perf_counter,
) -> GameResult:
    """One game; `seats[k]` and `choosers[k]` play seat k (seat 0 breaks)."""
    state = start(setup)
    R = table_of(state).R
    visits: list[_Visit] = [_Visit(state.turn)]
    turns: list[Turn] = []
    for n in range(max_inputs):
        if state.over:
            break
        seat = state.turn
        t0 = clock()
        action = choosers[seat].choose(state)
        seats[seat].times.append(clock() - t0)
        report = getattr(choosers[seat], "last", None)
        searched = isinstance(action, Shot) and isinstance(report, Report)
        if searched:
            seats[seat].simulations.append(report.simulations)
        try:
            check(state, action)
        except RuleError as exc:
            raise RuntimeError(f"{choosers[seat].name} sent a refused input: {exc}") from exc
        if isinstance(action, Shot):
            action = perturb(action, noise, draws(seed, 1, "arena", number, n)[0], R)
        before = state
        outcome = play(state, action)
        turns.append(Turn(seat, action, report.kind if searched else None, outcome.decision))
        state = outcome.state
        if outcome.decision is not None:
            visits[-1].scored += scored_by(before, outcome.decision)
        if not state.over and state.turn != visits[-1].seat:
            visits.append(_Visit(state.turn))
    for v in visits:
        seats[v.seat].visits += 1
        seats[v.seat].scored += v.scored
        seats[v.seat].highest = max(seats[v.seat].highest, v.scored)
    winner = state.winner if state.over else None
    if winner is None:
        return GameResult(None, n + 1)
    seats[winner].wins += 1
    loss = classify(turns, 1 - winner)
    seats[1 - winner].losses[loss] += 1
    if sum(1 for v in visits if v.seat == winner) == 1:
        seats[winner].run_outs += 1
    return GameResult(winner, n + 1, loss)


def arena(
    game: Game,
    a: Chooser,
    b: Chooser,
    games: int,
    seed: int,
    noise: Noise,
    *,
    target: int = 0,
    max_inputs: int = 400,
    progress: Callable[[int, GameResult, Side, Side], None] | None = None,
) -> dict:
    """Play the games and return the summary `{"games", "unfinished", "a": {...}, "b": {...}}`."""
    sides = (Side(a.name), Side(b.name))
    unfinished = 0
    for i in range(games):
        flip = i % 2 == 1
        seats = (sides[1], sides[0]) if flip else sides
        choosers = (b, a) if flip else (a, b)
        setup = Setup(game=game, seed=seed + i, target=target)
        result = play_game(setup, seats, choosers, noise, seed, i, max_inputs)
        unfinished += result.winner is None
        if progress is not None:
            progress(i, result, *sides)
    return {
        "game": str(game),
        "games": games,
        "unfinished": unfinished,
        "a": sides[0].summary(games),
        "b": sides[1].summary(games),
    }

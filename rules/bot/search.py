"""The search: candidates simulated under execution noise, judged by the referee.

One decision runs in stages, each a fixed number of simulations set by the level:

1. Candidates (rules.bot.candidates), cut to the level's `screen`. Each pot is first played
   once without noise and its heading corrected for the throw the engine gave the object ball
   (the ghost-ball aim ignores it), by the change of heading that turns the contact line by the
   error seen: dθ = dψ · 2R cos(cut) / d1.
2. Screen: every candidate played once without noise and valued (rules.bot.value); the best
   `width` go on.
3. Samples: each of those played `samples` times under the noise, then the best `leaders`
   `leader_samples` times more; the best mean wins (ties: the earlier candidate).

Sample k of every candidate uses the same k-th error draw (common random numbers), so the
comparison between two candidates is not blurred by luck, and the draws come from a stream
keyed by the bot's seed and the position (rules.bot.noise.draws): a decision is a function of
the position, the level and the seed, whatever the worker count or the machine. Only the
wall-clock `cap` of a level, a safety limit, can cut a search short between stages; the report
says when it did.

Simulations are batched as `Task`s and run by an `Evaluator`: in this process (with any
engine stand-in) or across worker processes, whose results come back in task order.
"""

from __future__ import annotations

import hashlib
import math
import time
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace
from typing import Protocol

import physics
from rules.bot.candidates import Candidate, Kind, Strokes, candidates
from rules.bot.levels import Level
from rules.bot.noise import Draw, Noise, draws, perturb
from rules.bot.value import KEEP_SURE, WIN, outcome_value
from rules.game import Outcome, Simulate, play, scene, shot_position
from rules.inputs import Shot
from rules.referee import table_of
from rules.state import State

#: The error draw of a shot played as meant.
EXACT: Draw = (0.0, 0.0, 0.0, 0.0, 0.0)
#: Largest object-ball direction error (degrees) taken for throw; more is some other failure
#: (a kiss, another ball first) that a heading tweak would not mend.
MAX_THROW = 3.0


@dataclass(frozen=True, slots=True)
class Task:
    """Play `shot` in `state` once per draw, perturbed by `noise`, and value each outcome
    (the opponent's table priced with `rival`, rules.bot.value)."""

    state: State
    shot: Shot
    draws: tuple[Draw, ...]
    noise: Noise
    rival: float = KEEP_SURE


def played_under(
    state: State, shot: Shot, noise: Noise, draw: Draw, simulate: Simulate = physics.simulate
) -> Outcome | None:
    """`shot` as a hand with `noise` plays it in `state` under the error `draw`: its outcome,
    or None when the engine fails on it (a search values that as a loss)."""
    played = perturb(shot, noise, draw, table_of(state).R)
    try:
        return play(state, played, simulate)
    except physics.SimulationError:
        return None


def run_task(task: Task, simulate: Simulate = physics.simulate) -> tuple[float, ...]:
    """The value of each play of a task; a shot the engine fails on is valued as a loss."""
    values = []
    for d in task.draws:
        outcome = played_under(task.state, task.shot, task.noise, d, simulate)
        if outcome is None:
            values.append(-WIN)
        else:
            values.append(outcome_value(task.state, outcome, task.noise, task.rival))
    return tuple(values)


class Evaluator(Protocol):
    def run(self, tasks: list[Task]) -> list[tuple[float, ...]]: ...

    def close(self) -> None: ...


class InProcess:
    """Runs tasks here, with any engine (tests pass stand-ins that count or script shots)."""

    def __init__(self, simulate: Simulate = physics.simulate) -> None:
        self.simulate = simulate

    def run(self, tasks: list[Task]) -> list[tuple[float, ...]]:
        return [run_task(t, self.simulate) for t in tasks]

    def close(self) -> None:
        pass


class Workers:
    """Runs tasks across `n` worker processes (the real engine), results in task order."""

    def __init__(self, n: int) -> None:
        self.n = n
        self._pool = ProcessPoolExecutor(max_workers=n)

    def run(self, tasks: list[Task]) -> list[tuple[float, ...]]:
        chunk = max(1, math.ceil(len(tasks) / (4 * self.n)))
        return list(self._pool.map(run_task, tasks, chunksize=chunk))

    def close(self) -> None:
        self._pool.shutdown()


def state_key(state: State) -> str:
    """A digest of the position and everything else in the state: the search's noise key."""
    return hashlib.sha256(state.model_dump_json().encode()).hexdigest()[:16]


def _departure(result: physics.Shot, ball: str) -> float | None:
    """The direction (radians) in which `ball` first moved, if it did."""
    for seg in result.trajectories.get(ball, ()):
        if seg.v != (0.0, 0.0):
            return math.atan2(seg.v[1], seg.v[0])
    return None


def throw_corrected(state: State, c: Candidate, simulate: Simulate) -> Candidate:
    """A pot with its heading corrected for the throw seen in one exact simulation; as it is
    when the engine fails on that simulation (the search then values its plays)."""
    pot = c.pot
    balls = shot_position(state, c.shot)
    try:
        moved = _departure(simulate(scene(state, c.shot, balls)), pot.target)
    except physics.SimulationError:
        return c
    if moved is None:
        return c
    at = state.balls[pot.target]
    want = math.atan2(at[1] - pot.ghost[1], at[0] - pot.ghost[0])
    error = math.remainder(moved - want, math.tau)
    if abs(math.degrees(error)) > MAX_THROW:
        return c
    R = table_of(state).R
    turn = math.degrees(error * 2 * R * pot.cos_cut / pot.d1)
    strike = c.shot.strike.model_validate(
        {**dict(c.shot.strike), "heading": c.shot.strike.heading + turn}
    )
    return replace(c, shot=c.shot.model_copy(update={"strike": strike}))


@dataclass(frozen=True, slots=True)
class Report:
    """How one decision went: candidates found and screened, simulations run, the noisy
    stages completed, whether the wall-clock cap cut it short, the time taken, and the chosen
    shot's kind and mean value."""

    candidates: int
    screened: int
    simulations: int
    stages: int
    capped: bool
    seconds: float
    kind: Kind
    value: float


@dataclass(slots=True)
class _Tally:
    values: list[float]

    @property
    def mean(self) -> float:
        return sum(self.values) / len(self.values)


def _best(tallies: dict[int, _Tally], among: list[int]) -> int:
    return max(among, key=lambda i: (tallies[i].mean, -i))


def search(
    state: State,
    level: Level,
    seed: int,
    noise: Noise,
    evaluator: Evaluator,
    simulate: Simulate = physics.simulate,
    clock: Callable[[], float] = time.monotonic,
    *,
    strokes: Strokes | None = None,
) -> tuple[Shot, Report]:
    """The best shot for the player to shoot in `state` (no choice pending), and the report.
    strokes: how pots and contacts are varied (default: the level's set, rules.bot.candidates)."""
    start = clock()
    found = candidates(state, level, strokes)
    cands = [throw_corrected(state, c, simulate) if c.pot else c for c in found[: level.screen]]
    sims = sum(1 for c in cands if c.pot)
    rival = level.rival
    screened = evaluator.run([Task(state, c.shot, (EXACT,), noise, rival) for c in cands])
    sims += len(cands)
    tallies = {i: _Tally(list(v)) for i, v in enumerate(screened)}
    among = sorted(tallies, key=lambda i: (-tallies[i].mean, i))[: level.width]
    stream = draws(seed, level.samples + level.leader_samples, "search", state_key(state))
    stages, capped = 0, False
    plan = ((level.width, stream[: level.samples]), (level.leaders, stream[level.samples :]))
    for n, batch in plan:
        if n == 0 or not batch:
            break
        if clock() - start > level.cap:
            capped = True
            break
        among = sorted(among, key=lambda i: (-tallies[i].mean, i))[:n]
        if stages == 0:
            for i in among:
                tallies[i] = _Tally([])
        tasks = [Task(state, cands[i].shot, tuple(batch), noise, rival) for i in among]
        results = evaluator.run(tasks)
        for i, v in zip(among, results, strict=True):
            tallies[i].values.extend(v)
        sims += len(among) * len(batch)
        stages += 1
    pick = _best(tallies, among)
    report = Report(
        len(found),
        len(cands),
        sims,
        stages,
        capped,
        clock() - start,
        cands[pick].kind,
        tallies[pick].mean,
    )
    return cands[pick].shot, report

"""The strongest level's pot strokes against richer sets: what more variations buy.

    .venv/bin/python bench/strokes.py [--positions N] [--from SEED] [--judge K] [--jobs J]

Whole games say whether the bot wins more, but a few hundred of them cannot show a change of
a percent or two (two versions' games diverge at their first different choice), and the bot's
figures against the pickers are that close to their bar. This bench asks a narrower question
with far less noise. On N random nine-ball and N random eight-ball positions (bench/runouts.py's,
from seed --from on), the strongest level decides with each set of pot strokes below, and each
chosen shot is played K times on error draws of its own, none of which the search saw, and
valued as the search values outcomes (rules.bot.value). The figure per set is the mean of that
value over the positions, less the first set's on the same positions, with its standard error
(paired by position), beside how many decisions changed, the median decision time (one
process) and the mean simulations a decision.

The sets differ only in how each straight pot is varied (`Strokes.pot_speeds` and
`pot_spins`); contacts, kicks, banks and the break are the same in all:

- `5 speeds, 5 spins`: the strongest level's own (rules.bot.candidates.FINE): speeds 0.6-1.6
  times the pot's own, and draw, stun, follow, running and check side;
- `7 speeds`: besides, half and twice the pot's speed (0.65 for 0.6);
- `9 spins`: besides, side with follow and side with draw (a quarter of a radius each way);
- `7 speeds, 9 spins`: both.

Every set is searched with the level's screen widened to `SCREEN`, which holds the eight
likeliest pots' 63 variations of the richest set with the banks, combinations and a safety
after them (the level's own 500 would cut the safeties off in such a position).

The value is the bot's own judgement of where a shot leaves the table, so a set that finds
better shots by it has still to win games; README.md ("More strokes") says what the richest
set did in games, and why the level keeps its own.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.runouts import positions
from rules.bot.candidates import FINE, Strokes
from rules.bot.levels import STRONGEST
from rules.bot.noise import Draw, draws, tournament
from rules.bot.search import InProcess, Task, run_task, search, state_key
from rules.inputs import Shot
from rules.racks import Game
from rules.state import State

SPEEDS = (0.5, 0.65, 0.8, 1.0, 1.25, 1.6, 2.0)
SPINS = (*FINE.pot_spins, (0.25, -0.25), (0.25, 0.25), (-0.25, -0.25), (-0.25, 0.25))
#: The sets compared, the first (the level's own) the reference.
SETS: dict[str, Strokes] = {
    "5 speeds, 5 spins": FINE,
    "7 speeds": replace(FINE, pot_speeds=SPEEDS),
    "9 spins": replace(FINE, pot_spins=SPINS),
    "7 speeds, 9 spins": replace(FINE, pot_speeds=SPEEDS, pot_spins=SPINS),
}
#: The screen every set is searched with: 8 pots x 63 variations, the banks and combinations,
#: and room for contacts.
SCREEN = 560
LEVEL = replace(STRONGEST, screen=SCREEN)
#: The seed of the search (the bot's own) and of the judging draws.
SEARCH_SEED, JUDGE_SEED = 0, 777


def judged(state: State, shot: Shot, judging: tuple[Draw, ...]) -> float:
    """The mean value of `shot` over plays on the `judging` draws (none the search saw), the
    opponent's table priced as the level prices it."""
    return statistics.fmean(run_task(Task(state, shot, judging, tournament(1.0), LEVEL.rival)))


def decide(job: tuple[State, int]) -> list[tuple[float, float, int, str]]:
    """For each set: (judged value, seconds, simulations, chosen shot's JSON) on one position,
    every set's choice judged on the same draws."""
    state, plays = job
    judging = tuple(draws(JUDGE_SEED, plays, "judge", state_key(state)))
    out = []
    for strokes in SETS.values():
        t0 = time.process_time()
        shot, report = search(
            state, LEVEL, SEARCH_SEED, tournament(1.0), InProcess(), strokes=strokes
        )
        seconds = time.process_time() - t0
        value = judged(state, shot, judging)
        out.append((value, seconds, report.simulations, shot.model_dump_json()))
    return out


def rows(game: Game, results: list[list[tuple[float, float, int, str]]]) -> list[str]:
    """The table's rows of one game: each set against the first, position by position."""
    lines = []
    for k, name in enumerate(SETS):
        gain = [r[k][0] - r[0][0] for r in results]
        changed = sum(r[k][3] != r[0][3] for r in results)
        se = statistics.stdev(gain) / math.sqrt(len(gain)) if len(gain) > 1 else float("nan")
        median = statistics.median(r[k][1] for r in results)
        sims = statistics.fmean(r[k][2] for r in results)
        lines.append(
            f"| {game.value} | {name} | {len(results)} | {changed} | "
            f"{statistics.fmean(gain):+.4f} +- {se:.4f} | {median:.3f} | {sims:.0f} |"
        )
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--positions", type=int, default=40, help="positions per game")
    ap.add_argument("--from", dest="first", type=int, default=500_000, help="first seed")
    ap.add_argument("--judge", type=int, default=400, help="plays judging each chosen shot")
    ap.add_argument("--jobs", type=int, default=2, help="processes")
    args = ap.parse_args()
    print("| game | pot strokes | positions | changed | value over the first set | "
          "median s | sims |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    with ProcessPoolExecutor(args.jobs) as pool:
        for game in (Game.NINEBALL, Game.EIGHTBALL):
            jobs = [(s, args.judge) for _, s in positions(game, args.first, args.positions)]
            results = []
            for n, r in enumerate(pool.map(decide, jobs), 1):
                results.append(r)
                print(f"  {game.value}: {n}/{len(jobs)}", file=sys.stderr, flush=True)
            print("\n".join(rows(game, results)), flush=True)


if __name__ == "__main__":
    main()

"""The bot's runs: from random positions, how often it clears the table before it leaves it.

    .venv/bin/python bench/runouts.py [--positions N] [--from SEED] [--game G] [--level L]

Draws random positions (tests.rules.bot.positions, from seed --from on; none with a choice
pending or a push-out allowed) and lets the bot play each one alone, every shot under the
tournament noise as the arena plays it, until the game ends or the table passes to the other
side. Per position it notes how the visit ended: `won` (the table cleared, nine-ball's 9 or
eight-ball's 8 potted legally), `lost` (the game lost on the shot), `missed` (a pot that did
not go), `foul`, or `safety` (the bot chose to give the table away: a contact, a kick or a
push-out). It prints the counts by the number of object balls the position began with, and the
balls potted a position: the run-out ability that nine-ball's 95% bar rests on, measured with
far fewer decisions than whole games need. Compare two versions of the bot on the same
positions; a figure from the positions a change was tuned on says less than one from others.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rules.bot.chooser import Bot
from rules.bot.levels import level
from rules.bot.losses import POTS
from rules.bot.noise import draws, perturb, tournament
from rules.game import play
from rules.inputs import Shot
from rules.racks import Game
from rules.referee import table_of
from rules.state import State
from tests.rules.bot.positions import random_position

ENDS = ("won", "lost", "missed", "foul", "safety")


def positions(game: Game, first: int, n: int) -> list[tuple[int, State]]:
    """The first n random positions from seed `first` on with no choice pending, no push-out."""
    found: list[tuple[int, State]] = []
    seed = first
    while len(found) < n:
        state = random_position(game, seed)
        if not (state.pending or state.shots == 1):
            found.append((seed, state))
        seed += 1
    return found


def run(bot: Bot, state: State, seed: int) -> tuple[str, int, list[float]]:
    """Play `state` with `bot` until its visit ends: how it ended, balls potted, decision times."""
    me, R, noise = state.turn, table_of(state).R, tournament(1.0)
    potted, times = 0, []
    for n in range(30):
        t0 = time.perf_counter()
        shot = bot.choose(state)
        times.append(time.perf_counter() - t0)
        assert isinstance(shot, Shot)
        kind = bot.last.kind
        outcome = play(state, perturb(shot, noise, draws(seed, 1, "runout", n)[0], R))
        state, decision = outcome.state, outcome.decision
        if state.over:
            return ("won" if state.winner == me else "lost"), potted, times
        if decision is not None and decision.fouls:
            return "foul", potted, times
        if state.turn != me or state.pending:
            return ("missed" if kind in POTS else "safety"), potted, times
        potted += len(decision.pocketed) if decision is not None else 0
    return "missed", potted, times


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--positions", type=int, default=100)
    ap.add_argument("--from", dest="first", type=int, default=50_000, help="first seed tried")
    ap.add_argument("--game", default="nineball", choices=["nineball", "eightball"])
    ap.add_argument("--level", type=int, default=5)
    args = ap.parse_args()
    game = Game(args.game)
    bot = Bot(level(args.level), seed=1)
    by_balls: dict[int, Counter[str]] = {}
    potted, times = [], []
    found = positions(game, args.first, args.positions)
    for k, (seed, state) in enumerate(found, 1):
        balls = sum(1 for b in state.balls if b != "cue")
        end, n, t = run(bot, state, seed)
        by_balls.setdefault(balls, Counter())[end] += 1
        potted.append(n)
        times += t
        print(f"\r{k}/{len(found)} seed {seed}: {end}", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    print(f"{game} level {args.level}, {len(found)} positions from seed {args.first}")
    print(f"{'balls':>5} {'n':>4} " + " ".join(f"{e:>7}" for e in ENDS))
    total: Counter[str] = Counter()
    for balls in sorted(by_balls):
        c = by_balls[balls]
        total += c
        n = sum(c.values())
        print(f"{balls:>5} {n:>4} " + " ".join(f"{c[e]:>7}" for e in ENDS))
    n = sum(total.values())
    print(f"{'all':>5} {n:>4} " + " ".join(f"{total[e]:>7}" for e in ENDS))
    print(f"won {total['won'] / n:.1%}; balls potted a position {statistics.fmean(potted):.2f}")
    print(f"decision median {statistics.median(times):.2f} s, {len(times)} decisions")


if __name__ == "__main__":
    main()

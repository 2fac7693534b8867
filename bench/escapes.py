"""The bot's escapes from snookers: how often the kick it chooses fouls, and what it earns.

    .venv/bin/python bench/escapes.py [--positions N] [--from SEED] [--plays K] [--game G]

Draws random positions (tests.rules.bot.positions, from seed --from on) until N of them are
snookered: no legal ball can be hit straight, so the strongest level's candidates are kicks.
For each it lets the bot choose, then plays the chosen shot K more times under the tournament
noise, on draws of its own (not the ones the search saw), and prints, per position and in all,
the share of those plays that fouled and their mean value (rules.bot.value: the points and the
table left, -1 a lost game, +1 a won one). Compare two versions of the bot on the same
positions by running this on each; a figure from the positions a change was tuned on says less
than one from others (--from).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rules.bot.candidates import FINE, Kind, contact_candidates, spots
from rules.bot.chooser import Bot
from rules.bot.levels import STRONGEST
from rules.bot.noise import draws, tournament
from rules.bot.search import played_under
from rules.bot.value import WIN, outcome_value
from rules.racks import Game
from rules.referee import allowed
from rules.state import State
from tests.rules.bot.positions import random_position


def snookered(game: Game, first: int, n: int) -> list[tuple[int, State]]:
    """The first n random positions from seed `first` on whose only candidates are kicks."""
    found: list[tuple[int, State]] = []
    seed = first
    while len(found) < n:
        state = random_position(game, seed)
        if not (state.pending or state.ball_in_hand or state.shots == 1):
            kinds = {
                c.kind for c in contact_candidates(spots(state)[0], allowed(state).targets, FINE)
            }
            if kinds == {Kind.KICK}:
                found.append((seed, state))
        seed += 1
    return found


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--positions", type=int, default=40)
    ap.add_argument("--from", dest="first", type=int, default=20_000, help="first seed tried")
    ap.add_argument("--plays", type=int, default=60, help="noisy plays of each chosen kick")
    ap.add_argument("--game", default="nineball", choices=["nineball", "eightball"])
    args = ap.parse_args()
    noise = tournament(1.0)
    fouls, values, times = [], [], []
    print(f"{'seed':>7}{'candidates':>11}{'estimate':>9}{'value':>7}{'fouls':>7}")
    for seed, state in snookered(Game(args.game), args.first, args.positions):
        bot = Bot(STRONGEST, seed=7)
        t0 = time.perf_counter()
        shot = bot.choose(state)
        times.append(time.perf_counter() - t0)
        plays = [played_under(state, shot, noise, d) for d in draws(seed, args.plays, "escapes")]
        fouls.append(statistics.fmean(o is None or bool(o.decision.fouls) for o in plays))
        values.append(
            statistics.fmean(
                -WIN if o is None else outcome_value(state, o, noise, STRONGEST.rival)
                for o in plays
            )
        )
        print(
            f"{seed:>7}{bot.last.candidates:>11}{bot.last.value:>9.3f}{values[-1]:>7.3f}"
            f"{fouls[-1]:>7.0%}",
            flush=True,
        )
    print(
        f"\n{len(fouls)} snookered {args.game} positions from seed {args.first}: the chosen kick"
        f" fouled in {statistics.fmean(fouls):.1%} of {args.plays} plays each, mean value"
        f" {statistics.fmean(values):.3f}; median decision {statistics.median(times):.2f} s"
    )


if __name__ == "__main__":
    main()

"""The bot's bars: arenas against the shot pickers and the search baseline, and the ladder.

    .venv/bin/python bench/bot.py [--rows ROW[:GAMES],...] [--games N] [--noise F] [--seed S]
                                  [--target T] [--workers W] [--jobs N]

Rows: nineball, eightball, snooker, three_cushion (the strongest level against the pickers),
mcts (the strongest level against the search baseline, rules.bot.mcts, nine-ball) and ladder
(each level against the one below, nine-ball), each with its own game count (`snooker:6`) or
--games. Every row is racked from a seed drawn when the benchmark runs unless --seed is given
(a figure from the seeds the bot was tuned on says nothing about racks in general); the table
prints each row's seed, so a row can be played again. Prints one table, with the bar each row
is held to, a row as soon as it is played, then why the strongest level lost the games it lost
(rules.bot.losses); progress (one line a game) goes to stderr. The bars want many games (400
nine-ball and eight-ball racks, 200 against the baseline, 20 snooker frames, 100 a ladder step):
the defaults are a small smoke run, and the table says when a row played fewer games than its
bar asks for. Decision times are the bot's own (one process unless --workers), on a machine
that may be shared; "sims" is the mean number of simulations a shot's search ran, which no
machine changes. --jobs N plays N rows at once, each in a process of its own (the rows print
in the order asked for): with no more jobs than cores, each arena's times are still one
core's, and the whole table (about 75 minutes of one core at the bars' game counts) takes a
fraction of that.
"""

from __future__ import annotations

import argparse
import secrets
import shlex
import sys
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from itertools import pairwise
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rules.bot.arena import arena, wilson
from rules.bot.chooser import chooser
from rules.bot.levels import LEVELS, STRONGEST
from rules.bot.noise import tournament
from rules.racks import Game


@dataclass(frozen=True)
class Row:
    """One arena: chooser a against chooser b, and the bar a must clear."""

    label: str
    game: Game
    a: str
    b: str
    bar: str
    min_games: int

    def met(self, r: dict) -> bool:
        a, games = r["a"], r["games"]
        fast = a["decision_median_s"] <= MAX_MEDIAN_S
        if self.game == Game.SNOOKER:
            return a["highest"] >= 80 and fast
        if self.game == Game.THREE_CUSHION:
            return a["per_visit"] >= 1.0 and fast
        if self.b == "picker":
            return a["wins"] >= 0.95 * games and fast
        if self.b == "mcts":
            return a["wins"] >= 0.8 * games and fast
        return a["wins"] >= 0.6 * games


#: The strongest level's median decision time, one core (s).
MAX_MEDIAN_S = 1.0


def rows() -> dict[str, list[Row]]:
    best = f"bot:{STRONGEST.number}"
    fast = f"median <= {MAX_MEDIAN_S:g} s"
    ladder = [
        Row(
            f"ladder {hi.number}/{lo.number}",
            Game.NINEBALL,
            f"bot:{hi.number}",
            f"bot:{lo.number}",
            ">= 60% wins",
            100,
        )
        for lo, hi in pairwise(LEVELS)
    ]
    return {
        "nineball": [Row("nineball", Game.NINEBALL, best, "picker", f">= 95% wins, {fast}", 400)],
        "eightball": [
            Row("eightball", Game.EIGHTBALL, best, "picker", f">= 95% wins, {fast}", 400)
        ],
        "mcts": [Row("mcts", Game.NINEBALL, best, "mcts", f">= 80% wins, {fast}", 200)],
        "snooker": [
            Row("snooker", Game.SNOOKER, best, "picker", f"highest break >= 80, {fast}", 20)
        ],
        "three_cushion": [
            Row("three_cushion", Game.THREE_CUSHION, best, "picker", ">= 1.0 points/inning", 10)
        ],
        "ladder": ladder,
    }


def run_row(row: Row, games: int, seed: int, args: argparse.Namespace) -> dict:
    a = chooser(row.a, 2 * seed + 1, expect=args.noise, workers=args.workers)
    b = chooser(row.b, 2 * seed + 2, expect=args.noise, workers=args.workers)

    def progress(i, game, sa, sb) -> None:
        lo, hi = wilson(sa.wins, i + 1)
        a_seat = i % 2  # the arena alternates the break: a holds seat 0 in even games
        lost = f", {sa.name} lost: {game.loss}" if game.winner == 1 - a_seat else ""
        print(
            f"{row.label}: game {i + 1}/{games}, {sa.name} {sa.wins} - {sb.wins} {sb.name}"
            f" ({sa.wins / (i + 1):.0%} [{lo:.2f}, {hi:.2f}], {sa.run_outs} run-outs,"
            f" highest {sa.highest}){lost}",
            file=sys.stderr,
            flush=True,
        )

    try:
        return arena(
            row.game,
            a,
            b,
            games,
            seed,
            tournament(args.noise),
            target=args.target,
            progress=progress,
        )
    finally:
        a.close()
        b.close()


HEADER = (
    f"{'row':<14}{'a':>6} {'b':>7}{'seed':>11}{'games':>6}{'a wins':>8}  {'95% CI':<13}"
    f"{'per visit':>9}{'run-outs':>9}{'highest':>8}{'median s':>9}{'p95 s':>7}{'sims':>6}  bar"
)


def line(row: Row, seed: int, r: dict) -> str:
    a = r["a"]
    ci = f"[{a['ci95'][0]:.2f}, {a['ci95'][1]:.2f}]"
    verdict = "met" if row.met(r) else "not met"
    if r["games"] < row.min_games:
        verdict += f" (only {r['games']} of {row.min_games} games)"
    return (
        f"{row.label:<14}{row.a:>6} {row.b:>7}{seed:>11}{r['games']:>6}"
        f"{a['wins'] / r['games']:>8.0%}  {ci:<13}{a['per_visit']:>9.2f}"
        f"{a['run_outs'] / r['games']:>9.0%}{a['highest']:>8}{a['decision_median_s']:>9.2f}"
        f"{a['decision_p95_s']:>7.2f}{a['simulations_mean']:>6.0f}  {row.bar}: {verdict}"
    )


def losses(row: Row, r: dict) -> str:
    """Why side a lost the games it lost (rules.bot.losses), most frequent first."""
    lost = r["a"]["losses"]
    why = ", ".join(f"{k} {n}" for k, n in lost.items()) if lost else "none"
    return f"{row.label:<14}{sum(lost.values()):>4} lost: {why}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--games", type=int, default=4, help="games per row without its own count")
    ap.add_argument("--rows", default="nineball,eightball,mcts,snooker,three_cushion,ladder")
    ap.add_argument("--noise", type=float, default=1.0, help="execution noise factor")
    ap.add_argument("--seed", type=int, default=None, help="every row's seed (default: drawn)")
    ap.add_argument("--target", type=int, default=0, help="three-cushion points to win")
    ap.add_argument("--workers", type=int, default=1, help="worker processes per bot")
    ap.add_argument("--jobs", type=int, default=1, help="rows played at once, a process each")
    args = ap.parse_args()
    table = rows()
    print("    " + shlex.join(["python", "bench/bot.py", *sys.argv[1:]]))
    drawn = "given" if args.seed is not None else "drawn at run time"
    print(f"noise factor {args.noise}, seeds {drawn}")
    print(HEADER, flush=True)
    plan = []
    for item in args.rows.split(","):
        name, _, count = item.partition(":")
        for row in table[name]:
            seed = args.seed if args.seed is not None else secrets.randbelow(10**9)
            plan.append((row, int(count) if count else args.games, seed))
    why = []
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        running = [pool.submit(run_row, row, games, seed, args) for row, games, seed in plan]
        for (row, _, seed), future in zip(plan, running, strict=True):
            result = future.result()
            print(line(row, seed, result), flush=True)
            why.append(losses(row, result))
    print("\nwhy the games were lost (the loser's last act before the winner's final visit):")
    print("\n".join(why))


if __name__ == "__main__":
    main()

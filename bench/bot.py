"""The bot's bars: arenas against the shot pickers in each game, and the strength ladder.

    .venv/bin/python bench/bot.py [--rows ROW[:GAMES],...] [--games N] [--noise F] [--seed S]
                                  [--target T] [--workers W]

Rows: nineball, eightball, snooker, three_cushion (the strongest level against the pickers)
and ladder (each level against the one below, nine-ball), each with its own game count
(`snooker:6`) or --games. Prints one table, with the bar each row is held to and the command
that printed it, a row as soon as it is played; progress (one line a game) goes to stderr. The
bars want many games (200 nine-ball racks, 20 snooker frames): the defaults are a small
smoke run, and the table says when a row played fewer games than its bar asks for. Decision
times are the bot's own (one process unless --workers), on a machine that may be shared;
"sims" is the mean number of simulations a shot's search ran, which no machine changes.
"""

from __future__ import annotations

import argparse
import shlex
import sys
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
        if self.game == Game.SNOOKER and self.b == "picker":
            return a["highest"] >= 50
        if self.game == Game.THREE_CUSHION:
            return a["per_visit"] >= 0.6
        if self.b == "picker":
            ok = a["wins"] >= 0.9 * games
            if self.game == Game.NINEBALL:
                ok = ok and a["run_outs"] >= 0.3 * games and a["decision_median_s"] <= 2.0
            return ok
        return a["wins"] > games / 2


def rows() -> dict[str, list[Row]]:
    best = f"bot:{STRONGEST.number}"
    ladder = [
        Row(
            f"ladder {hi.number}/{lo.number}",
            Game.NINEBALL,
            f"bot:{hi.number}",
            f"bot:{lo.number}",
            "wins > 50%",
            1,
        )
        for lo, hi in pairwise(LEVELS)
    ]
    return {
        "nineball": [
            Row(
                "nineball",
                Game.NINEBALL,
                best,
                "picker",
                ">= 90% wins, >= 30% run-outs, median <= 2 s",
                200,
            )
        ],
        "eightball": [Row("eightball", Game.EIGHTBALL, best, "picker", ">= 90% wins", 200)],
        "snooker": [Row("snooker", Game.SNOOKER, best, "picker", "highest break >= 50", 20)],
        "three_cushion": [
            Row("three_cushion", Game.THREE_CUSHION, best, "picker", ">= 0.6 points/inning", 1)
        ],
        "ladder": ladder,
    }


def run_row(row: Row, games: int, args: argparse.Namespace) -> dict:
    a = chooser(row.a, 2 * args.seed + 1, expect=args.noise, workers=args.workers)
    b = chooser(row.b, 2 * args.seed + 2, expect=args.noise, workers=args.workers)

    def progress(i, game, sa, sb) -> None:
        lo, hi = wilson(sa.wins, i + 1)
        print(
            f"{row.label}: game {i + 1}/{games}, {sa.name} {sa.wins} - {sb.wins} {sb.name}"
            f" ({sa.wins / (i + 1):.0%} [{lo:.2f}, {hi:.2f}], {sa.run_outs} run-outs,"
            f" highest {sa.highest})",
            file=sys.stderr,
            flush=True,
        )

    try:
        return arena(
            row.game,
            a,
            b,
            games,
            args.seed,
            tournament(args.noise),
            target=args.target,
            progress=progress,
        )
    finally:
        a.close()
        b.close()


HEADER = (
    f"{'row':<14}{'a':>6} {'b':>7}{'games':>6}{'a wins':>8}  {'95% CI':<13}{'per visit':>9}"
    f"{'run-outs':>9}{'highest':>8}{'median s':>9}{'p95 s':>7}{'sims':>6}  bar"
)


def line(row: Row, r: dict) -> str:
    a = r["a"]
    ci = f"[{a['ci95'][0]:.2f}, {a['ci95'][1]:.2f}]"
    verdict = "met" if row.met(r) else "not met"
    if r["games"] < row.min_games:
        verdict += f" (only {r['games']} of {row.min_games} games)"
    return (
        f"{row.label:<14}{row.a:>6} {row.b:>7}{r['games']:>6}{a['wins'] / r['games']:>8.0%}  "
        f"{ci:<13}{a['per_visit']:>9.2f}{a['run_outs'] / r['games']:>9.0%}{a['highest']:>8}"
        f"{a['decision_median_s']:>9.2f}{a['decision_p95_s']:>7.2f}{a['simulations_mean']:>6.0f}"
        f"  {row.bar}: {verdict}"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--games", type=int, default=4, help="games per row without its own count")
    ap.add_argument("--rows", default="nineball,eightball,snooker,three_cushion,ladder")
    ap.add_argument("--noise", type=float, default=1.0, help="execution noise factor")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--target", type=int, default=0, help="three-cushion points to win")
    ap.add_argument("--workers", type=int, default=1, help="worker processes per bot")
    args = ap.parse_args()
    table = rows()
    print("    " + shlex.join(["python", "bench/bot.py", *sys.argv[1:]]))
    print(f"noise factor {args.noise}, seed {args.seed}")
    print(HEADER, flush=True)
    for item in args.rows.split(","):
        name, _, count = item.partition(":")
        for row in table[name]:
            result = run_row(row, int(count) if count else args.games, args)
            print(line(row, result), flush=True)


if __name__ == "__main__":
    main()

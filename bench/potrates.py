"""The bot's chosen pots: how often they drop under the noise, against the chance it gave them.

    .venv/bin/python bench/potrates.py [--positions N] [--from SEED] [--plays K]

Takes the strongest level's first decision on N random nine-ball positions (those of
bench/runouts.py with the cue ball on the table) wherever it is a straight pot, plays that
shot K more times under the tournament noise on draws of its own, and prints, by the
geometry's estimate of the pot (rules.bot.geometry.pots, the best pot on the ball the shot
drops when played as meant), how often the ball dropped without a foul. A chosen pot that
drops nothing when played as meant is counted and left out of the bands. If the pots drop as
often as estimated, the bot's misses are the noise's, not its aim's.
"""

from __future__ import annotations

import argparse
import itertools
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.runouts import positions
from rules.bot.candidates import Kind
from rules.bot.chooser import Bot
from rules.bot.geometry import pots
from rules.bot.levels import STRONGEST
from rules.bot.noise import draws, perturb, tournament
from rules.game import play
from rules.inputs import Shot
from rules.racks import Game
from rules.referee import allowed, table_of
from rules.state import State

#: The rows: estimates from each bound up to the next.
BANDS = (0.0, 0.8, 0.95, 0.99)


def pot_rate(seed: int, state: State, shot: Shot, plays: int) -> tuple[float, float] | None:
    """(estimate, share dropped) of the pot `shot` in `state`; None when, played as meant, it
    drops no ball or fouls (there is then no ball to hold its estimate against)."""
    exact = play(state, shot).decision
    if exact.fouls or not exact.pocketed:
        return None
    ball, table, noise = exact.pocketed[0], table_of(state), tournament(1.0)
    found = pots(table, state.balls["cue"], state.balls, allowed(state).targets, noise)
    estimate = max((p.chance for p in found if p.target == ball), default=0.0)
    dropped = 0
    for d in draws(seed, plays, "potrates"):
        decision = play(state, perturb(shot, noise, d, table.R)).decision
        dropped += ball in decision.pocketed and not decision.fouls
    return estimate, dropped / plays


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--positions", type=int, default=140)
    ap.add_argument("--from", dest="first", type=int, default=90_000, help="first seed tried")
    ap.add_argument("--plays", type=int, default=60, help="noisy plays of each chosen pot")
    args = ap.parse_args()
    bot = Bot(STRONGEST, seed=1)
    found = positions(Game.NINEBALL, args.first, args.positions)
    rates, chosen = [], 0
    for k, (seed, state) in enumerate(found, 1):
        shot = None if state.ball_in_hand else bot.choose(state)
        if shot is not None and bot.last.kind == Kind.POT:
            chosen += 1
            rate = pot_rate(seed, state, shot, args.plays)
            rates += [rate] if rate is not None else []
        print(f"\r{k}/{len(found)}: {chosen} pots", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    print(
        f"{chosen} pots chosen on {len(found)} positions from seed {args.first}, "
        f"{chosen - len(rates)} of them dropping nothing as meant (left out)"
    )
    print(f"{'estimate':<12}{'pots':>5}{'estimated':>10}{'dropped':>9}")
    bounds = [*BANDS, 1.01]
    rows = [(f"{lo:.2f}-{hi:.2f}", lo, hi) for lo, hi in itertools.pairwise(bounds)]
    for label, lo, hi in [*rows, ("all", 0.0, 1.01)]:
        band = [r for r in rates if lo <= r[0] < hi]
        if band:
            est = statistics.fmean(r[0] for r in band)
            dropped = statistics.fmean(r[1] for r in band)
            print(f"{label:<12}{len(band):>5}{est:>10.3f}{dropped:>9.3f}")


if __name__ == "__main__":
    main()

"""The geometry's pot chances against the engine: every straight pot, estimated and played.

    .venv/bin/python bench/pot_chances.py [--from 300000,400000] [--positions 600] [--plays 40]
                                          [--fit]

On `--positions` random nine-ball positions from each seed in `--from` (those of
bench/runouts.py with the cue ball on the table), takes every straight pot the geometry sees
on the legal ball (rules.bot.geometry.pots), plays it `--plays` times under the tournament
noise as the bot would (its pot speed, centre ball, the heading corrected for throw) and
counts the plays that drop the ball. Prints, by band of the estimate, the pots, their mean
estimate and the share that dropped, and the log-likelihood of all the plays under the
estimate (higher is better), for the bot's estimate (CHANCE) and for the heading's Gaussian
alone, which it was before: the bot values every position by these chances, so a band that
drops less often than it is estimated is a band of positions the bot overrates.

`--fit` fits the estimate's four constants (rules.bot.geometry.ChanceModel) to the plays by
maximum likelihood and prints them, and the table again under the fitted model. Fit on some
seeds, then measure on others: the figures worth quoting are those of seeds not fitted on.
"""

from __future__ import annotations

import argparse
import itertools
import math
import statistics
import sys
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import physics
from bench.runouts import positions
from rules.bot.candidates import Candidate, Kind, pot_speed, spots
from rules.bot.geometry import CHANCE, MIN_HEADING_SD, ChanceModel, pots, tolerance
from rules.bot.noise import draws, perturb, tournament
from rules.bot.search import throw_corrected
from rules.game import play
from rules.racks import Game
from rules.referee import allowed, table_of
from rules.state import State

#: The estimate as it was before its fit: the heading's Gaussian alone.
GAUSSIAN = ChanceModel(turn_spread=1.0, object_spread=0.0, shift=0.0, slope=1.0)
#: The rows: estimates from each bound up to the next.
BANDS = (0.0, 0.5, 0.8, 0.9, 0.95, 0.97, 0.99, 0.995)


@dataclass(frozen=True, slots=True)
class Measured:
    """One pot: what the estimate is made of (tolerance, travel, turn), and its plays."""

    tol: float
    travel: float
    turn: float
    plays: int
    dropped: int


def measure(seed: int, state: State, plays: int) -> list[Measured]:
    """Every straight pot on the legal ball in `state`, played `plays` times under the noise."""
    noise = tournament(1.0)
    spot = spots(state)[0]
    table, R = spot.table, table_of(state).R
    found = []
    for p in pots(table, spot.cue, spot.balls, allowed(state).targets, noise):
        strike = {"speed": round(pot_speed(p), 3), "heading": p.heading}
        shot = spot.shot(p.target, p.pocket, **strike)
        aimed = throw_corrected(state, Candidate(shot, Kind.POT, p), physics.simulate).shot
        dropped = sum(
            p.target in play(state, perturb(aimed, noise, d, R)).decision.pocketed
            for d in draws(seed, plays, "pot_chances", p.target, p.pocket)
        )
        pocket = next(k for k in table.pockets if k.name == p.pocket)
        at = spot.balls[p.target]
        away = math.dist(at, pocket.center)
        way = ((pocket.center[0] - at[0]) / away, (pocket.center[1] - at[1]) / away)
        turn = max(p.d1, 2 * R) / (2 * R * p.cos_cut)
        found.append(Measured(tolerance(table, pocket, way), p.travel, turn, plays, dropped))
    return found


def estimate(model: ChanceModel, m: Measured) -> float:
    return model(m.tol, m.travel, m.turn, max(tournament(1.0).heading, MIN_HEADING_SD))


def log_likelihood(model: ChanceModel, measured: list[Measured]) -> float:
    total = 0.0
    for m in measured:
        p = min(max(estimate(model, m), 1e-9), 1 - 1e-9)
        total += m.dropped * math.log(p) + (m.plays - m.dropped) * math.log(1 - p)
    return total


def table(model: ChanceModel, measured: list[Measured]) -> None:
    print(f"{'estimate':<12}{'pots':>6}{'estimated':>11}{'dropped':>9}")
    rated = [(estimate(model, m), m.dropped / m.plays) for m in measured]
    for lo, hi in itertools.pairwise([*BANDS, 1.01]):
        band = [(e, d) for e, d in rated if lo <= e < hi]
        if band:
            mean_e = statistics.fmean(e for e, _ in band)
            mean_d = statistics.fmean(d for _, d in band)
            print(f"{lo:.3f}-{min(hi, 1):.3f}{len(band):>6}{mean_e:>11.3f}{mean_d:>9.3f}")
    print(f"log-likelihood of the plays: {log_likelihood(model, measured):.1f}")


def fit(measured: list[Measured]) -> ChanceModel:
    """The model's four constants that make the plays likeliest (scipy's Nelder-Mead)."""
    from scipy.optimize import minimize

    start = (CHANCE.turn_spread, CHANCE.object_spread, CHANCE.shift, CHANCE.slope)
    found = minimize(
        lambda x: -log_likelihood(ChanceModel(*x), measured),
        start,
        method="Nelder-Mead",
        options={"maxiter": 4000, "xatol": 1e-4, "fatol": 1e-3},
    )
    return ChanceModel(*(round(float(v), 3) for v in found.x))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--from", dest="first", default="300000", help="first seeds, comma-separated")
    ap.add_argument("--positions", type=int, default=600, help="positions from each seed")
    ap.add_argument("--plays", type=int, default=40, help="noisy plays of each pot")
    ap.add_argument("--fit", action="store_true", help="fit the model's constants and print them")
    args = ap.parse_args()
    seeds = [int(s) for s in args.first.split(",")]
    found = [f for s in seeds for f in positions(Game.NINEBALL, s, args.positions)]
    measured: list[Measured] = []
    for k, (seed, state) in enumerate(found, 1):
        if not state.ball_in_hand:
            measured += measure(seed, state, args.plays)
        print(f"\r{k}/{len(found)}: {len(measured)} pots", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    print(f"{len(measured)} straight pots on {len(found)} positions from seeds {args.first},")
    print(f"{args.plays} plays each. The heading's Gaussian alone ({GAUSSIAN}):")
    table(GAUSSIAN, measured)
    print(f"rules.bot.geometry.CHANCE ({CHANCE}):")
    table(CHANCE, measured)
    if args.fit:
        fitted = fit(measured)
        print(f"fitted: {fitted}")
        table(fitted, measured)


if __name__ == "__main__":
    main()

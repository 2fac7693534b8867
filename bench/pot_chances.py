"""The geometry's pot chances against the engine: every straight pot, estimated and played.

    .venv/bin/python bench/pot_chances.py [--from 300000,400000] [--positions 600] [--plays 40]
                                          [--fit] [--model T,O,S,L]

On `--positions` random nine-ball positions from each seed in `--from` (those of
bench/runouts.py with the cue ball on the table), takes every straight pot the geometry sees
on the legal ball (rules.bot.geometry.pots), plays it `--plays` times under the tournament
noise as the bot would (its pot speed, centre ball, the heading corrected for throw) and
counts the plays that drop the ball. Prints, by band of the estimate, the pots, their mean
estimate and the share that dropped, and the log-likelihood of all the plays under the
estimate (higher is better): the bot values every position by these chances
(rules.bot.geometry.chance, the heading's Gaussian), so a band that drops less often than it
is estimated is a band of positions the bot overrates.

`ChanceModel` is that estimate with what it leaves out: the object ball's own direction error
and a recalibration in log-odds. `--fit` fits its four constants to the plays by maximum
likelihood and prints them with the table under them; `--model T,O,S,L` prints the table under
given constants, for measuring a fit on seeds it was not fitted on. The README says what a
fitted estimate did to the bot's play (measured, not kept).
"""

from __future__ import annotations

import argparse
import itertools
import math
import statistics
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import physics
from bench.runouts import positions
from rules.bot.candidates import Candidate, Kind, pot_speed, spots
from rules.bot.geometry import _direction, _Leg, _turn, chance, pots, tolerance
from rules.bot.noise import draws, perturb, tournament
from rules.bot.search import throw_corrected
from rules.game import play
from rules.racks import Game
from rules.referee import allowed, table_of
from rules.state import State

#: The noise the bot plans under at its strongest level.
NOISE = tournament(1.0)
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


@dataclass(frozen=True, slots=True)
class ChanceModel:
    """The geometry's estimate with the errors it leaves out (turn_spread 1, object_spread 0,
    shift 0, slope 1 is the estimate itself).

    The object ball's sideways miss at the pocket, `travel` away, is Gaussian with sd `travel`
    times its direction error: the heading error as the cue ball's path feels it
    (`turn_spread` times the noise's: the tip's errors add squirt), turned by `turn`, and
    beside it the object ball's own error (the throw, which the speed's and the tip's errors
    vary), `object_spread` times the noise's heading error. The Gaussian's probability q of
    staying within the tolerance is mapped to `shift` + `slope` * logit(q) in log-odds.
    """

    turn_spread: float
    object_spread: float
    shift: float
    slope: float

    def __call__(self, m: Measured) -> float:
        if m.tol <= 0.0:
            return 0.0
        spread = m.travel * math.hypot(self.turn_spread * m.turn, self.object_spread)
        q = min(chance(m.tol, spread, NOISE), 1.0 - 1e-12)
        return 1.0 / (1.0 + math.exp(-(self.shift + self.slope * math.log(q / (1.0 - q)))))


def geometry(m: Measured) -> float:
    """The estimate the bot plans with (rules.bot.geometry.chance)."""
    return chance(m.tol, m.travel * m.turn, NOISE)


def measure(seed: int, state: State, plays: int) -> list[Measured]:
    """Every straight pot on the legal ball in `state`, played `plays` times under the noise."""
    spot = spots(state)[0]
    table, R = spot.table, table_of(state).R
    found = []
    for p in pots(table, spot.cue, spot.balls, allowed(state).targets, NOISE):
        strike = {"speed": round(pot_speed(p), 3), "heading": p.heading}
        shot = spot.shot(p.target, p.pocket, **strike)
        aimed = throw_corrected(state, Candidate(shot, Kind.POT, p), physics.simulate).shot
        dropped = sum(
            p.target in play(state, perturb(aimed, NOISE, d, R)).decision.pocketed
            for d in draws(seed, plays, "pot_chances", p.target, p.pocket)
        )
        pocket = next(k for k in table.pockets if k.name == p.pocket)
        tol = tolerance(table, pocket, _direction(spot.balls[p.target], pocket.center))
        turn = _turn(_Leg(p.ghost, p.d1, p.cos_cut), R)
        found.append(Measured(tol, p.travel, turn, plays, dropped))
    return found


Estimate = Callable[[Measured], float]


def log_likelihood(estimate: Estimate, measured: list[Measured]) -> float:
    total = 0.0
    for m in measured:
        p = min(max(estimate(m), 1e-9), 1 - 1e-9)
        total += m.dropped * math.log(p) + (m.plays - m.dropped) * math.log(1 - p)
    return total


def table(estimate: Estimate, measured: list[Measured]) -> None:
    print(f"{'estimate':<12}{'pots':>6}{'estimated':>11}{'dropped':>9}")
    rated = [(estimate(m), m.dropped / m.plays) for m in measured]
    for lo, hi in itertools.pairwise([*BANDS, 1.01]):
        band = [(e, d) for e, d in rated if lo <= e < hi]
        if band:
            mean_e = statistics.fmean(e for e, _ in band)
            mean_d = statistics.fmean(d for _, d in band)
            print(f"{lo:.3f}-{min(hi, 1):.3f}{len(band):>6}{mean_e:>11.3f}{mean_d:>9.3f}")
    print(f"log-likelihood of the plays: {log_likelihood(estimate, measured):.1f}")


def fit(measured: list[Measured]) -> ChanceModel:
    """The model's four constants that make the plays likeliest (scipy's Nelder-Mead)."""
    from scipy.optimize import minimize

    start = (1.0, 1.0, 0.0, 1.0)  # near the geometry's estimate (object_spread 0)
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
    ap.add_argument("--fit", action="store_true", help="fit ChanceModel's constants")
    ap.add_argument("--model", help="ChanceModel's constants T,O,S,L to measure")
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
    print(f"{args.plays} plays each. The estimate the bot plans with (the heading's Gaussian):")
    table(geometry, measured)
    models = [fit(measured)] if args.fit else []
    models += [ChanceModel(*map(float, args.model.split(",")))] if args.model else []
    for model in models:
        print(f"{model}:")
        table(model, measured)


if __name__ == "__main__":
    main()

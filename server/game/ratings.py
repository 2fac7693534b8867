"""Glicko-2 ratings (Glickman, "Example of the Glicko-2 system", 2013), one per player and game.

Each rated match is one rating period with one game, as lichess rates each game at once. The
parameters, and why:

- a new player starts at rating 1500, deviation 350, volatility 0.06: Glickman's suggested
  defaults (350 is the uncertainty of a complete unknown on the Glicko scale);
- tau = 0.5, the system constant limiting how fast volatility moves: Glickman suggests 0.3 to
  1.2 and uses 0.5 in his example; billiards results are noisy (a rack turns on a few rolls), so
  a middle value;
- convergence tolerance 1e-6 in the volatility iteration (Glickman's);
- a rating is shown as provisional while its deviation exceeds 110, lichess's threshold;
- deviations do not grow with idle time (no rating periods without games): a guest identity
  is cheap, so a returning player's uncertainty comes from its few games, not from a calendar.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from pydantic import BaseModel, ConfigDict

#: Glicko to Glicko-2 scale factor (Glickman: 173.7178 = 400 / ln 10).
SCALE = 400.0 / math.log(10.0)
START_RATING, START_DEVIATION, START_VOLATILITY = 1500.0, 350.0, 0.06
TAU = 0.5
EPSILON = 1e-6
PROVISIONAL_DEVIATION = 110.0


class Rating(BaseModel):
    """A player's rating in one game, on the Glicko scale."""

    model_config = ConfigDict(frozen=True)

    rating: float = START_RATING
    deviation: float = START_DEVIATION
    volatility: float = START_VOLATILITY
    games: int = 0

    @property
    def provisional(self) -> bool:
        return self.deviation > PROVISIONAL_DEVIATION


def _g(phi: float) -> float:
    return 1.0 / math.sqrt(1.0 + 3.0 * phi * phi / (math.pi * math.pi))


def _expected(mu: float, mu_j: float, phi_j: float) -> float:
    return 1.0 / (1.0 + math.exp(-_g(phi_j) * (mu - mu_j)))


def _volatility(sigma: float, phi: float, v: float, delta: float, tau: float) -> float:
    """The new volatility: the root of Glickman's f(x) by the Illinois variant of regula falsi."""
    a = math.log(sigma * sigma)

    def f(x: float) -> float:
        ex = math.exp(x)
        return ex * (delta * delta - phi * phi - v - ex) / (2.0 * (phi * phi + v + ex) ** 2) - (
            x - a
        ) / (tau * tau)

    big_a = a
    if delta * delta > phi * phi + v:
        big_b = math.log(delta * delta - phi * phi - v)
    else:
        k = 1
        while f(a - k * tau) < 0:
            k += 1
        big_b = a - k * tau
    f_a, f_b = f(big_a), f(big_b)
    while abs(big_b - big_a) > EPSILON:
        big_c = big_a + (big_a - big_b) * f_a / (f_b - f_a)
        f_c = f(big_c)
        if f_c * f_b <= 0:
            big_a, f_a = big_b, f_b
        else:
            f_a /= 2.0
        big_b, f_b = big_c, f_c
    return math.exp(big_a / 2.0)


def update(player: Rating, games: Sequence[tuple[Rating, float]], tau: float = TAU) -> Rating:
    """The player's rating after one rating period of `games` (opponent, score 1/0.5/0)."""
    mu = (player.rating - START_RATING) / SCALE
    phi = player.deviation / SCALE
    if not games:
        return player
    opponents = [
        ((o.rating - START_RATING) / SCALE, o.deviation / SCALE, score) for o, score in games
    ]
    v = 1.0 / sum(
        _g(phi_j) ** 2 * _expected(mu, mu_j, phi_j) * (1.0 - _expected(mu, mu_j, phi_j))
        for mu_j, phi_j, _ in opponents
    )
    gain = sum(_g(phi_j) * (s - _expected(mu, mu_j, phi_j)) for mu_j, phi_j, s in opponents)
    sigma = _volatility(player.volatility, phi, v, v * gain, tau)
    phi_star = math.sqrt(phi * phi + sigma * sigma)
    phi_new = 1.0 / math.sqrt(1.0 / (phi_star * phi_star) + 1.0 / v)
    mu_new = mu + phi_new * phi_new * gain
    return Rating(
        rating=START_RATING + SCALE * mu_new,
        deviation=SCALE * phi_new,
        volatility=sigma,
        games=player.games + len(games),
    )


def after_match(winner: Rating, loser: Rating) -> tuple[Rating, Rating]:
    """Both players' ratings after one decided match (each is the other's only game)."""
    return update(winner, [(loser, 1.0)]), update(loser, [(winner, 0.0)])

"""The execution-noise model: seeded, scaled by one factor, and always a legal input."""

from __future__ import annotations

import statistics

import pytest

from physics.cue import MISCUE_LIMIT
from rules.bot.noise import FASTFIZ, HEADING_SD, draws, perturb, tournament
from rules.inputs import Shot, Strike, check_canonical
from rules.spots import POOL_TABLE

R = POOL_TABLE.R


def test_draws_are_fixed_by_seed_and_key():
    assert draws(3, 5, "a", 1) == draws(3, 5, "a", 1)
    assert draws(3, 5, "a", 1) != draws(3, 5, "a", 2)
    assert draws(3, 5, "a", 1) != draws(4, 5, "a", 1)
    assert draws(3, 8, "k")[:5] == draws(3, 5, "k")


def test_the_factor_scales_every_deviation():
    twice = tournament(2.0)
    assert twice.heading == 2 * FASTFIZ.heading and twice.tip == 2 * FASTFIZ.tip
    assert tournament(0.0).silent
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError):
            tournament(bad)


def test_heading_errors_have_the_tournament_spread():
    shot = Shot(strike=Strike(ball="cue", speed=2.0, heading=90.0))
    moved = [perturb(shot, FASTFIZ, d, R).strike.heading - 90.0 for d in draws(1, 2000, "sd")]
    assert statistics.fmean(moved) == pytest.approx(0.0, abs=0.02)
    assert statistics.stdev(moved) == pytest.approx(HEADING_SD, rel=0.08)


@pytest.mark.parametrize(
    "strike",
    [
        {"speed": 0.002, "heading": 0.0, "elevation": 0.0},
        {"speed": 12.0, "heading": 359.9999, "elevation": 89.0},
        {"speed": 3.0, "heading": 10.0, "a": 0.35, "b": -0.35},
        {"speed": 3.0, "heading": 10.0, "a": 0.0, "b": 0.5},
    ],
)
def test_a_perturbed_shot_is_canonical_and_within_bounds(strike):
    shot = Shot(strike=Strike(ball="cue", **strike), place=(0.5, 0.5))
    for d in draws(2, 300, "bounds"):
        out = perturb(shot, tournament(5.0), d, R)
        check_canonical(out)
        s = out.strike
        assert 0 < s.speed <= 12.0 and 0 <= s.elevation <= 89.0
        assert (s.a * s.a + s.b * s.b) ** 0.5 <= MISCUE_LIMIT
        assert out.place == shot.place


def test_silent_noise_changes_nothing():
    shot = Shot(strike=Strike(ball="cue", speed=2.0, heading=45.0, a=0.1))
    assert perturb(shot, tournament(0.0), (1.0, 1.0, 1.0, 1.0, 1.0), R) == shot

"""Glicko-2 against the worked example of Glickman's paper, and what must always hold."""

from __future__ import annotations

import pytest
from hypothesis import example, given
from hypothesis import strategies as st

from server.game.ratings import Rating, after_match, update


def test_glickmans_worked_example() -> None:
    # The paper's example: a 1500 / 200 / 0.06 player, tau 0.5, beats a 1400 / 30 player and
    # loses to 1550 / 100 and 1700 / 300 within one rating period.
    player = Rating(rating=1500, deviation=200, volatility=0.06)
    games = [
        (Rating(rating=1400, deviation=30), 1.0),
        (Rating(rating=1550, deviation=100), 0.0),
        (Rating(rating=1700, deviation=300), 0.0),
    ]
    after = update(player, games, tau=0.5)
    assert after.rating == pytest.approx(1464.06, abs=0.01)
    assert after.deviation == pytest.approx(151.52, abs=0.01)
    assert after.volatility == pytest.approx(0.05999, abs=1e-5)
    assert after.games == 3


def test_a_new_player_is_provisional_until_its_deviation_falls() -> None:
    player, regular = Rating(), Rating(rating=1500, deviation=50)
    assert player.provisional and player.rating == 1500
    for game in range(1, 31):
        player, _ = after_match(player, regular) if game % 2 else after_match(regular, player)[::-1]
        if not player.provisional:
            break
    assert not player.provisional and 5 <= game < 30 and player.deviation <= 110


ratings = st.builds(
    Rating,
    rating=st.floats(800, 2800),
    deviation=st.floats(30, 350),
    volatility=st.floats(0.03, 0.1),
)


@given(ratings, ratings)
@example(  # an upset that raises the winner's volatility
    Rating(rating=800, deviation=30, volatility=0.1),
    Rating(rating=1647, deviation=30, volatility=0.0625),
)
def test_the_winner_gains_the_loser_loses_and_both_grow_surer(w: Rating, l: Rating) -> None:
    won, lost = after_match(w, l)
    assert won.rating > w.rating and lost.rating < l.rating
    # A rating period first widens the deviation by the new volatility (Glickman's step 6),
    # then the game narrows it: never past that widening, though a surprise may raise the
    # volatility (an 800 beating a 1647 did, past its old 0.1).
    for before, after in ((w, won), (l, lost)):
        assert after.deviation < (before.deviation**2 + (after.volatility * 173.7178) ** 2) ** 0.5
    assert won.games == w.games + 1 and lost.games == l.games + 1

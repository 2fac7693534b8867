"""The bot's judgement of a position (rules.bot.value): the shape a next pot leaves counts,
and where the cue ball may go after a pot is a place it may really stop."""

from __future__ import annotations

import math

import pytest

from rules.bot.geometry import pots
from rules.bot.noise import tournament
from rules.bot.placements import placements
from rules.bot.value import (
    KEEP_NOTHING,
    KEEP_SURE,
    cue_after,
    keep,
    position_value,
    shape,
    theirs,
    value_for,
)
from rules.racks import Game, rack
from rules.referee import referee
from rules.spots import POOL_TABLE, SNOOKER, in_region, is_free
from rules.state import State

NOISE = tournament(1.0)
R = POOL_TABLE.R
#: The cue ball a short way straight behind the 1, which sits before the bottom-left pocket:
#: a sure pot whatever else is on the table.
ONE = (0.25, 0.25)
CUE = (0.4, 0.4)
#: The 2 in the open, and the same 2 boxed in by six balls, one on its way to each pocket.
TWO = (0.6, 1.3)


def boxed(at: tuple[float, float]) -> dict[str, tuple[float, float]]:
    """Six balls around `at`, each just off the line from it to one pocket."""
    out = {}
    for name, pocket in zip("345678", POOL_TABLE.pockets, strict=True):
        dx, dy = pocket.center[0] - at[0], pocket.center[1] - at[1]
        d = math.hypot(dx, dy)
        out[name] = (at[0] + dx / d * 2.2 * R, at[1] + dy / d * 2.2 * R)
    return out


def nineball(balls: dict) -> State:
    return State(game=Game.NINEBALL, balls=balls, shots=5)


def the_pot(state: State):
    now = referee(state.game).targets(state, state.balls)
    return pots(POOL_TABLE, state.balls["cue"], dict(state.balls), now, NOISE)[0]


def test_a_next_pot_that_leaves_no_shot_on_the_ball_after_is_worth_less():
    far = {"3": (1.1, 2.3), "4": (1.15, 2.4), "5": (0.2, 2.3), "6": (0.1, 2.4)}
    far |= {"7": (1.15, 1.0), "8": (0.1, 1.0)}
    open_ = nineball({"cue": CUE, "1": ONE, "2": TWO, "9": (1.0, 2.0), **far})
    shut = nineball({"cue": CUE, "1": ONE, "2": TWO, "9": (1.0, 2.0), **boxed(TWO)})
    assert the_pot(open_).chance == the_pot(shut).chance
    assert shape(shut, POOL_TABLE, the_pot(shut), dict(shut.balls), NOISE) == 0.0
    assert shape(open_, POOL_TABLE, the_pot(open_), dict(open_.balls), NOISE) > 0.0
    assert position_value(shut, NOISE) < position_value(open_, NOISE)


def test_the_last_ball_needs_no_shape():
    """With only the 9 left there is no ball after it: its pot counts in full."""
    state = nineball({"cue": CUE, "9": ONE})
    pot = the_pot(state)
    assert shape(state, POOL_TABLE, pot, dict(state.balls), NOISE) == 1.0
    assert position_value(state, NOISE) == keep(state, pot.chance, 0)


def test_the_cue_ball_is_sent_only_where_it_can_stop():
    state = nineball({"cue": CUE, "1": ONE, "2": TWO, "9": (1.0, 2.0), **boxed(TWO)})
    pot = the_pot(state)
    left = {b: p for b, p in state.balls.items() if b not in ("cue", pot.target)}
    places = cue_after(POOL_TABLE, pot, dict(state.balls))
    assert places
    for x, y in places:
        assert R <= x <= POOL_TABLE.width - R and R <= y <= POOL_TABLE.length - R
        assert is_free((x, y), left, R)


def test_a_ball_in_hand_in_the_d_is_valued_from_fewer_places_all_in_the_d():
    """The look-ahead values the D from one arc of the places a shot's search tries."""
    state = State(game=Game.SNOOKER, balls=dict(rack(Game.SNOOKER, 1)), ball_in_hand="D")
    balls = {b: p for b, p in state.balls.items() if b != "cue"}
    fine = placements(state, SNOOKER, balls)
    coarse = placements(state, SNOOKER, balls, coarse=True)
    assert coarse and len(coarse) < len(fine) and set(coarse) <= set(fine)
    assert all(in_region(p, "D", SNOOKER) for p in coarse)


def test_a_weaker_rival_makes_less_of_the_same_table():
    """Priced as a rival who makes 0.6 of a sure pot, the opponent's sure 9 costs the bot
    less than an equal's would, by the same scale about KEEP_NOTHING; no pot costs the same."""
    sure = nineball({"cue": CUE, "9": ONE}).model_copy(update={"turn": 1})
    v = position_value(sure, NOISE)
    assert v > 0.8
    assert value_for(sure, 0, NOISE) == -v
    weaker = value_for(sure, 0, NOISE, 0.6)
    assert weaker == -theirs(sure, v, 0.6) > -v
    assert theirs(sure, KEEP_SURE, 0.6) == pytest.approx(0.6)
    assert theirs(sure, KEEP_NOTHING, 0.6) == KEEP_NOTHING
    assert value_for(sure, 1, NOISE, 0.6) == v  # the player to act prices only the other


def test_a_rival_prices_only_the_pool_games():
    state = State(game=Game.SNOOKER, balls=dict(rack(Game.SNOOKER, 1)), turn=1)
    assert theirs(state, 0.5, 0.6) == 0.5

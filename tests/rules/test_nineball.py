"""Nine-ball rules, one scripted shot per rule (see rules/nineball.py)."""

from __future__ import annotations

import math

import pytest

from rules.codes import FoulCode, NoteCode, Refusal
from rules.game import choose, play
from rules.inputs import Choice, Shot, Strike
from rules.nineball import new_game
from rules.spots import POOL_TABLE
from rules.state import State

from .script import codes, hit, jaw, pot, rail, refused, scripted, shoot

R = POOL_TABLE.R


def table(shots: int = 5, **fields) -> State:
    balls = {"cue": (0.6, 0.5), "3": (0.6, 1.2), "5": (0.3, 1.6), "9": (0.9, 1.9)}
    return State(game="nineball", balls=balls, shots=shots, **fields)


def test_break_that_pockets_a_ball_is_legal_and_the_breaker_continues():
    state, d = shoot(new_game(1), hit("cue", "1"), pot("4"))
    assert d.fouls == () and d.pocketed == ("4",)
    assert state.turn == 0 and state.ball_in_hand is None and "4" not in state.balls


def test_break_with_four_balls_to_a_cushion_is_legal():
    events = [hit("cue", "1"), *(rail(b) for b in ("2", "3", "5", "6"))]
    state, d = shoot(new_game(1), *events)
    assert d.fouls == () and state.turn == 1 and state.ball_in_hand is None


def test_break_with_three_balls_to_a_cushion_is_a_foul():
    events = [hit("cue", "1"), rail("cue"), *(rail(b) for b in ("2", "3", "5"))]
    state, d = shoot(new_game(1), *events)
    assert codes(d.fouls) == (FoulCode.ILLEGAL_BREAK,)
    assert state.turn == 1 and state.ball_in_hand == "anywhere"


def test_break_must_hit_the_one_first():
    events = [hit("cue", "2"), *(rail(b) for b in ("1", "3", "5", "6"))]
    _, d = shoot(new_game(1), *events)
    assert codes(d.fouls) == (FoulCode.WRONG_BALL_FIRST,) and d.fouls[0].ball == "2"


def test_nine_on_the_break_wins():
    state, d = shoot(new_game(1), hit("cue", "1"), hit("1", "9"), pot("9"))
    assert d.over and d.winner == 0 and state.scores == (1, 0) and state.over


def test_lowest_ball_must_be_hit_first():
    state, d = shoot(table(), hit("cue", "5"), rail("5"))
    assert codes(d.fouls) == (FoulCode.WRONG_BALL_FIRST,) and d.fouls[0].ball == "5"
    assert state.turn == 1 and state.ball_in_hand == "anywhere"


def test_no_cushion_after_contact_and_nothing_pocketed_is_a_foul():
    _, d = shoot(table(), hit("cue", "3"))
    assert codes(d.fouls) == (FoulCode.NO_RAIL,)


def test_a_cushion_before_contact_does_not_satisfy_the_rail_rule():
    _, d = shoot(table(), rail("cue"), hit("cue", "3"))
    assert codes(d.fouls) == (FoulCode.NO_RAIL,)


@pytest.mark.parametrize("after", [rail("cue"), rail("3"), jaw("5")])
def test_any_ball_to_a_cushion_or_jaw_after_contact_is_legal(after):
    state, d = shoot(table(), hit("cue", "3"), after)
    assert d.fouls == () and state.turn == 1 and state.ball_in_hand is None


def test_hitting_no_ball_is_a_foul():
    _, d = shoot(table(), rail("cue"), rail("cue", "top"))
    assert codes(d.fouls) == (FoulCode.NO_CONTACT,)


def test_scratch_is_a_foul_and_the_opponent_must_place_the_cue_ball():
    state, d = shoot(table(), hit("cue", "3"), rail("3"), pot("cue"))
    assert codes(d.fouls) == (FoulCode.CUE_POCKETED,)
    assert "cue" not in state.balls and state.ball_in_hand == "anywhere" and state.turn == 1
    with refused(Refusal.PLACE_REQUIRED):
        shoot(state, hit("cue", "3"), rail("3"))
    with refused(Refusal.PLACE_BLOCKED):
        shoot(state, hit("cue", "3"), rail("3"), place=(0.6, 1.2 + 1.5 * R))
    after, d2 = shoot(state, hit("cue", "3"), rail("3"), place=(0.2, 2.3))
    assert d2.fouls == () and after.balls["cue"] == (0.2, 2.3)


def test_legal_pot_continues_and_a_legal_miss_passes_the_turn():
    state, _ = shoot(table(), hit("cue", "3"), pot("3"))
    assert state.turn == 0 and "3" not in state.balls
    state, _ = shoot(state, hit("cue", "5"), rail("5"))
    assert state.turn == 1


def test_nine_pocketed_on_a_legal_shot_wins_in_combination():
    state, d = shoot(table(), hit("cue", "3"), hit("3", "9"), pot("9"))
    assert d.fouls == () and d.winner == 0 and state.over


def test_nine_pocketed_on_a_foul_is_respotted_on_the_foot_spot():
    state, d = shoot(table(), hit("cue", "5"), hit("5", "9"), pot("9"))
    assert d.fouls and not d.over
    assert d.respotted == {"9": POOL_TABLE.foot_spot} and state.balls["9"] == POOL_TABLE.foot_spot


def test_respotted_nine_goes_behind_a_ball_on_the_foot_spot_frozen_to_it():
    fx, fy = POOL_TABLE.foot_spot
    start = table().model_copy(update={"balls": {**table().balls, "5": (fx, fy + 0.01)}})
    state, _ = shoot(start, hit("cue", "5"), pot("9"))
    x, y = state.balls["9"]
    assert x == pytest.approx(fx) and y > fy + 0.01
    assert 2 * R < math.dist((x, y), state.balls["5"]) < 2 * R + 1e-5


def test_push_out_after_the_break_needs_no_contact_and_the_opponent_chooses():
    state, d = shoot(table(shots=1), rail("cue"), push_out=True)
    assert d.fouls == () and codes(d.notes) == (NoteCode.PUSH_OUT,)
    assert state.turn == 1 and state.pending == ("play_on", "play_again")
    with refused(Refusal.CHOICE_PENDING):
        shoot(state, hit("cue", "3"), rail("3"))
    back = choose(state, Choice(option="play_again"))
    assert back.turn == 0 and back.pending == ()
    on = choose(state, Choice(option="play_on"))
    assert on.turn == 1 and on.pending == ()


def test_push_out_only_on_the_shot_after_the_break():
    with refused(Refusal.NO_PUSH_OUT):
        shoot(table(shots=2), rail("cue"), push_out=True)


def test_nine_pocketed_on_a_push_out_is_respotted_and_a_push_out_scratch_is_a_foul():
    state, d = shoot(table(shots=1, visit=2, best=(2, 0)), hit("cue", "9"), pot("9"), push_out=True)
    assert not d.over and "9" in d.respotted and state.pending == ("play_on", "play_again")
    assert state.best == (2, 0)  # the 9 is back on the table: no ball of the visit
    state, d = shoot(table(shots=1), rail("cue"), pot("cue"), push_out=True)
    assert codes(d.fouls) == (FoulCode.CUE_POCKETED,) and state.ball_in_hand == "anywhere"
    assert state.pending == ()


def test_three_fouls_in_a_row_lose_the_rack():
    state, d = shoot(table(foul_streak=(1, 0)), hit("cue", "5"), rail("5"))
    assert state.foul_streak == (2, 0) and not d.over and codes(d.notes) == (NoteCode.FOUL_WARNING,)
    state, d = shoot(table(foul_streak=(2, 0)), hit("cue", "5"), rail("5"))
    assert d.over and d.winner == 1 and state.scores == (0, 1)
    assert codes(d.notes) == (NoteCode.THREE_FOULS,)


def test_a_legal_shot_resets_the_foul_count():
    state, _ = shoot(table(foul_streak=(2, 1)), hit("cue", "3"), rail("3"))
    assert state.foul_streak == (0, 1)


def test_inputs_out_of_turn_are_refused_and_change_nothing():
    state = table()
    with refused(Refusal.NOT_AN_OPTION):
        choose(state, Choice(option="play_on"))
    bad = Shot(strike=Strike(ball="3", speed=2.0, heading=0.0))
    with refused(Refusal.WRONG_CUE_BALL):
        play(state, bad, scripted([]))
    with refused(Refusal.NOT_IN_HAND):
        shoot(state, hit("cue", "3"), rail("3"), place=(0.3, 0.3))
    over, _ = shoot(table(), hit("cue", "3"), pot("9"))
    with refused(Refusal.GAME_OVER):
        shoot(over, hit("cue", "3"))
    assert state == table()


def test_the_visit_counts_balls_pocketed_until_the_turn_passes_or_a_foul():
    """A visit (the leaderboard's pool break) is kept by the referee in `State.visit`, and each
    player's best in `State.best`: the balls of one turn at the table, break included."""
    state, _ = shoot(new_game(1), hit("cue", "1"), pot("4"), pot("6"))
    assert state.turn == 0 and state.visit == 2 and state.best == (2, 0)
    state = state.evolve(balls={"cue": (0.6, 0.5), "3": (0.6, 1.2), "5": (0.3, 1.6)})
    state, _ = shoot(state, hit("cue", "3"), pot("3"))
    assert state.visit == 3 and state.best == (3, 0)
    state, _ = shoot(state, hit("cue", "5"), rail("5"))  # nothing pocketed: the turn passes
    assert state.turn == 1 and state.visit == 0 and state.best == (3, 0)
    state, d = shoot(state, hit("cue", "5"), pot("5"), pot("cue"))  # a ball down on a foul
    assert d.fouls and state.visit == 0 and state.best == (3, 0)


def test_a_foul_scores_no_visit_even_with_balls_down():
    state, d = shoot(table(visit=2, best=(2, 0)), hit("cue", "5"), pot("3"))
    assert d.fouls and state.turn == 1 and state.visit == 0 and state.best == (2, 0)

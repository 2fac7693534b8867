"""Three-cushion rules, one scripted shot per rule (see rules/three_cushion.py)."""

from __future__ import annotations

from rules.codes import FoulCode, NoteCode, Refusal
from rules.game import play
from rules.inputs import Shot, Strike
from rules.state import State
from rules.three_cushion import new_game

from .script import codes, hit, rail, refused, scripted, shoot

BALLS = {"white": (0.4, 0.7), "yellow": (0.7, 1.4), "red": (1.0, 2.1)}


def table(**fields) -> State:
    return State(game="three_cushion", balls=BALLS, shots=4, target=5, **fields)


def three(ball: str = "white") -> list[dict]:
    return [rail(ball, "left"), rail(ball, "top"), rail(ball, "right")]


def test_three_cushions_then_both_balls_is_a_point_and_the_player_continues():
    state, d = shoot(table(), *three(), hit("white", "red"), hit("white", "yellow"))
    assert d.points == (1, 0) and state.turn == 0 and state.visit == 1


def test_cushions_between_the_two_balls_count():
    _, d = shoot(table(), hit("white", "red"), *three(), hit("yellow", "white"))
    assert d.points == (1, 0)


def test_two_cushions_are_not_enough():
    state, d = shoot(table(), hit("white", "red"), *three()[:2], hit("white", "yellow"))
    assert d.points == (0, 0) and state.turn == 1
    assert codes(d.notes) == (NoteCode.NO_POINT_CUSHIONS,)


def test_cushions_after_the_second_ball_do_not_count():
    _, d = shoot(table(), hit("white", "red"), rail("white"), hit("white", "yellow"), *three())
    assert d.points == (0, 0)


def test_object_balls_cushions_and_ball_contacts_do_not_count():
    events = [hit("white", "red"), *three("red"), hit("red", "yellow"), hit("white", "red")]
    _, d = shoot(table(), *events)
    assert d.points == (0, 0) and codes(d.notes) == (NoteCode.NO_POINT_CONTACT,)


def test_break_must_hit_the_red_first():
    _, d = shoot(new_game(3, target=5), hit("white", "yellow"), *three(), hit("white", "red"))
    assert d.points == (0, 0) and codes(d.fouls) == (FoulCode.BREAK_NOT_RED,)
    _, d = shoot(new_game(3, target=5), hit("white", "red"), *three(), hit("white", "yellow"))
    assert d.points == (1, 0)


def test_second_player_strikes_the_yellow():
    state = table(turn=1)
    wrong = Shot(strike=Strike(ball="white", speed=2.0, heading=0.0))
    with refused(Refusal.WRONG_CUE_BALL):
        play(state, wrong, scripted(three()))
    after, d = shoot(state, *three("yellow"), hit("yellow", "red"), hit("yellow", "white"))
    assert d.points == (0, 1) and after.turn == 1


def test_run_is_the_points_of_one_inning_and_the_race_ends_at_target():
    state = table(scores=(3, 2))
    state, _ = shoot(state, *three(), hit("white", "red"), hit("white", "yellow"))
    assert state.visit == 1 and state.best == (1, 0) and not state.over
    state, d = shoot(state, *three(), hit("white", "red"), hit("white", "yellow"))
    assert d.over and d.winner == 0 and state.scores == (5, 2) and state.best == (2, 0)


def test_a_miss_ends_the_run():
    state, _ = shoot(table(visit=3, best=(3, 0)), hit("white", "red"))
    assert state.visit == 0 and state.best == (3, 0) and state.turn == 1

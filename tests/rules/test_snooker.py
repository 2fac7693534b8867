"""Snooker rules, one scripted shot per rule (see rules/snooker.py)."""

from __future__ import annotations

import math

import pytest

from rules.codes import FoulCode, NoteCode, Refusal
from rules.game import choose
from rules.inputs import Choice
from rules.spots import SNOOKER, SNOOKER_SPOTS
from rules.state import State

from .script import codes, hit, pot, rail, refused, shoot

R = SNOOKER.R
MID = SNOOKER.width / 2


def table(reds: int = 2, on: str = "red", **fields) -> State:
    balls = dict(SNOOKER_SPOTS)
    balls["cue"] = (0.5, 1.0)
    reds_at = [(0.5, 2.2), (1.3, 2.2), (MID, 3.345), (MID, 3.445)]
    balls.update({f"red{i + 1}": reds_at[i] for i in range(reds)})
    return State(game="snooker", balls=balls, shots=10, on=on, **fields)


def test_potting_a_red_scores_one_and_a_colour_is_on_next():
    state, d = shoot(table(), hit("cue", "red1"), pot("red1"))
    assert d.fouls == () and d.points == (1, 0) and state.on == "colour" and state.turn == 0
    assert state.visit == 1


def test_colour_after_a_red_scores_its_value_and_is_respotted():
    state, d = shoot(table(on="colour", visit=1), hit("cue", "pink"), pot("pink"))
    assert d.points == (6, 0) and d.respotted == {"pink": SNOOKER_SPOTS["pink"]}
    assert state.on == "red" and state.visit == 7 and state.best == (7, 0)


def test_nominated_colour_must_be_hit_first():
    _, d = shoot(table(on="colour"), hit("cue", "pink"), rail("pink"), nominate="blue")
    assert (
        codes(d.fouls) == (FoulCode.WRONG_BALL_FIRST,)
        and d.fouls[0].ball == "pink"
        and d.points == (0, 6)
    )


def test_potting_a_colour_when_on_a_red_is_a_foul_valued_at_the_colour():
    state, d = shoot(table(), hit("cue", "red1"), pot("pink"))
    assert (
        codes(d.fouls) == (FoulCode.POCKETED_NOT_ON,)
        and d.fouls[0].ball == "pink"
        and d.points == (0, 6)
    )
    assert state.balls["pink"] == SNOOKER_SPOTS["pink"] and state.turn == 1
    assert state.pending == ("play_on", "play_again")  # the red was hit: not a miss


def test_missing_every_ball_costs_at_least_four():
    _, d = shoot(table(), rail("cue"))
    assert codes(d.fouls) == (FoulCode.NO_CONTACT,) and d.points == (0, 4)


def test_hitting_a_higher_ball_first_costs_its_value():
    _, d = shoot(table(), hit("cue", "black"), rail("black"))
    assert d.points == (0, 7)


def test_in_off_gives_ball_in_hand_in_the_d_and_the_choice_to_the_opponent():
    state, d = shoot(table(), hit("cue", "red1"), pot("red1"), pot("cue"))
    assert codes(d.fouls) == (FoulCode.CUE_POCKETED,) and d.points == (0, 4)
    assert "red1" not in state.balls  # reds pocketed on a foul stay down
    assert state.turn == 1 and state.ball_in_hand == "D"
    again = choose(state, Choice(option="play_again"))
    assert again.turn == 0 and again.ball_in_hand == "D" and "cue" not in again.balls
    with refused(Refusal.OUTSIDE_REGION):
        shoot(again, hit("cue", "red2"), rail("red2"), place=(MID, 1.5))
    placed, _ = shoot(again, hit("cue", "red2"), rail("red2"), place=(MID - 0.1, 0.6))
    assert placed.balls["cue"] == (MID - 0.1, 0.6)


def test_colour_goes_to_the_highest_free_spot_when_its_own_is_covered():
    moved = {"red1": SNOOKER_SPOTS["pink"], "black": (0.3, 3.0)}
    _, d = shoot(table(), hit("cue", "red1"), pot("pink"), moved=moved)
    assert d.respotted == {"pink": SNOOKER_SPOTS["black"]}


def test_colour_goes_toward_the_top_cushion_when_every_spot_is_covered():
    px, py = SNOOKER_SPOTS["pink"]
    moved = {"red1": (px, py)}
    # Every other spot holds its own colour; the pink lands behind the red, frozen to it.
    _, d = shoot(table(), hit("cue", "red1"), pot("pink"), moved=moved)
    x, y = d.respotted["pink"]
    assert x == pytest.approx(px) and y > py
    assert 2 * R < math.dist((x, y), (px, py)) < 2 * R + 1e-5


def test_black_goes_below_its_spot_when_the_way_to_the_top_cushion_is_blocked():
    bx, by = SNOOKER_SPOTS["black"]
    # red1 on the spot, red3 and red4 (from the table) and red2 fill the line to the cushion.
    moved = {"red1": (bx, by), "red2": (bx, 3.54)}
    state, d = shoot(table(reds=4), hit("cue", "red1"), pot("black"), moved=moved)
    x, y = d.respotted["black"]
    assert x == pytest.approx(bx) and by - 2 * R - 1e-5 < y < by - 2 * R
    others = [p for b, p in state.balls.items() if b != "black"]
    assert all(math.dist((x, y), p) > 2 * R for p in others)


def test_colours_stage_potted_colour_stays_down_and_the_next_is_on():
    state, d = shoot(table(reds=0, on="yellow"), hit("cue", "yellow"), pot("yellow"))
    assert d.points == (2, 0) and "yellow" not in state.balls and state.on == "green"
    assert state.turn == 0


def test_colours_stage_potting_the_wrong_colour_is_a_foul_and_it_is_respotted():
    state, d = shoot(table(reds=0, on="yellow"), hit("cue", "yellow"), pot("green"))
    assert (
        codes(d.fouls) == (FoulCode.POCKETED_NOT_ON,)
        and d.fouls[0].ball == "green"
        and d.points == (0, 4)
    )
    assert state.balls["green"] == SNOOKER_SPOTS["green"] and state.on == "yellow"


def test_colour_after_the_last_red_is_respotted_and_yellow_is_on_next():
    state, d = shoot(table(reds=0, on="colour"), hit("cue", "pink"), pot("pink"))
    assert d.points == (6, 0) and state.balls["pink"] == SNOOKER_SPOTS["pink"]
    assert state.on == "yellow"
    state, d = shoot(table(reds=0, on="colour"), hit("cue", "pink"), rail("pink"))
    assert d.fouls == () and state.turn == 1 and state.on == "yellow"


def snookered_table() -> State:
    """One red straight behind the blue from the cue ball: snookered on the red."""
    balls = dict(SNOOKER_SPOTS)
    balls.update({"cue": (MID, 1.2), "red1": (MID, 2.3)})
    return State(game="snooker", balls=balls, shots=10, on="red")


def test_free_ball_after_a_foul_that_leaves_the_opponent_snookered():
    state, d = shoot(snookered_table().model_copy(update={"turn": 1}), rail("cue"))
    assert state.free_ball and NoteCode.FREE_BALL in codes(d.notes)
    state = choose(state, Choice(option="play_on"))
    after, d = shoot(state, hit("cue", "blue"), pot("blue"), nominate="blue")
    assert d.fouls == () and d.points == (1, 0) and after.on == "colour"
    assert after.balls["blue"] == SNOOKER_SPOTS["blue"]
    with refused(Refusal.BAD_NOMINATION):
        shoot(state, hit("cue", "red1"), rail("red1"), nominate="red1")


def test_no_free_ball_when_not_snookered_and_nothing_to_nominate():
    state, _ = shoot(table(turn=1), rail("cue"))
    assert not state.free_ball
    with refused(Refusal.BAD_NOMINATION):
        shoot(choose(state, Choice(option="play_on")), hit("cue", "blue"), nominate="blue")


def test_miss_when_not_snookered_lets_the_opponent_have_the_balls_replaced():
    start = table(scores=(10, 20))
    moved = {"cue": (0.2, 3.0), "pink": (1.0, 3.1)}
    state, d = shoot(start, hit("cue", "pink"), rail("pink"), moved=moved)
    assert NoteCode.MISS in codes(d.notes) and "replace" in state.pending
    back = choose(state, Choice(option="replace"))
    assert back.balls == start.balls and back.turn == 0 and back.scores == (10, 26)


def test_no_miss_when_snookered():
    state, d = shoot(snookered_table(), hit("cue", "blue"), rail("blue"))
    assert d.fouls and "replace" not in state.pending and d.points == (0, 5)


def test_last_black_potted_ends_the_frame():
    balls = {"cue": (MID, 2.5), "black": SNOOKER_SPOTS["black"]}
    state = State(game="snooker", balls=balls, shots=50, on="black", scores=(40, 30))
    end, d = shoot(state, hit("cue", "black"), pot("black"))
    assert d.over and d.winner == 0 and end.scores == (47, 30)


def test_a_foul_on_the_last_black_ends_the_frame():
    balls = {"cue": (MID, 2.5), "black": SNOOKER_SPOTS["black"]}
    state = State(game="snooker", balls=balls, shots=50, on="black", scores=(30, 40))
    end, d = shoot(state, hit("cue", "black"), pot("cue"))
    assert d.over and d.winner == 1 and end.scores == (30, 47)


def test_tie_on_the_last_black_respots_it_with_ball_in_hand():
    balls = {"cue": (MID, 2.5), "black": SNOOKER_SPOTS["black"]}
    state = State(game="snooker", balls=balls, shots=50, on="black", scores=(26, 33))
    end, d = shoot(state, hit("cue", "black"), pot("black"))
    assert not d.over and end.scores == (33, 33)
    assert end.balls == {"black": SNOOKER_SPOTS["black"]} and end.ball_in_hand == "D"
    assert end.on == "black" and codes(d.notes) == (NoteCode.BLACK_RESPOTTED,)


def test_the_break_is_the_points_of_one_visit():
    state, _ = shoot(table(), hit("cue", "red1"), pot("red1"))
    state, _ = shoot(state, hit("cue", "black"), pot("black"))
    assert state.visit == 8 and state.best == (8, 0)
    state, _ = shoot(state, hit("cue", "red2"), rail("red2"))
    assert state.visit == 0 and state.best == (8, 0) and state.turn == 1
    state, _ = shoot(state, hit("cue", "red2"), pot("red2"))
    assert state.visit == 1 and state.best == (8, 1)


def test_only_colours_can_be_nominated_after_a_red():
    with refused(Refusal.BAD_NOMINATION):
        shoot(table(on="colour"), hit("cue", "red1"), nominate="red1")
    with refused(Refusal.BAD_NOMINATION):
        shoot(table(), hit("cue", "red1"), nominate="blue")


def test_a_free_ball_must_not_leave_the_opponent_snookered_behind_it():
    fouled, _ = shoot(snookered_table().model_copy(update={"turn": 1}), rail("cue"))
    state = choose(fouled, Choice(option="play_on"))
    # The blue (the free ball) stays between the cue ball and the only red.
    _, d = shoot(state, hit("cue", "blue"), rail("blue"), nominate="blue")
    assert codes(d.fouls) == (FoulCode.FREE_BALL_SNOOKER,) and d.fouls[0].ball == "blue"
    assert d.points == (0, 4)
    # Moved out of the way, it is a fair free-ball shot.
    _, d = shoot(state, hit("cue", "blue"), rail("blue"), nominate="blue", moved={"blue": (0.3, 1)})
    assert d.fouls == ()

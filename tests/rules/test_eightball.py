"""Eight-ball rules, one scripted shot per rule (see rules/eightball.py)."""

from __future__ import annotations

from rules.codes import FoulCode, NoteCode, Refusal
from rules.eightball import new_game
from rules.spots import POOL_TABLE, is_free
from rules.state import State

from .script import codes, hit, pot, rail, refused, shoot


def table(groups=(None, None), **fields) -> State:
    balls = {"cue": (0.6, 0.5), "2": (0.6, 1.2), "10": (0.3, 1.6), "8": (0.9, 1.9)}
    return State(game="eightball", balls=balls, shots=5, groups=groups, **fields)


def on_eight(**fields) -> State:
    """P1 (solids) has cleared the group: only the 8 and a stripe are left."""
    balls = {"cue": (0.6, 0.5), "10": (0.3, 1.6), "8": (0.9, 1.9)}
    return State(game="eightball", balls=balls, shots=9, groups=("solids", "stripes"), **fields)


def test_legal_break_with_a_pot_continues_and_the_table_stays_open():
    state, d = shoot(new_game(2), hit("cue", "3"), pot("3"))
    assert d.fouls == () and state.turn == 0 and state.groups == (None, None)


def test_illegal_break_gives_ball_in_hand_behind_the_head_string():
    state, d = shoot(new_game(2), hit("cue", "3"), rail("3"), rail("4"))
    assert codes(d.fouls) == (FoulCode.ILLEGAL_BREAK,)
    assert state.turn == 1 and state.ball_in_hand == "kitchen"
    with refused(Refusal.OUTSIDE_REGION):
        shoot(state, hit("cue", "3"), rail("3"), place=(0.6, POOL_TABLE.length / 2))
    placed, _ = shoot(state, hit("cue", "3"), rail("3"), place=(0.4, 0.3))
    assert placed.balls["cue"] == (0.4, 0.3)


def test_scratch_on_a_legal_break_is_a_foul_with_ball_in_hand_in_the_kitchen():
    state, d = shoot(new_game(2), hit("cue", "3"), pot("3"), pot("cue"))
    assert codes(d.fouls) == (FoulCode.CUE_POCKETED,) and state.ball_in_hand == "kitchen"
    assert "3" not in state.balls


def test_eight_on_the_break_is_respotted_and_the_breaker_continues():
    state, d = shoot(new_game(2), hit("cue", "3"), pot("8"), pot("3"))
    assert not d.over and state.turn == 0
    assert state.visit == 1 and state.best == (1, 0)  # the 3; the 8 is back on the table
    # The rack still covers the foot spot: the 8 goes behind it on the long string.
    x, y = d.respotted["8"]
    assert x == POOL_TABLE.foot_spot[0] and y > POOL_TABLE.foot_spot[1]
    assert is_free((x, y), {b: p for b, p in state.balls.items() if b != "8"}, POOL_TABLE.R)


def test_eight_and_a_scratch_on_the_break_respot_the_eight_for_the_opponent():
    state, d = shoot(new_game(2), hit("cue", "3"), pot("8"), pot("cue"))
    assert not d.over and "8" in state.balls and state.turn == 1
    assert state.ball_in_hand == "kitchen"


def test_open_table_the_eight_may_not_be_hit_first():
    state, d = shoot(table(), hit("cue", "8"), rail("8"))
    assert codes(d.fouls) == (FoulCode.WRONG_BALL_FIRST,) and d.fouls[0].ball == "8"
    assert state.ball_in_hand == "anywhere" and state.turn == 1


def test_open_table_first_ball_pocketed_chooses_the_group():
    state, d = shoot(table(), hit("cue", "2"), pot("10"), pot("2"))
    assert d.fouls == () and state.groups == ("stripes", "solids") and state.turn == 0
    state, _ = shoot(table(turn=1), hit("cue", "10"), pot("2"))
    assert state.groups == ("stripes", "solids") and state.turn == 1


def test_own_group_must_be_hit_first():
    _, d = shoot(table(("solids", "stripes")), hit("cue", "10"), pot("10"))
    assert codes(d.fouls) == (FoulCode.WRONG_BALL_FIRST,) and d.fouls[0].ball == "10"


def test_pocketing_only_the_opponents_ball_passes_the_turn():
    state, d = shoot(table(("solids", "stripes")), hit("cue", "2"), pot("10"))
    assert d.fouls == () and state.turn == 1 and "10" not in state.balls


def test_no_cushion_after_contact_is_a_foul():
    _, d = shoot(table(("solids", "stripes")), hit("cue", "2"))
    assert codes(d.fouls) == (FoulCode.NO_RAIL,)


def test_early_eight_loses():
    state, d = shoot(table(("solids", "stripes")), hit("cue", "2"), pot("8"))
    assert d.over and d.winner == 1 and state.scores == (0, 1)
    assert codes(d.notes)[-1] == NoteCode.EIGHT_EARLY


def test_eight_in_the_called_pocket_wins():
    _, d = shoot(on_eight(), hit("cue", "8"), pot("8", "top_right"), call="top_right")
    assert d.over and d.winner == 0


def test_eight_in_another_pocket_loses():
    _, d = shoot(on_eight(), hit("cue", "8"), pot("8", "top_left"), call="top_right")
    assert d.over and d.winner == 1 and codes(d.notes)[-1] == NoteCode.EIGHT_WRONG_POCKET


def test_scratch_on_the_eight_loses():
    _, d = shoot(on_eight(), hit("cue", "8"), pot("8", "top_right"), pot("cue"), call="top_right")
    assert d.over and d.winner == 1 and codes(d.fouls) == (FoulCode.CUE_POCKETED,)


def test_on_the_eight_it_must_be_hit_first_and_called():
    _, d = shoot(on_eight(), hit("cue", "10"), rail("10"), call="top_left")
    assert codes(d.fouls) == (FoulCode.WRONG_BALL_FIRST,) and d.fouls[0].ball == "10"
    with refused(Refusal.CALL_REQUIRED):
        shoot(on_eight(), hit("cue", "8"), rail("8"))
    with refused(Refusal.NO_CALL):
        shoot(table(("solids", "stripes")), hit("cue", "2"), rail("2"), call="top_left")


def test_the_visit_counts_every_ball_of_a_turn_at_the_table():
    state, _ = shoot(
        table(groups=("solids", "stripes"), visit=1, best=(1, 4)), hit("cue", "2"), pot("2")
    )
    assert state.turn == 0 and state.visit == 2 and state.best == (2, 4)
    # The 8 is on (called), and missed: the turn passes and the visit ends.
    state, _ = shoot(state, hit("cue", "8"), rail("8"), call="top_left")
    assert state.turn == 1 and state.visit == 0 and state.best == (2, 4)

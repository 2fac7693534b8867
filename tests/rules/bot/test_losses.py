"""Why a game was lost (rules.bot.losses): each class from a game written to show it, and the
arena's counts adding up to the games each side lost."""

from __future__ import annotations

import pytest

from rules.bot.arena import arena
from rules.bot.candidates import Kind
from rules.bot.chooser import Picker
from rules.bot.losses import Loss, Turn, classify
from rules.bot.noise import tournament
from rules.codes import FoulCode, NoteCode
from rules.inputs import Choice, Shot, Strike
from rules.racks import Game
from rules.state import Decision, Foul, Note

SHOT = Shot(strike=Strike(ball="cue", speed=2.0, heading=90.0))
PUSH = SHOT.model_copy(update={"push_out": True})
A, B = 0, 1  # A loses every game below


def turn(seat: int, kind: Kind | None = Kind.POT, *, potted=(), foul=False, note=None, act=SHOT):
    fouls = (Foul(code=FoulCode.CUE_POCKETED, reason="scratch"),) if foul else ()
    notes = (Note(code=note, text=str(note)),) if note else ()
    nxt = seat if potted and not foul else 1 - seat
    decision = Decision(
        player=seat, pocketed=tuple(potted), fouls=fouls, notes=notes, next_player=nxt
    )
    return Turn(seat, act, kind, decision)


def run_out(seat: int) -> list[Turn]:
    """The winner's last visit: two pots, the last one winning."""
    return [turn(seat, potted=("8",)), turn(seat, potted=("9",))]


def test_the_opponent_ran_out_from_the_break():
    assert classify([turn(B, Kind.BREAK, potted=("3",)), *run_out(B)], A) == Loss.BREAK_AND_RUN


def test_a_break_that_handed_over_the_table():
    assert classify([turn(A, Kind.BREAK), *run_out(B)], A) == Loss.BREAK


@pytest.mark.parametrize(
    "last, loss",
    [
        (turn(A, Kind.POT), Loss.MISSED_POT),
        (turn(A, Kind.BANK), Loss.MISSED_POT),
        (turn(A, Kind.CONTACT), Loss.SAFETY),
        (turn(A, Kind.KICK, foul=True), Loss.FOUL),
        (turn(A, Kind.PUSH_OUT, act=PUSH), Loss.PUSH_OUT),
        (turn(A, None, act=Choice(option="play_on")), Loss.CHOICE),
        (turn(A, None), Loss.OTHER),
    ],
)
def test_the_act_that_ended_the_losers_last_visit(last, loss):
    opening = [turn(A, Kind.BREAK, potted=("2",)), turn(A, Kind.POT, potted=("1",))]
    between = [turn(B, Kind.CONTACT)]
    game = [*opening[:1], turn(A, Kind.CONTACT), *between, last, *run_out(B)]
    assert classify(game, A) == loss


def test_a_safety_after_pots_in_the_same_visit_is_position_left():
    visit = [turn(A, Kind.POT, potted=("1",)), turn(A, Kind.POT, potted=("2",))]
    game = [turn(B, Kind.BREAK), *visit, turn(A, Kind.CONTACT), *run_out(B)]
    assert classify(game, A) == Loss.POSITION
    # The same safety at the start of a visit is a safety that failed.
    assert classify([turn(B, Kind.BREAK), turn(A, Kind.CONTACT), *run_out(B)], A) == Loss.SAFETY


def test_losing_on_ones_own_shot():
    early = turn(A, Kind.POT, potted=("8",), note=NoteCode.EIGHT_EARLY)
    assert classify([turn(B, Kind.BREAK), early], A) == Loss.FOUL
    third = turn(A, Kind.CONTACT, foul=True, note=NoteCode.THREE_FOULS)
    assert classify([turn(B, Kind.BREAK), third], A) == Loss.THREE_FOULS


@pytest.mark.parametrize("game", [Game.NINEBALL, Game.EIGHTBALL])
def test_the_arena_classifies_every_game_lost(game):
    result = arena(game, Picker(), Picker(), 4, seed=11, noise=tournament(1.0))
    for me, them in (("a", "b"), ("b", "a")):
        assert sum(result[me]["losses"].values()) == result[them]["wins"]
        assert set(result[me]["losses"]) <= {str(k) for k in Loss}

"""Codes for everything a referee says: refusals of an input, fouls and notes of a shot.

`RuleError` is the refusal itself: raised before anything is simulated, with a `Refusal` code
beside its words, so a server can answer `rejected {code, reason}`.

Each code travels beside its words: clients show, translate or test the code and read the
words, so a sentence can be reworded without breaking anyone. The values are the wire form.
"""

from __future__ import annotations

from enum import StrEnum


class Refusal(StrEnum):
    """Why an input was refused (`RuleError.code`). Nothing changed when one is given."""

    MALFORMED = "malformed"  # not a valid input: wrong type, out of range, NaN, unknown field
    GAME_OVER = "game_over"
    CHOICE_PENDING = "choice_pending"  # a choice must be made before anyone shoots
    NOT_AN_OPTION = "not_an_option"  # a choice that is not on offer
    WRONG_CUE_BALL = "wrong_cue_ball"
    NOT_IN_HAND = "not_in_hand"  # a placement without ball in hand
    PLACE_REQUIRED = "place_required"  # the cue ball is off the table: a placement is needed
    OUTSIDE_REGION = "outside_region"  # placement outside the ball-in-hand region
    PLACE_BLOCKED = "place_blocked"  # placement on or against another ball
    NO_PUSH_OUT = "no_push_out"
    CALL_REQUIRED = "call_required"
    NO_CALL = "no_call"
    BAD_NOMINATION = "bad_nomination"
    ENGINE_VERSION = "engine_version"  # a record played under another engine
    REPLAY_DIFFERS = "replay_differs"  # a record whose replay is not the game it states
    BAD_POSITION = "bad_position"  # a set-up position that cannot start a rack


class FoulCode(StrEnum):
    CUE_POCKETED = "cue_pocketed"  # pool's scratch, snooker's in-off
    NO_CONTACT = "no_contact"
    WRONG_BALL_FIRST = "wrong_ball_first"
    NO_RAIL = "no_rail"  # nothing pocketed and no cushion after contact
    ILLEGAL_BREAK = "illegal_break"
    POCKETED_NOT_ON = "pocketed_not_on"
    FREE_BALL_SNOOKER = "free_ball_snooker"  # a free ball that snookers the opponent
    BREAK_NOT_RED = "break_not_red"  # three-cushion's break must hit the red first


class NoteCode(StrEnum):
    PUSH_OUT = "push_out"
    FOUL_WARNING = "foul_warning"  # one more foul loses the rack
    THREE_FOULS = "three_fouls"
    EIGHT_ON_BREAK = "eight_on_break"
    EIGHT_EARLY = "eight_early"  # the 8 down before the group was cleared
    EIGHT_ON_FOUL = "eight_on_foul"
    EIGHT_WRONG_POCKET = "eight_wrong_pocket"
    EIGHT_CALLED = "eight_called"  # the 8 in the called pocket: the rack is won
    GROUP_TAKEN = "group_taken"
    POINT = "point"
    NO_POINT_CUSHIONS = "no_point_cushions"  # both balls hit, too few cushions before the second
    NO_POINT_CONTACT = "no_point_contact"  # not both object balls hit
    BLACK_RESPOTTED = "black_respotted"  # scores level at the end of the frame
    MISS = "miss"
    FREE_BALL = "free_ball"


class RuleError(ValueError):
    """An input the rules do not allow here (out of turn, a bad placement, a wrong choice).

    Raised before anything is simulated, so a rejected input changes nothing. `code` says which
    rule refused it, `reason` (also `str(error)`) says so in words. Pickles with both, so a
    worker process can raise it to the game service.
    """

    def __init__(self, code: Refusal, reason: str) -> None:
        super().__init__(code, reason)
        self.code = Refusal(code)
        self.reason = reason

    def __str__(self) -> str:
        return self.reason

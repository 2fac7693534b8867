"""Rules shared by nine-ball and eight-ball (WPA): the contact fouls, the legal break, respots.

A shot is legal when the cue ball stays on the table, first hits a ball the shooter may hit,
and afterwards some ball is pocketed or some ball (the cue ball included) touches a cushion.
A break is legal when a ball is pocketed or at least four object balls touch a cushion.
"""

from __future__ import annotations

from collections.abc import Mapping

from rules.codes import FoulCode
from rules.events import ShotFacts
from rules.inputs import ShotOptions
from rules.spots import POOL_SIZES, STANDARD_SIZE, Point, place_near
from rules.state import Decision, Foul, Note, Region, State, award, conclude, foul

POCKETS = ("bottom_left", "bottom_right", "middle_left", "middle_right", "top_left", "top_right")

#: Balls to a cushion that make a break legal when nothing is pocketed.
BREAK_CUSHION_BALLS = 4


#: What a pool shot may declare when the game has nothing special on.
PLAIN = ShotOptions()


def contact_fouls(facts: ShotFacts, targets: frozenset[str], wanted: str, rail: bool) -> list[Foul]:
    """The fouls of an ordinary shot: scratch, no contact, wrong ball first, no rail.

    `wanted` names the legal first ball(s) for the reason ("the 3", "one of the solids");
    `rail` is False on the break, where the legal-break rule replaces the rail rule.
    """
    fouls = []
    if facts.cue_pocketed:
        fouls.append(SCRATCH)
    if facts.first_hit is None:
        fouls.append(foul(FoulCode.NO_CONTACT, "cue ball hit no ball"))
    elif facts.first_hit not in targets:
        why = f"cue ball did not hit {wanted} first (hit the {facts.first_hit})"
        fouls.append(foul(FoulCode.WRONG_BALL_FIRST, why, facts.first_hit))
    elif rail and not facts.pocketed and not facts.cushion_after_contact:
        why = "no ball was pocketed and no ball reached a cushion after contact"
        fouls.append(foul(FoulCode.NO_RAIL, why))
    return fouls


SCRATCH = foul(FoulCode.CUE_POCKETED, "cue ball pocketed (scratch)")


def break_fouls(facts: ShotFacts) -> list[Foul]:
    if facts.pocketed or len(facts.cushioned) >= BREAK_CUSHION_BALLS:
        return []
    why = (
        f"illegal break: no ball pocketed and only {len(facts.cushioned)} object balls "
        f"reached a cushion (at least {BREAK_CUSHION_BALLS} needed)"
    )
    return [foul(FoulCode.ILLEGAL_BREAK, why)]


def object_balls(balls: Mapping[str, Point]) -> list[str]:
    return [b for b in balls if b != "cue"]


def respot_on_foot_spot(positions: dict[str, Point], size: int = STANDARD_SIZE) -> Point:
    """Where a respotted ball goes on the `size` ft table: the foot spot, else frozen behind
    it on the long string toward the top cushion, else in front of it toward the head (WPA)."""
    on = POOL_SIZES[size]
    return place_near(on.foot_spot, ((0.0, 1.0), (0.0, -1.0)), positions, on)


def conclude_rack(
    state: State,
    facts: ShotFacts,
    balls: dict[str, Point],
    verdict: tuple[int, Region | None, int | None],
    fouls: list[Foul],
    respotted: dict[str, Point],
    notes: list[Note],
    **fields,
) -> tuple[State, Decision]:
    """`conclude` for a pool rack: `balls` after respots; verdict: (next player, ball in hand,
    winner), the winner scoring the rack; `fields`: other State fields the shot changed."""
    nxt, bih, winner = verdict
    return conclude(
        state,
        balls=balls,
        next_player=nxt,
        fouls=fouls,
        points=award(winner, 1) if winner is not None else (0, 0),
        pocketed=tuple(facts.pocketed),
        respotted=respotted,
        notes=notes,
        ball_in_hand=bih,
        winner=winner,
        **visit_after(state, _kept_down(facts, respotted), bool(fouls), nxt),
        **fields,
    )


def _kept_down(facts: ShotFacts, respotted: dict[str, Point]) -> int:
    """The balls a shot pocketed that stay down: a respotted one (nine-ball's 9 on a foul or a
    push-out, eight-ball's 8 on the break) is not pocketed for the visit. Before, it counted,
    and a break could score more than the balls it took off the table."""
    return sum(1 for ball in facts.pocketed if ball not in respotted)


def visit_after(state: State, pocketed: int, fouled: bool, next_player: int) -> dict[str, object]:
    """The `visit` and `best` fields after a pool shot: a visit counts the balls pocketed on
    the shots of one player's turn at the table (the break included), a foul scores nothing
    and ends it, and it ends when the turn passes; `best` is each player's highest visit (the
    leaderboard's nine-ball and eight-ball break)."""
    me = state.turn
    visit = 0 if fouled else state.visit + pocketed
    best = list(state.best)
    best[me] = max(best[me], visit)
    return {"visit": visit if next_player == me and not fouled else 0, "best": tuple(best)}

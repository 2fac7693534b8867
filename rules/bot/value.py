"""What a position is worth, and what a simulated shot earned: the bot's judgement of outcomes.

Everything here reads the referee's states and decisions (rules.game.play produced them); the
rules are never written again. The scale is a win probability turned into [-1, 1]: a game won
is +1, lost -1. A position is worth to the player to act in it what their best next pot
promises (`position_value`: the one-level look-ahead, from the straight pots they would have,
their chance estimated by rules.bot.geometry, a ball in hand included), and to the opponent
minus that; in snooker and three-cushion the points a shot scores count besides. A choice
pending after a foul is valued as its chooser will make it, through the referee's `choose`.

The shape (keep the table: between KEEP_NOTHING and KEEP_SURE; give it away: minus the
same for the opponent) makes a pot that leaves no next shot worth less than a safety that
leaves the opponent none, and any miss that leaves an easy pot costly.
"""

from __future__ import annotations

from rules.bot.geometry import pots
from rules.bot.noise import Noise
from rules.bot.placements import placements
from rules.game import Outcome, choose
from rules.inputs import OPTIONS, Choice
from rules.racks import Game
from rules.referee import referee, table_of
from rules.snooker import value as snooker_value
from rules.spots import Point, Table
from rules.state import State, other

#: A game won (lost: the opposite).
WIN = 1.0
#: What having the table is worth with no pot on, and with a certain one.
KEEP_NOTHING, KEEP_SURE = -0.2, 0.9
#: Worth of one point scored, per game (pool games score racks, which end the game).
POINT = {Game.NINEBALL: 0.0, Game.EIGHTBALL: 0.0, Game.SNOOKER: 0.06, Game.THREE_CUSHION: 0.8}
#: A ball in hand anywhere is worth at least a pot of this chance: where no place for a pot
#: is found, the player still chooses the table he plays from (a safety, a bank, a kick).
IN_HAND_ANYWHERE = 0.5


def _ball_points(state: State, ball: str) -> int:
    """Points a pot of `ball` scores now (snooker; nothing in the pool games)."""
    return snooker_value(ball) if state.game == Game.SNOOKER else 0


def keep(state: State, p: float, points: float) -> float:
    """The worth of having the table with a best pot of chance `p` that scores `points`."""
    return KEEP_NOTHING + (KEEP_SURE - KEEP_NOTHING) * p + POINT[state.game] * points * p


def _best_from(state: State, table: Table, cue: Point, balls: dict[str, Point], noise: Noise):
    now = referee(state.game).targets(state, balls)
    return max(
        (
            keep(state, a.chance, _ball_points(state, a.target))
            for a in pots(table, cue, balls, now, noise)
        ),
        default=keep(state, 0.0, 0),
    )


def position_value(state: State, noise: Noise) -> float:
    """What `state` is worth to the player to act in it (no choice pending)."""
    table = table_of(state)
    if not table.pockets:
        return 0.0
    if not state.ball_in_hand:
        return _best_from(state, table, state.balls["cue"], dict(state.balls), noise)
    balls = {b: p for b, p in state.balls.items() if b != "cue"}
    spots = placements(state, table, balls) + ([state.balls["cue"]] if "cue" in state.balls else [])
    floor = IN_HAND_ANYWHERE if state.ball_in_hand == "anywhere" else 0.0
    values = (_best_from(state, table, p, {**balls, "cue": p}, noise) for p in spots)
    return max([keep(state, floor, 0), *values])


def choice_values(state: State, noise: Noise) -> dict[str, float]:
    """Each option pending in `state`, valued for the player who chooses (the one to act)."""
    chooser = state.turn
    return {
        option: value_for(choose(state, Choice(option=option)), chooser, noise)
        for option in OPTIONS
        if option in state.pending
    }


def value_for(state: State, me: int, noise: Noise) -> float:
    """What `state` is worth to player `me` (whoever is to act in it)."""
    if state.over:
        return WIN if state.winner == me else -WIN
    if state.pending:
        best = max(choice_values(state, noise).values())
        return best if state.turn == me else -best
    v = position_value(state, noise)
    return v if state.turn == me else -v


def outcome_value(before: State, outcome: Outcome, noise: Noise) -> float:
    """What the shot that led from `before` to `outcome` earned its player: the points it
    scored (net of the opponent's) and the value of the table it left."""
    me = before.turn
    gained = outcome.state.scores[me] - before.scores[me]
    given = outcome.state.scores[other(me)] - before.scores[other(me)]
    points = 0.0 if outcome.state.over else POINT[before.game] * (gained - given)
    return points + value_for(outcome.state, me, noise)

"""What a position is worth, and what a simulated shot earned: the bot's judgement of outcomes.

Everything here reads the referee's states and decisions (rules.game.play produced them); the
rules are never written again. The scale is a win probability turned into [-1, 1]: a game won
is +1, lost -1. A position is worth to the player to act in it what their best next pot
promises (`position_value`: the one-level look-ahead, from the straight pots they would have,
their chance estimated by rules.bot.geometry, a ball in hand included), and to the opponent
minus that; in snooker and three-cushion the points a shot scores count besides. In the pool
games a next pot is also judged by the shape it leaves (`shape`: whether the cue ball, sent
on from the ghost ball, can reach a pot of the ball after it), since under the tournament
noise most short pots are near certain and the next pot's chance alone cannot tell a run from
a dead end. A choice pending after a foul is valued as its chooser will make it, through the
referee's `choose`; its ball in hand in the D is tried from fewer places than a shot's.

The scale (keep the table: between KEEP_NOTHING and KEEP_SURE; give it away: minus the
same for the opponent) makes a pot that leaves no next shot worth less than a safety that
leaves the opponent none, and any miss that leaves an easy pot costly.

How much the opponent makes of the table is the bot's model of its opponent (`rival`: what a
sure pot is worth to them, KEEP_SURE for the bot's equal). Priced as the bot's equal, a pool
opponent's every chance costs as much as the bot's own are worth, and against weaker players
that overpays for safety: in 400 nine-ball racks against the shot pickers (the README, "The
bot"), choices the search valued about 0 (an even game) were in racks won 90% of the time.
"""

from __future__ import annotations

import math

from rules.bot.geometry import Pot, best_chances, best_pots
from rules.bot.noise import Noise
from rules.bot.placements import placements
from rules.game import Outcome, choose
from rules.inputs import OPTIONS, Choice
from rules.racks import Game
from rules.referee import referee, table_of
from rules.snooker import value as snooker_value
from rules.spots import Point, Table, is_free
from rules.state import State, other

#: A game won (lost: the opposite).
WIN = 1.0
#: What having the table is worth with no pot on, and with a certain one.
KEEP_NOTHING, KEEP_SURE = -0.2, 0.9
#: The games in which `rival` prices the opponent's table; snooker's and three-cushion's
#: values are mostly the points a visit scores, and their bars are met without it.
RIVAL_GAMES = frozenset({Game.NINEBALL, Game.EIGHTBALL})
#: Worth of one point scored, per game (pool games score racks, which end the game).
POINT = {Game.NINEBALL: 0.0, Game.EIGHTBALL: 0.0, Game.SNOOKER: 0.06, Game.THREE_CUSHION: 0.8}
#: A ball in hand anywhere is worth at least a pot of this chance: where no place for a pot
#: is found, the player still chooses the table he plays from (a safety, a bank, a kick).
IN_HAND_ANYWHERE = 0.5
#: Shape (pool): how much of a next pot's chance rests on the pot after it. A next pot from
#: which the cue ball can reach no pot of the ball after counts for 1 - SHAPE_WEIGHT of its
#: chance; one that leaves a sure pot after it counts in full. Without it every position with a
#: short straight pot is worth KEEP_SURE and the search cannot tell a run from a dead end.
SHAPE_WEIGHT = 0.3
#: Shape is judged for the likeliest SHAPE_POTS next pots, and only while the balls that may
#: follow are at most SHAPE_TARGETS (nine-ball's next ball; eight-ball's last few), so that
#: it costs a few straight-pot estimates, not a search.
SHAPE_POTS = 2
SHAPE_TARGETS = 2
#: Where the cue ball may stop after a pot, from the ghost ball (m): along the tangent line
#: (stun), bent ahead of it (follow) and back from it (draw), near and far.
SHAPE_REACH = (0.25, 0.6)


def theirs(state: State, v: float, rival: float) -> float:
    """What a position worth `v` to the bot is worth to an opponent who makes of a sure pot
    `rival` (KEEP_SURE: as much as the bot): scaled about KEEP_NOTHING, the worth of no pot."""
    if rival == KEEP_SURE or state.game not in RIVAL_GAMES:
        return v
    return KEEP_NOTHING + (rival - KEEP_NOTHING) / (KEEP_SURE - KEEP_NOTHING) * (v - KEEP_NOTHING)


def _ball_points(state: State, ball: str) -> int:
    """Points a pot of `ball` scores now (snooker; nothing in the pool games)."""
    return snooker_value(ball) if state.game == Game.SNOOKER else 0


def keep(state: State, p: float, points: float) -> float:
    """The worth of having the table with a best pot of chance `p` that scores `points`."""
    return KEEP_NOTHING + (KEEP_SURE - KEEP_NOTHING) * p + POINT[state.game] * points * p


def _unit(x: float, y: float) -> Point:
    d = math.hypot(x, y)
    return (x / d, y / d) if d > 1e-9 else (0.0, 0.0)


def cue_after(table: Table, pot: Pot, balls: dict[str, Point]) -> list[Point]:
    """Places the cue ball may be sent to by `pot` (stun, follow or draw, near and far): the
    ghost ball moved along the tangent line and bent either way from it, kept on the table and
    clear of the balls left."""
    u = _unit(pot.ghost[0] - pot.cue[0], pot.ghost[1] - pot.cue[1])
    at = balls[pot.target]
    n = _unit(at[0] - pot.ghost[0], at[1] - pot.ghost[1])
    along = u[0] * n[0] + u[1] * n[1]
    t = _unit(u[0] - along * n[0], u[1] - along * n[1])
    ways = [t, _unit(t[0] + n[0], t[1] + n[1]), _unit(t[0] - n[0], t[1] - n[1])]
    R = table.R
    left = {b: p for b, p in balls.items() if b not in ("cue", pot.target)}
    found = [pot.ghost]
    for wx, wy in ways:
        for d in SHAPE_REACH:
            x = min(table.width - R, max(R, pot.ghost[0] + wx * d))
            y = min(table.length - R, max(R, pot.ghost[1] + wy * d))
            found.append((x, y))
    return [p for p in found if is_free(p, left, R)]


def shape(state: State, table: Table, pot: Pot, balls: dict[str, Point], noise: Noise) -> float:
    """The best chance of a pot on the balls that may follow `pot`, from where it may leave
    the cue ball (1 when no ball follows, or more than SHAPE_TARGETS may)."""
    left = {b: p for b, p in balls.items() if b != pot.target}
    following = referee(state.game).targets(state, left)
    if not following or len(following) > SHAPE_TARGETS:
        return 1.0
    chances = best_chances(table, cue_after(table, pot, balls), left, following, noise)
    return max(chances.values())


def _unshaped(state: State, a: Pot) -> float:
    """The worth of pot `a` from its chance and points alone."""
    return keep(state, a.chance, _ball_points(state, a.target))


def _pot_worth(
    state: State, table: Table, a: Pot, balls: dict[str, Point], noise: Noise, shaped: bool
) -> float:
    """The worth of having the table with pot `a` to play: its chance, cut (when `shaped`) by
    the share of it that the shape it leaves cannot carry on."""
    p = a.chance
    if shaped:
        p *= 1 - SHAPE_WEIGHT * (1 - shape(state, table, a, balls, noise))
    return keep(state, p, _ball_points(state, a.target))


def _best_from(
    state: State,
    table: Table,
    cue: Point,
    balls: dict[str, Point],
    noise: Noise,
    shaped: bool = False,
) -> float:
    """The worth of having the table with the cue ball at `cue`: its best pot's (by chance
    and points), or (when `shaped`) the best of its likeliest SHAPE_POTS pots' with the shape
    each leaves."""
    now = referee(state.game).targets(state, balls)
    n = SHAPE_POTS if shaped else 1
    found = best_pots(table, cue, balls, now, noise, n, lambda a: _unshaped(state, a))
    return max(
        (_pot_worth(state, table, a, balls, noise, shaped) for a in found),
        default=keep(state, 0.0, 0),
    )


def position_value(state: State, noise: Noise) -> float:
    """What `state` is worth to the player to act in it (no choice pending)."""
    table = table_of(state)
    if not table.pockets:
        return 0.0
    if not state.ball_in_hand:
        shaped = state.game in (Game.NINEBALL, Game.EIGHTBALL)
        return _best_from(state, table, state.balls["cue"], dict(state.balls), noise, shaped)
    balls = {b: p for b, p in state.balls.items() if b != "cue"}
    spots = placements(state, table, balls, coarse=True)
    spots += [state.balls["cue"]] if "cue" in state.balls else []
    floor = IN_HAND_ANYWHERE if state.ball_in_hand == "anywhere" else 0.0
    values = (_best_from(state, table, p, {**balls, "cue": p}, noise) for p in spots)
    return max([keep(state, floor, 0), *values])


def choice_values(state: State, noise: Noise, rival: float = KEEP_SURE) -> dict[str, float]:
    """Each option pending in `state`, valued for the player who chooses (the one to act),
    who prices the other's table with `rival`."""
    chooser = state.turn
    return {
        option: value_for(choose(state, Choice(option=option)), chooser, noise, rival)
        for option in OPTIONS
        if option in state.pending
    }


def value_for(state: State, me: int, noise: Noise, rival: float = KEEP_SURE) -> float:
    """What `state` is worth to player `me` (whoever is to act in it), the opponent's table
    priced with `rival`. An opponent's pending choice is taken as they would value it as the
    bot's equal."""
    if state.over:
        return WIN if state.winner == me else -WIN
    if state.pending:
        mine = state.turn == me
        best = max(choice_values(state, noise, rival if mine else KEEP_SURE).values())
        return best if mine else -theirs(state, best, rival)
    v = position_value(state, noise)
    return v if state.turn == me else -theirs(state, v, rival)


def outcome_value(before: State, outcome: Outcome, noise: Noise, rival: float = KEEP_SURE) -> float:
    """What the shot that led from `before` to `outcome` earned its player, who prices the
    opponent's table with `rival`: the points it scored (net of the opponent's) and the value
    of the table it left."""
    me = before.turn
    gained = outcome.state.scores[me] - before.scores[me]
    given = outcome.state.scores[other(me)] - before.scores[other(me)]
    points = 0.0 if outcome.state.over else POINT[before.game] * (gained - given)
    return points + value_for(outcome.state, me, noise, rival)

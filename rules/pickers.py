"""Simple shot pickers: enough of a player to play a whole game, for self-play and tests.

Pool and snooker: for every ball the player may hit and every pocket, aim the cue ball at the
ghost ball that sends the object ball straight at the pocket, keeping only shots whose two
straight paths are clear and whose cut is not too thin; take the easiest. With ball in hand,
place the cue ball straight behind the easiest pot. With no pot on, play a plain contact on a
legal ball, through a cushion when no legal ball can be hit directly. Three-cushion: try a
fixed fan of strokes through the engine and play the first that scores (else the one whose cue
ball touched the most balls and cushions). After a foul or a push-out the picker plays on.

Everything is deterministic: the same state gives the same input, so a self-played game is
reproducible from its seed alone. What a player may do comes from the game's referee
(rules.referee), never from the game's name.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import physics
from rules.aim import ghost, path_clear
from rules.game import Simulate, scene
from rules.inputs import PLACE_STEPS, Choice, PlayerInput, Shot, Strike, quantise
from rules.racks import Game
from rules.referee import allowed, referee, table_of
from rules.spots import BAULK_Y, Point, Table, in_region, is_free
from rules.state import State
from rules.three_cushion import count_point

#: Thinnest cut tried: cos of the angle between the cue ball's path and the object ball's.
MIN_CUT_COS = 0.35
#: Largest angle (deg) between an object ball's path and a pocket's opening that still drops.
CORNER_APPROACH, SIDE_APPROACH = 55.0, 35.0
#: Distance (m) behind the ghost ball at which a placed cue ball is put.
PLACE_BEHIND = 0.25
#: Games the picker breaks by driving the cue ball at the rack's apex, and how hard (m/s).
BREAK_SPEED = {Game.NINEBALL: 8.0, Game.EIGHTBALL: 8.0}


@dataclass(frozen=True, slots=True)
class Aim:
    """A candidate pot: cue ball to ghost, then object ball to pocket."""

    score: float
    target: str
    pocket: str
    heading: float
    speed: float


def _heading(a: Point, b: Point) -> float:
    return round(math.degrees(math.atan2(b[1] - a[1], b[0] - a[0])), 4)


def _opening(table: Table, name: str) -> tuple[Point, float]:
    """A pocket's aim point and the direction (unit vector) a ball must roughly travel in."""
    pocket = next(p for p in table.pockets if p.name == name)
    cx, cy = pocket.center
    dx = -1.0 if cx < table.width / 2 else 1.0
    if name.startswith("middle"):
        return pocket.center, (dx, 0.0)
    dy = -1.0 if cy < table.length / 2 else 1.0
    return pocket.center, (dx / math.sqrt(2), dy / math.sqrt(2))


def pot_aims(
    table: Table, cue: Point, balls: dict[str, Point], targets: frozenset[str]
) -> list[Aim]:
    """Every makeable straight pot of one of `targets`, easiest first."""
    R = table.R
    aims = []
    for t in sorted(targets):
        tp = balls[t]
        for pocket in table.pockets:
            mouth, opening = _opening(table, pocket.name)
            to_pocket = (mouth[0] - tp[0], mouth[1] - tp[1])
            d2 = math.hypot(*to_pocket)
            limit = SIDE_APPROACH if pocket.name.startswith("middle") else CORNER_APPROACH
            approach = (to_pocket[0] * opening[0] + to_pocket[1] * opening[1]) / d2
            if approach < math.cos(math.radians(limit)):
                continue
            g = ghost(tp, mouth, R)
            to_ghost = (g[0] - cue[0], g[1] - cue[1])
            d1 = math.hypot(*to_ghost)
            if d1 < 1e-6:
                continue
            cut = (to_ghost[0] * to_pocket[0] + to_ghost[1] * to_pocket[1]) / (d1 * d2)
            if cut < MIN_CUT_COS:
                continue
            if not path_clear(cue, g, balls, R, ignore={"cue", t}):
                continue
            if not path_clear(tp, mouth, balls, R, ignore={"cue", t}):
                continue
            speed = min(6.0, 1.2 + 1.1 * (d1 + d2 / cut))
            score = cut / (d1 + d2)
            aims.append(Aim(score, t, pocket.name, _heading(cue, g), round(speed, 3)))
    return sorted(aims, key=lambda a: -a.score)


def _kicks(table: Table, cue: Point, target: Point) -> list[Point]:
    """Where the cue ball's centre meets each cushion on a one-cushion path to `target`
    (mirror the target in the line the centre bounces on), skipping bounces near a pocket."""
    R = table.R
    x, y = target
    lines = ((0, R), (0, table.width - R), (1, R), (1, table.length - R))
    bounces = []
    for axis, at in lines:
        mirror = [x, y]
        mirror[axis] = 2 * at - target[axis]
        span = mirror[axis] - cue[axis]
        if abs(span) < 1e-9:
            continue
        f = (at - cue[axis]) / span
        b = (cue[0] + f * (mirror[0] - cue[0]), cue[1] + f * (mirror[1] - cue[1]))
        if 0 < f < 1 and all(math.dist(b, p.center) > p.radius + 3 * R for p in table.pockets):
            bounces.append(b)
    return bounces


def _full_and_half_ball(cue: Point, target: Point, R: float) -> list[Point]:
    """Aim points for a full-ball hit and for half-ball hits on either side (the cue ball's
    centre line passing R from the target's centre)."""
    dx, dy = target[0] - cue[0], target[1] - cue[1]
    d = math.hypot(dx, dy)
    px, py = -dy / d * R, dx / d * R
    return [target, (target[0] + px, target[1] + py), (target[0] - px, target[1] - py)]


def contact_heading(
    table: Table, cue: Point, balls: dict[str, Point], targets: frozenset[str]
) -> float:
    """A heading that reaches a legal ball: full or half ball in a straight line if the path
    is clear, else off a cushion (mirror the ball in the cushion line), else straight at the
    nearest legal ball."""
    R = table.R
    by_distance = sorted(targets, key=lambda t: (math.dist(cue, balls[t]), t))
    for t in by_distance:
        for aim_at in _full_and_half_ball(cue, balls[t], R):
            if path_clear(cue, aim_at, balls, R, ignore={"cue", t}):
                return _heading(cue, aim_at)
    for t in by_distance:
        for bounce in _kicks(table, cue, balls[t]):
            clear = path_clear(cue, bounce, balls, R, {"cue", t})
            if clear and path_clear(bounce, balls[t], balls, R, {"cue", t}):
                return _heading(cue, bounce)
    return _heading(cue, balls[by_distance[0]])


def _targets(state: State, balls: dict[str, Point]) -> frozenset[str]:
    return referee(state.game).targets(state, balls)


def _on_grid(p: Point) -> Point:
    """A placement as the input will hold it, so that it is checked where it will be."""
    return (quantise(p[0], PLACE_STEPS), quantise(p[1], PLACE_STEPS))


def _placements(state: State, table: Table, balls: dict[str, Point]) -> list[Point]:
    """Candidate cue-ball positions for ball in hand: straight behind each legal ball on the
    line to each pocket (ball in hand anywhere), then a spread over the region (arcs in the D,
    a grid behind the head string, which is also the fallback for "anywhere")."""
    found = []
    if state.ball_in_hand == "anywhere":
        for t in sorted(_targets(state, balls)):
            tp = balls[t]
            for pocket in table.pockets:
                mouth, _ = _opening(table, pocket.name)
                g = ghost(tp, mouth, table.R)
                d = math.dist(g, tp)
                back = PLACE_BEHIND / d
                found.append((g[0] - back * (tp[0] - g[0]), g[1] - back * (tp[1] - g[1])))
    if state.ball_in_hand == "D":
        cx, cy = table.width / 2, BAULK_Y
        found += [
            (cx + r * math.cos(a), cy - r * math.sin(a))
            for r in (0.05, 0.15, 0.25)
            for a in (0.0, math.pi / 4, math.pi / 2, 3 * math.pi / 4, math.pi)
        ]
    else:
        head = table.length / 4
        found += [
            (table.width * i / 8, head - table.length * j / 16)
            for j in (0, 1, 2)
            for i in range(1, 8)
        ]
    placed = [_on_grid(p) for p in found]
    return [
        p for p in placed if in_region(p, state.ball_in_hand, table) and is_free(p, balls, table.R)
    ]


def _plan(state: State, table: Table, balls: dict[str, Point]) -> tuple[Point, Aim | None]:
    """Where the cue ball will be, and the best pot from there (if any)."""
    targets = _targets(state, balls)
    if state.ball_in_hand:
        others = {b: p for b, p in balls.items() if b != "cue"}
        options = _placements(state, table, others)
        if "cue" in balls:
            options.append(balls["cue"])
        best: tuple[Point, Aim | None] | None = None
        for p in options:
            aims = pot_aims(table, p, {**others, "cue": p}, targets)
            if aims and (best is None or best[1] is None or aims[0].score > best[1].score):
                best = (p, aims[0])
            elif best is None:
                best = (p, None)
        return best
    return balls["cue"], (pot_aims(table, balls["cue"], balls, targets) or [None])[0]


def pick_table_game(state: State) -> Shot:
    """A shot for a game on a table with pockets (nine-ball, eight-ball, snooker)."""
    table = table_of(state)
    balls = dict(state.balls)
    if state.shots == 0 and state.game in BREAK_SPEED:
        apex = min((b for b in balls if b != "cue"), key=lambda b: balls[b][1])
        heading = _heading(balls["cue"], balls[apex])
        return Shot(strike=Strike(ball="cue", speed=BREAK_SPEED[state.game], heading=heading))
    cue, aim_ = _plan(state, table, balls)
    place = cue if state.ball_in_hand and cue != balls.get("cue") else None
    balls["cue"] = cue
    targets = _targets(state, balls)
    if aim_ is not None:
        strike = Strike(ball="cue", speed=aim_.speed, heading=aim_.heading, b=-0.1)
        target, pocket = aim_.target, aim_.pocket
    else:
        heading = contact_heading(table, cue, balls, targets)
        strike = Strike(ball="cue", speed=2.5, heading=heading)
        target = min(targets, key=lambda t: (math.dist(cue, balls[t]), t))
        pocket = min(table.pockets, key=lambda p: math.dist(p.center, balls[target])).name
    may = referee(state.game).options(state)
    call = pocket if may.call else None
    nominate = target if target in may.nominate else None
    return Shot(strike=strike, place=place, call=call, nominate=nominate)


#: Three-cushion candidates: heading offsets (deg) from the line to the red, tried in order,
#: each with running side on either side, at one speed (m/s).
CAROM_OFFSETS = tuple(o for k in range(0, 61, 3) for o in ((k, -k) if k else (0,)))
CAROM_SPEED = 3.5


def pick_carom(state: State, simulate: Simulate) -> Shot:
    """A shot for three-cushion: the first candidate stroke that scores, tried in the engine."""
    cue = referee(state.game).cue_ball(state)
    base = _heading(state.balls[cue], state.balls["red"])
    best, best_key = None, (-1, -1)
    for offset in CAROM_OFFSETS:
        for side in (0.3, -0.3):
            strike = Strike(ball=cue, speed=CAROM_SPEED, heading=round(base + offset, 4), a=side)
            shot = Shot(strike=strike)
            events = simulate(scene(state, shot, state.balls)).events
            scored, touched, cushions = count_point(events, cue)
            if scored and (state.shots > 0 or touched[0] == "red"):
                return shot
            if (len(touched), cushions) > best_key:
                best, best_key = shot, (len(touched), cushions)
    return best


def pick(state: State, simulate: Simulate = physics.simulate) -> PlayerInput:
    """The picker's next input for the player to act in `state`."""
    if allowed(state).choices:
        return Choice(option="play_on")
    if not table_of(state).pockets:
        return pick_carom(state, simulate)
    return pick_table_game(state)

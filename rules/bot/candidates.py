"""The shots the bot considers, built from the table and from what the referee allows now.

- The break (pool): from a few places behind the head string, at the rack's apex ball, hard.
- Pots: the likeliest straight pots (rules.bot.geometry), from every place a ball in hand
  allows, varied in speed and in follow, stun, draw and side; and the likeliest one-cushion
  banks and two-ball combinations, varied in speed.
- Contacts, which are the safeties: the nearest legal balls hit full, half-ball and thin on
  either side, soft to firm, one drawn. Kicks: when no legal ball can be hit straight,
  contacts off one cushion and off two, each at a fan of headings around the mirror path's
  (a cushion is no mirror), which is the escape from a snooker.
- Three-cushion: a fan of headings around each object ball, with running and check side, at
  two speeds; which of them score is for the simulation to say.
- Push-outs, when the referee offers one (nine-ball, the shot after the break): soft rolls of
  the cue ball all around the compass. The opponent then chooses who shoots from the table
  left, so the search values a push-out as the worse of the two for the bot (rules.bot.value
  reads the choice the referee offers); it wins only when no shot is better than a table
  neither player wants.

Every candidate carries the declarations the referee asks for (the called pocket on the 8, the
nomination in snooker) and is checked with `rules.game.check` before it is kept, so the search
never spends a simulation on an input the referee would refuse. The order is fixed: the same
state gives the same candidates in the same order.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from enum import StrEnum
from itertools import pairwise
from types import MappingProxyType

from rules.aim import path_clear
from rules.bot.geometry import Pot, banks, combos, cushion_bounces, pots, two_cushion_paths
from rules.bot.levels import Level
from rules.bot.noise import Noise
from rules.bot.placements import placements
from rules.codes import RuleError
from rules.game import check
from rules.inputs import Shot, Strike
from rules.racks import Game
from rules.referee import Allowed, allowed, referee, table_of
from rules.spots import Point, Table
from rules.state import State

#: Aim offsets of a contact (the cue ball's line passes this many ball diameters from the
#: object ball's centre: 0 full, 0.5 half-ball, 0.85 thin).
CONTACT_OFFSETS = (0.0, 0.5, -0.5, 0.85, -0.85)


#: Break: cue-ball places on the head string (fractions of the width) and speeds (m/s), a
#: centre-ball hit on the apex ball. Measured on the engine under the tournament noise (60
#: racks each): in nine-ball, from a third of the way across, 5-7 m/s keeps the table 95% of
#: the time and scratches 2-5%; from the centre, or harder, or with draw, the cue ball
#: scratches in a quarter to a third of the breaks. Eight-ball's fifteen balls need 10 m/s.
BREAK_PLACES = (0.3, 0.35, 0.25)
BREAK_SPEEDS = MappingProxyType({Game.NINEBALL: (5.0, 6.0, 7.0), Game.EIGHTBALL: (8.5, 10.0, 11.5)})
#: The strongest level's breaks (the lower levels and the search baseline keep the set above).
#: Nine-ball's rack still pots a ball on 98-99% of breaks at 4 m/s, and a softer break
#: scratches less: centre ball, 1-2% at 4 m/s, 4-6% at 5, 5-10% at 6 (60 racks, 6 noise draws
#: each, from each place above). With 5-7 m/s the search chose 6 or 7 on half of the racks for
#: the spread they leave and scratched on 6.5% of its breaks, handing ball in hand on a full
#: rack to the other side; with these, 0.7% (40 racks, 20 draws each).
SOFT_BREAK_SPEEDS = MappingProxyType({**BREAK_SPEEDS, Game.NINEBALL: (4.0, 4.5, 5.0)})


@dataclass(frozen=True, slots=True)
class Strokes:
    """How each straight pot and each contact is varied.

    pot_speeds: factors of the pot's own speed. pot_spins: tip offsets (a: side, b: draw or
    follow). contacts: (speed in m/s, b) of each contact. breaks: the break's speeds (m/s)
    per game.
    """

    pot_speeds: tuple[float, ...]
    pot_spins: tuple[tuple[float, float], ...]
    contacts: tuple[tuple[float, float], ...]
    breaks: Mapping[Game, tuple[float, ...]] = field(default_factory=lambda: BREAK_SPEEDS)


#: The coarse set, which the smaller screens of the lower levels hold: three speeds with draw,
#: stun and follow; contacts soft to firm.
COARSE = Strokes(
    (0.75, 1.0, 1.4),
    ((0.0, -0.3), (0.0, 0.0), (0.0, 0.3)),
    ((1.0, 0.0), (2.0, 0.0), (3.5, 0.0)),
)
#: The fine set (Level.fine): five speeds, and running or check side besides, which throws
#: the cue ball off the cushions another way (position the vertical spins cannot reach);
#: contacts from very soft to firm, and a drawn one that keeps the cue ball near the contact.
FINE = Strokes(
    (0.6, 0.8, 1.0, 1.25, 1.6),
    ((0.0, -0.3), (0.0, 0.0), (0.0, 0.3), (-0.3, 0.0), (0.3, 0.0)),
    ((0.6, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, -0.4), (3.5, 0.0)),
    SOFT_BREAK_SPEEDS,
)
KICK_SPEEDS = (1.5, 2.5, 4.0)
#: One-cushion kicks: turns (degrees) of the mirror heading tried. With the mirror heading
#: alone, the strongest level's escapes from 40 snookered random nine-ball positions fouled in
#: 16% of plays under the tournament noise (mean value -0.30); with this fan, and the
#: two-cushion kicks tried beside the one-cushion ones, in 8% (mean value -0.06); eight-ball's,
#: 15% (-0.38) and 12% (-0.17) (bench/escapes.py).
ONE_CUSHION_FAN = (-2.4, -1.6, -0.8, 0.0, 0.8, 1.6, 2.4)
#: Two-cushion kicks: turns (degrees) of the mirror heading tried, since a cushion is no
#: mirror (it gives back less speed than it took, and spin bends the path) and the error
#: grows over two of them; the simulation finds which turn reaches the ball.
TWO_CUSHION_FAN = (-3.0, -1.5, 0.0, 1.5, 3.0)
#: The speed (m/s) of the stroke of last resort, straight at the nearest legal ball.
PLAIN_SPEED = 2.0
#: Legal balls tried for contacts, nearest first, and from how many cue-ball spots.
CONTACT_TARGETS = 3
CONTACT_SPOTS = 3
#: Three-cushion: the widest heading offset (degrees), the side spins, the speeds, follow.
FAN_WIDTH = 60.0
FAN_SIDES = (-0.4, 0.0, 0.4)
FAN_SPEEDS = (3.0, 4.5)
FAN_FOLLOW = 0.1
#: Push-outs: evenly spaced headings, and speeds (m/s) that roll the cue ball a short way
#: (about 0.1, 0.3 and 0.65 m on the engine's cloth, before any cushion or ball).
PUSH_HEADINGS = 16
PUSH_SPEEDS = (0.2, 0.35, 0.5)


class Kind(StrEnum):
    """What a candidate is; the pots' kinds are the geometry's `Via` values."""

    BREAK = "break"
    POT = "direct"
    BANK = "bank"
    COMBO = "combo"
    CONTACT = "contact"
    KICK = "kick"
    CAROM = "carom"
    PUSH_OUT = "push_out"


@dataclass(frozen=True, slots=True)
class Candidate:
    """One shot to try. pot: the straight pot it plays (for the throw correction), if any."""

    shot: Shot
    kind: Kind
    pot: Pot | None = None


@dataclass(frozen=True, slots=True)
class Spot:
    """The table as the cue ball will find it: where it stands (`place`: where it is put, for
    a ball in hand), the balls with it there, and what the referee allows."""

    now: Allowed
    table: Table
    balls: dict[str, Point]
    place: Point | None

    @property
    def cue(self) -> Point:
        return self.balls[self.now.cue]

    def shot(self, target: str, pocket: str | None = None, **strike: float) -> Shot:
        """A shot at `target` with the declarations the referee asks for: the pocket called
        (the one nearest the target when none is aimed at), the target nominated when it
        may be."""
        if self.now.options.call and pocket is None:
            at = self.balls[target]
            pocket = min(self.table.pockets, key=lambda k: math.dist(k.center, at)).name
        return Shot(
            strike=Strike(ball=self.now.cue, **strike),
            place=self.place,
            call=pocket if self.now.options.call else None,
            nominate=target if target in self.now.options.nominate else None,
        )


def heading_to(a: Point, b: Point) -> float:
    return math.degrees(math.atan2(b[1] - a[1], b[0] - a[0]))


def pot_speed(p: Pot) -> float:
    """A cue speed (m/s) that sends the object ball to the pocket with some to spare."""
    return min(6.0, 1.2 + 1.1 * (p.d1 + p.travel / p.cos_cut))


def spots(state: State) -> list[Spot]:
    """Where the cue ball may stand: where it lies, and every ball-in-hand place considered."""
    now = allowed(state)
    table = table_of(state)
    others = {b: p for b, p in state.balls.items() if b != now.cue}
    found = []
    if now.cue in state.balls:
        found.append(Spot(now, table, dict(state.balls), None))
    for p in placements(state, table, others):
        found.append(Spot(now, table, {**others, now.cue: p}, p))
    return found


#: Pots are ranked under the tournament noise: the ranking only chooses what to simulate.
NOISE_FOR_RANKING = Noise()
#: Banks and combinations tried (each kind, likeliest first), from the cue ball's first spot,
#: and the least estimated chance that earns one a place.
EXTRA_POTS = 2
EXTRA_MIN_CHANCE = 0.2
#: Speed factors of a bank or a combination (plain centre-ball strokes).
EXTRA_SPEEDS = (1.0, 1.4)


def _varied(spot: Spot, p: Pot, speeds: tuple[float, ...], spins: tuple[tuple[float, float], ...]):
    for f in speeds:
        for a, b in spins:
            strike = {"speed": round(f * pot_speed(p), 3), "heading": p.heading, "a": a, "b": b}
            yield Candidate(spot.shot(p.target, p.pocket, **strike), Kind(p.via), p)


def pot_candidates(
    where: list[Spot], targets: frozenset[str], n: int, strokes: Strokes
) -> list[Candidate]:
    """The n likeliest straight pots over every spot, each varied in speed and spin, then the
    likeliest banks and combinations from the first spot."""
    direct = sorted(
        (
            (p, i)
            for i, s in enumerate(where)
            for p in pots(s.table, s.cue, s.balls, targets, NOISE_FOR_RANKING)
        ),
        key=lambda pi: (-pi[0].chance, pi[1], pi[0].target, pi[0].pocket),
    )[:n]
    out = [
        c for p, i in direct for c in _varied(where[i], p, strokes.pot_speeds, strokes.pot_spins)
    ]
    if where:
        s = where[0]
        for find in (banks, combos):
            found = find(s.table, s.cue, s.balls, targets, NOISE_FOR_RANKING)
            likely = [p for p in found if p.chance >= EXTRA_MIN_CHANCE][:EXTRA_POTS]
            out += [c for p in likely for c in _varied(s, p, EXTRA_SPEEDS, ((0.0, 0.0),))]
    return out


def _contact_points(cue: Point, at: Point, R: float) -> list[Point]:
    dx, dy = at[0] - cue[0], at[1] - cue[1]
    d = math.hypot(dx, dy)
    px, py = -dy / d * 2 * R, dx / d * 2 * R
    return [(at[0] + f * px, at[1] + f * py) for f in CONTACT_OFFSETS]


def contact_candidates(spot: Spot, targets: frozenset[str], strokes: Strokes) -> list[Candidate]:
    """Contacts on the nearest legal balls in sight; kicks off one cushion when none is."""
    R = spot.table.R
    ignore = lambda t: {spot.now.cue, t}  # noqa: E731
    near = sorted(targets, key=lambda t: (math.dist(spot.cue, spot.balls[t]), t))
    out = []
    seen = 0
    for t in near:
        points = _contact_points(spot.cue, spot.balls[t], R)
        clear = [p for p in points if path_clear(spot.cue, p, spot.balls, R, ignore(t))]
        for aim_at in clear:
            for v, b in strokes.contacts:
                shot = spot.shot(t, speed=v, heading=heading_to(spot.cue, aim_at), b=b)
                out.append(Candidate(shot, Kind.CONTACT))
        seen += bool(clear)
        if seen == CONTACT_TARGETS:
            break
    if out:
        return out
    for t in near:
        for bounce in cushion_bounces(spot.table, spot.cue, spot.balls[t]):
            out += kicks(spot, t, (bounce,), ONE_CUSHION_FAN)
    for t in near:
        for bounces in two_cushion_paths(spot.table, spot.cue, spot.balls[t]):
            out += kicks(spot, t, bounces, TWO_CUSHION_FAN)
    return out


def kicks(
    spot: Spot, t: str, bounces: tuple[Point, ...], fan: tuple[float, ...] = (0.0,)
) -> list[Candidate]:
    """Kicks at `t` by way of `bounces` (cushion points, in order), if every leg is clear:
    at the mirror heading turned by each of `fan` (degrees), at each of KICK_SPEEDS."""
    legs = pairwise((spot.cue, *bounces, spot.balls[t]))
    if not all(path_clear(a, b, spot.balls, spot.table.R, {spot.now.cue, t}) for a, b in legs):
        return []
    heading = heading_to(spot.cue, bounces[0])
    return [
        Candidate(spot.shot(t, speed=v, heading=heading + turn), Kind.KICK)
        for turn in fan
        for v in KICK_SPEEDS
    ]


def push_out_candidates(spot: Spot, targets: frozenset[str]) -> list[Candidate]:
    """Push-outs: the cue ball rolled softly in PUSH_HEADINGS directions at PUSH_SPEEDS."""
    t = min(targets, key=lambda t: (math.dist(spot.cue, spot.balls[t]), t))
    out = []
    for k in range(PUSH_HEADINGS):
        for v in PUSH_SPEEDS:
            shot = spot.shot(t, speed=v, heading=360.0 * k / PUSH_HEADINGS)
            out.append(Candidate(shot.model_copy(update={"push_out": True}), Kind.PUSH_OUT))
    return out


def break_candidates(state: State, speeds: Mapping[Game, tuple[float, ...]]) -> list[Candidate]:
    """Pool's break: from a few places on the head string, hard at the apex ball, at the
    game's `speeds`."""
    now = allowed(state)
    table = table_of(state)
    others = {b: p for b, p in state.balls.items() if b != now.cue}
    apex = min(others, key=lambda b: (others[b][1], b))
    out = []
    for f in BREAK_PLACES:
        place = (round(table.width * f, 4), round(table.head_string, 4))
        spot = Spot(now, table, {**others, now.cue: place}, place)
        for v in speeds[state.game]:
            strike = {"speed": v, "heading": heading_to(place, others[apex])}
            out.append(Candidate(spot.shot(apex, **strike), Kind.BREAK))
    return out


def carom_candidates(state: State, budget: int) -> list[Candidate]:
    """Three-cushion: evenly spaced headings within FAN_WIDTH of each object ball, as many as
    `budget` candidates allow (with every side spin and speed at each)."""
    now = allowed(state)
    table = table_of(state)
    spot = Spot(now, table, dict(state.balls), None)
    per_heading = len(FAN_SIDES) * len(FAN_SPEEDS) * len(now.targets)
    n = max(1, (budget // per_heading - 1) // 2)
    step = FAN_WIDTH / n
    out = []
    for t in sorted(now.targets):
        base = heading_to(spot.cue, spot.balls[t])
        for k in range(-n, n + 1):
            for a in FAN_SIDES:
                for v in FAN_SPEEDS:
                    strike = {"speed": v, "heading": base + k * step, "a": a, "b": FAN_FOLLOW}
                    out.append(Candidate(spot.shot(t, **strike), Kind.CAROM))
    return out


def candidates(state: State, level: Level, strokes: Strokes | None = None) -> list[Candidate]:
    """The candidates for the player to shoot in `state` (no choice pending), those the
    referee accepts, in a fixed order: pots first (likeliest first), then contacts, then
    push-outs. strokes: how pots and contacts are varied (default: the level's set)."""
    now = allowed(state)
    ref = referee(state.game)
    strokes = strokes or (FINE if level.fine else COARSE)
    if not ref.TABLE.pockets:
        found = carom_candidates(state, level.screen)
    elif state.shots == 0 and state.ball_in_hand == "kitchen":
        found = break_candidates(state, strokes.breaks)
    else:
        where = spots(state)
        targets = now.targets | (now.options.nominate if state.free_ball else frozenset())
        found = pot_candidates(where, targets, level.pots, strokes)
        for spot in where[:CONTACT_SPOTS]:
            found += contact_candidates(spot, targets, strokes)
        if now.options.push_out and where:
            found += push_out_candidates(where[0], targets)
        if not found and where:
            found = [plain(where[0], targets)]
    return [c for c in found if accepted(state, c)]


def plain(spot: Spot, targets: frozenset[str]) -> Candidate:
    """The stroke of last resort, when no contact was found: straight at the nearest legal
    ball, whatever is in the way."""
    t = min(targets, key=lambda t: (math.dist(spot.cue, spot.balls[t]), t))
    shot = spot.shot(t, speed=PLAIN_SPEED, heading=heading_to(spot.cue, spot.balls[t]))
    return Candidate(shot, Kind.CONTACT)


def accepted(state: State, candidate: Candidate) -> bool:
    try:
        check(state, candidate.shot)
    except RuleError:
        return False
    return True

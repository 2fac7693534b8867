"""Snooker referee (WPBSA rules), one frame.

- The ball on: a red while reds remain, then (after potting a red) a colour, and so on; once
  the reds are gone (and the colour after the last red has been played), the colours in order
  yellow, green, brown, blue, pink, black. After a red the player may nominate a colour; if he
  does not, the colour the cue ball hits first is taken as nominated.
- Potting: each red 1 point; a colour its value. Colours are respotted while reds remain (and
  after the colour that follows the last red); in the colours stage a potted colour stays down.
- Fouls: the cue ball pocketed, no ball hit, a ball not on hit first, a ball not on pocketed.
  The penalty goes to the opponent: the value of the ball on, or of the highest ball concerned
  (hit first, or pocketed in error) if higher, but at least 4 and at most 7. Reds pocketed on a
  foul stay down; colours are respotted.
- Respotting: a colour goes on its own spot; if that is covered, on the highest-valued free
  spot; if none is free, as near its own spot as possible on the line toward the top cushion
  (when that line is blocked, which can happen to the pink and black, on the line below the
  spot instead). When several colours go back, the highest value is placed first.
- After a foul the opponent chooses to play on or to make the offender play again. Ball in hand
  in the D when the cue ball was pocketed.
- Free ball: if after a foul the incoming player is snookered (no ball on can be hit on both
  extreme edges in a straight line), he may nominate any other ball as the ball on. Hitting it
  first is legal; potting it scores the value of the ball on and it is respotted; if the ball on
  is potted too, only the ball on scores. A free-ball stroke that scores nothing and leaves the
  opponent snookered behind the free ball is a foul (except with only pink and black left).
- Miss (the common simplified form; in the real game a referee's judgement): a foul in which the
  cue ball first hit no ball on, while the striker was not snookered, is also a miss; the
  opponent may then also have the balls replaced where they were and the offender play again
  (the "replace" option). The three-miss frame loss and "best attempt" judgements are left out.
- End of frame: when only the black is left, the first score or foul ends the frame; if the
  scores are then equal, the black is respotted and the player to shoot first, with ball in
  hand in the D, is decided by lot (here: by the parity of the strokes played, so that a
  replay reproduces it).
- The break (points in one visit) is tracked; `best` holds each player's highest break.

Left out: the touching ball and push shot (the engine does not report contact durations),
jump shots, concessions and the "snookers required" situation, and obstruction by pocket jaws
in the snookered test (only balls obstruct here).
"""

from __future__ import annotations

from collections.abc import Mapping
from itertools import pairwise

import physics
from rules.aim import snookered
from rules.codes import FoulCode, NoteCode
from rules.events import ShotFacts, read_shot
from rules.inputs import Shot, ShotOptions
from rules.racks import REDS_FULL, Game, rack
from rules.spots import SNOOKER, SNOOKER_SPOTS, Point, is_free, place_near
from rules.state import Decision, Foul, Note, State, award, conclude, foul, note, other

GAME = Game.SNOOKER
TABLE = SNOOKER
COLOURS = ("yellow", "green", "brown", "blue", "pink", "black")
VALUES = {"yellow": 2, "green": 3, "brown": 4, "blue": 5, "pink": 6, "black": 7}
NEXT_COLOUR = dict(pairwise(COLOURS))
MIN_PENALTY, MAX_PENALTY = 4, 7


def new_game(
    seed: int, gap: float = 0.0, target: int = 0, reds: int = REDS_FULL, size: int = 9
) -> State:
    return State(game=GAME, balls=rack(GAME, seed, gap, reds), ball_in_hand="D", on="red")


def cue_ball(state: State) -> str:
    return "cue"


def is_red(ball: str) -> bool:
    return ball.startswith("red")


def value(ball: str) -> int:
    return 1 if is_red(ball) else VALUES[ball]


def balls_on(on: str, balls: Mapping[str, Point], colour: str | None = None) -> frozenset[str]:
    """The balls on for the stage `on`; after a red, `colour` narrows "any colour" to one."""
    if on == "red":
        return frozenset(b for b in balls if is_red(b))
    if on == "colour":
        return frozenset({colour} if colour else (b for b in balls if b in VALUES))
    return frozenset({on})


def targets(state: State, balls: Mapping[str, Point]) -> frozenset[str]:
    return balls_on(state.on, balls)


def options(state: State) -> ShotOptions:
    """A free ball may be any object ball but the ball on; after a red, any colour may be
    nominated; otherwise nothing is nominated."""
    if state.free_ball:
        on = balls_on(state.on, state.balls)
        return ShotOptions(nominate=frozenset(state.balls) - on - {"cue"})
    if state.on == "colour":
        return ShotOptions(nominate=balls_on("colour", state.balls))
    return ShotOptions()


def respot_colours(colours: list[str], positions: dict[str, Point]) -> dict[str, Point]:
    """Put colours back (highest value first) per the respotting rule; updates `positions`."""
    placed: dict[str, Point] = {}
    by_value = sorted(colours, key=value, reverse=True)
    for c in by_value:
        spot = SNOOKER_SPOTS[c]
        free = [
            s
            for s in sorted(VALUES, key=value, reverse=True)
            if is_free(SNOOKER_SPOTS[s], positions, SNOOKER.R)
        ]
        if is_free(spot, positions, SNOOKER.R):
            p = spot
        elif free:
            p = SNOOKER_SPOTS[free[0]]
        else:
            p = place_near(spot, ((0.0, 1.0), (0.0, -1.0)), positions, SNOOKER)
        placed[c] = positions[c] = p
    return placed


def _next_on_after_visit(on: str, positions: dict[str, Point]) -> str:
    """The ball on for the incoming player once a visit ends."""
    if any(is_red(b) for b in positions):
        return "red"
    return on if on in VALUES else "yellow"


def _snookers_behind(free: str, on: str, facts: ShotFacts) -> bool:
    """After a free ball that scored nothing: is the opponent snookered by the free ball (and
    only because of it)? Allowed when the pink and black are the only object balls left."""
    after = facts.positions
    if set(after) - {"cue"} <= {"pink", "black"} or "cue" not in after:
        return False
    on_set = balls_on(_next_on_after_visit(on, after), after)
    without = {b: p for b, p in after.items() if b != free}
    return snookered("cue", on_set, after, SNOOKER.R) and not snookered(
        "cue", on_set, without, SNOOKER.R
    )


def _fouls(facts: ShotFacts, legal: frozenset[str], on_words: str) -> tuple[list[Foul], list[int]]:
    """The contact fouls of a stroke, and the values of the balls they concern."""
    fouls: list[Foul] = []
    concerned: list[int] = []
    if facts.cue_pocketed:
        fouls.append(foul(FoulCode.CUE_POCKETED, "cue ball pocketed (in-off)"))
    if facts.first_hit is None:
        why = f"cue ball hit no ball (the ball on was {on_words})"
        fouls.append(foul(FoulCode.NO_CONTACT, why))
    elif facts.first_hit not in legal:
        why = f"cue ball hit the {facts.first_hit} first, not {on_words}"
        fouls.append(foul(FoulCode.WRONG_BALL_FIRST, why, facts.first_hit))
        concerned.append(value(facts.first_hit))
    for b in facts.pocketed:
        if b not in legal:
            why = f"the {b} was pocketed but was not on"
            fouls.append(foul(FoulCode.POCKETED_NOT_ON, why, b))
            concerned.append(value(b))
    return fouls, concerned


def judge(
    state: State, shot: Shot, before: dict[str, Point], result: physics.Shot
) -> tuple[State, Decision]:
    me, opp = state.turn, other(state.turn)
    facts = read_shot(result, "cue", before)
    free = shot.nominate if state.free_ball else None
    colour = None
    if state.on == "colour":
        hit = facts.first_hit
        colour = shot.nominate or (hit if hit in VALUES else None)
    on_set = balls_on(state.on, before, colour)
    legal = on_set | ({free} if free else set())
    on_value = value(colour) if colour else (value(state.on) if state.on != "colour" else 0)

    on_words = {"red": "a red", "colour": colour or "a colour"}.get(state.on, state.on)
    fouls, concerned = _fouls(facts, legal, on_words)
    if free and not fouls and not facts.pocketed and _snookers_behind(free, state.on, facts):
        why = f"the free ball ({free}) left the opponent snookered"
        fouls.append(foul(FoulCode.FREE_BALL_SNOOKER, why, free))

    positions = dict(facts.positions)
    potted_colours = [b for b in facts.pocketed if b in VALUES]
    notes: list[Note] = []
    if fouls:
        penalty = min(MAX_PENALTY, max(MIN_PENALTY, on_value, *concerned))
        points = award(opp, penalty)
        back = potted_colours
        scored = 0
    else:
        if state.on in ("red", "colour"):
            scored = sum(value(b) if b in on_set else 1 for b in facts.pocketed)
            back = potted_colours
        else:
            scored = on_value if facts.pocketed else 0
            back = [b for b in potted_colours if b != state.on]
        points = award(me, scored)
    ends_frame = state.on == "black" and (fouls or scored)
    if ends_frame:
        back = []
    respotted = respot_colours(back, positions)
    visit = state.visit + scored
    best = list(state.best)
    best[me] = max(best[me], visit)
    common = {"balls": positions, "fouls": fouls, "points": points, "notes": notes}
    common["pocketed"] = tuple(facts.pocketed)
    common["respotted"] = respotted
    common["best"] = tuple(best)
    if ends_frame:
        total = (state.scores[0] + points[0], state.scores[1] + points[1])
        if total[0] != total[1]:
            winner = 0 if total[0] > total[1] else 1
            return conclude(state, next_player=winner, winner=winner, visit=0, **common)
        positions.pop("cue", None)
        positions.pop("black", None)
        common["respotted"] = respot_colours(["black"], positions)
        notes.append(note(NoteCode.BLACK_RESPOTTED, "scores level: the black is respotted"))
        lot = state.shots % 2
        return conclude(
            state,
            next_player=lot,
            ball_in_hand="D",
            on="black",
            free_ball=False,
            retake=None,
            visit=0,
            **common,
        )
    if fouls:
        on_next = _next_on_after_visit(state.on, positions)
        cue_down = facts.cue_pocketed
        next_on = balls_on(on_next, positions)
        free_next = not cue_down and snookered("cue", next_on, positions, SNOOKER.R)
        miss = facts.first_hit not in legal and not snookered("cue", legal, before, SNOOKER.R)
        options = ("play_on", "play_again", "replace") if miss else ("play_on", "play_again")
        if miss:
            notes.append(note(NoteCode.MISS, "foul and a miss"))
        if free_next:
            notes.append(note(NoteCode.FREE_BALL, "free ball"))
        return conclude(
            state,
            next_player=opp,
            ball_in_hand="D" if cue_down else None,
            options=options,
            on=on_next,
            free_ball=free_next,
            retake=state.evolve(retake=None) if miss else None,
            visit=0,
            **common,
        )
    if scored:
        if state.on == "red":
            on_next = "colour"
        elif state.on == "colour":
            on_next = "red" if any(is_red(b) for b in positions) else "yellow"
        else:
            on_next = NEXT_COLOUR[state.on] if state.on in facts.pocketed else state.on
        return conclude(
            state, next_player=me, on=on_next, free_ball=False, retake=None, visit=visit, **common
        )
    return conclude(
        state,
        next_player=opp,
        on=_next_on_after_visit(state.on, positions),
        free_ball=False,
        retake=None,
        visit=0,
        **common,
    )

"""Set-up positions: a rack of the player's own making (practice), checked and started.

A position names where some of a game's own balls lie. Two checks, one per source:

- A player's position (`check_position`, strict): every ball one of the game's (snooker's
  reds as the setup counts them), wholly on the bed and outside every pocket's capture circle
  (`rules.spots.on_table`), no two closer than 2R plus the spots' CLEARANCE, and the balls the
  game cannot end without there (`REQUIRED`: the 9, the 8, the black, all three carom balls).
  Its coordinates are rounded to the steps a placed cue ball is canonical in (0.1 mm,
  `rules.inputs.PLACE_STEPS`), so that a share link carries it exactly.
- A position the engine left (`check_start`, what a setup accepts): the same balls, each where
  the engine itself lets a ball rest (frozen to a neighbour, in a pocket's mouth: the scene's
  own check), coordinates as they are. A retake starts from the balls as a shot left them, to
  the last bit, so a record from it replays exactly.

A set-up position is never a break: its first shot is refereed as an ordinary shot of a rack
under way (`SET_UP_SHOTS`: no break rules, no nine-ball push-out), with ball in hand (the
game's region at the break: pool's anywhere, snooker's D) when the cue ball is left off.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import physics
from rules.codes import Refusal, RuleError
from rules.inputs import PLACE_STEPS, quantise
from rules.racks import REDS_FULL, Game, rack, table
from rules.spots import STANDARD_SIZE, Point, is_free, on_table
from rules.state import Region, State

#: The balls a position of each game must hold: the game cannot end (or, in three-cushion,
#: be played) without them.
REQUIRED: dict[Game, tuple[str, ...]] = {
    Game.NINEBALL: ("9",),
    Game.EIGHTBALL: ("8",),
    Game.SNOOKER: ("black",),
    Game.THREE_CUSHION: ("white", "yellow", "red"),
}
#: The ball in hand of a position without its cue ball.
IN_HAND: dict[Game, Region] = {
    Game.NINEBALL: "anywhere",
    Game.EIGHTBALL: "anywhere",
    Game.SNOOKER: "D",
}
#: Strokes a set-up position counts as played: past the break (0) and nine-ball's push-out
#: shot (1), so the referees judge its first shot as any other.
SET_UP_SHOTS = 2
#: Larger than any table (m): a coordinate beyond it is refused before it is rounded.
FAR = 100.0
#: Snooker's colours from the lowest value: the ball on when no red is left.
COLOURS = ("yellow", "green", "brown", "blue", "pink", "black")


def ball_names(game: Game, reds: int = REDS_FULL) -> tuple[str, ...]:
    """Every ball of `game` (snooker with `reds` reds), sorted: what a position may hold."""
    return tuple(sorted(rack(game, 0, reds=reds)))


def _finite(balls: Mapping[str, Point]) -> None:
    """RuleError (BAD_POSITION) for a coordinate no table has (not finite, beyond FAR m)."""
    for ball, p in balls.items():
        if not all(math.isfinite(v) and abs(v) <= FAR for v in p):
            raise _refuse(f"the {ball} is not on the table bed")


def canonical(balls: Mapping[str, Point]) -> dict[str, Point]:
    """The position with its coordinates in PLACE_STEPS, sorted by ball name; RuleError
    (BAD_POSITION) for a coordinate no table has."""
    _finite(balls)
    return {
        b: (quantise(p[0], PLACE_STEPS), quantise(p[1], PLACE_STEPS))
        for b, p in sorted(balls.items())
    }


def _balls_of_the_game(game: Game, position: Mapping[str, Point], reds: int) -> None:
    known = ball_names(game, reds)
    for ball in position:
        if ball not in known:
            raise _refuse(f"{ball!r} is not a ball of {game.value} (its balls: {', '.join(known)})")
    missing = [b for b in REQUIRED[game] if b not in position]
    if missing:
        raise _refuse(f"a {game.value} position needs the {', '.join(missing)}")


def check_start(
    game: Game, balls: Mapping[str, Point], size: int = STANDARD_SIZE, reds: int = REDS_FULL
) -> dict[str, Point]:
    """The position as given (its order too: the engine meets simultaneous contacts, as in a
    frozen rack, in the order of the balls), if a rack can start from it as the engine left it
    (module docstring); RuleError (BAD_POSITION) naming what is wrong otherwise."""
    _finite(balls)
    _balls_of_the_game(game, balls, reds)
    try:
        physics.parse_scene({"table": table(game, size).preset, "balls": dict(balls)})
    except physics.SceneError as error:
        raise _refuse(f"the balls cannot rest there: {error}") from None
    return dict(balls)


def _refuse(why: str) -> RuleError:
    return RuleError(Refusal.BAD_POSITION, why)


def check_position(
    game: Game, balls: Mapping[str, Point], size: int = STANDARD_SIZE, reds: int = REDS_FULL
) -> dict[str, Point]:
    """A player's position, canonical (see `canonical`); RuleError (BAD_POSITION) naming the
    first ball that cannot start there, or the ball missing, when it is not a valid start."""
    on = table(game, size)
    position = canonical(balls)
    _balls_of_the_game(game, position, reds)
    for ball, (x, y) in position.items():
        if not on_table((x, y), on):
            raise _refuse(f"the {ball} is not on the table bed (or is in a pocket)")
    for ball, p in position.items():
        if not is_free(p, position, on.R, ignore=ball):
            raise _refuse(f"the {ball} overlaps another ball")
    return position


def opening(first: State, position: Mapping[str, Point]) -> State:
    """The state a set-up position starts from: the rack's own start (`first`, with its
    options and breaker) with the position's balls, judged as a rack under way."""
    cue = "cue" if first.game in IN_HAND else None
    in_hand = IN_HAND[first.game] if cue is not None and cue not in position else None
    on = first.on
    if first.game is Game.SNOOKER and not any(b.startswith("red") for b in position):
        on = next(c for c in COLOURS if c in position)
    return first.evolve(
        balls=dict(position), ball_in_hand=in_hand, shots=SET_UP_SHOTS, on=on, visit=0
    )


# ----- named presets --------------------------------------------------------------------------
#: Space between the centres of two balls set frozen (m): 2R and 0.2 mm, so that they still
#: do not overlap once each coordinate is rounded to PLACE_STEPS.
FROZEN = 2e-4


def _toward(a: Point, b: Point, d: float) -> Point:
    """The point `d` from `a` toward `b`."""
    k = d / math.dist(a, b)
    return (a[0] + k * (b[0] - a[0]), a[1] + k * (b[1] - a[1]))


def _pool_presets(game: Game, size: int) -> dict[str, dict[str, Point]]:
    on = table(game, size)
    w, l, R = on.width, on.length, on.R
    corner = (w, l)  # the top right pocket's mouth
    key = "9" if game is Game.NINEBALL else "8"
    lead = "1"  # the lowest ball, hit first
    front = _toward(corner, (w / 2, l / 2), 0.25 * w)
    behind = _toward(front, corner, -(2 * R + FROZEN))
    spare = (0.2 * w, 0.7 * l)
    # Nine-ball: the 1 into the 9; eight-ball: the 1 into the 9, the 8 out of the way.
    combination = {lead: behind, "9": front, "cue": _toward(behind, corner, -0.5 * w)}
    if game is Game.EIGHTBALL:
        combination["8"] = spare
    long_pot = {lead: _toward(corner, (0.0, 0.0), 0.2 * l), "cue": (0.2 * w, 0.2 * l)}
    long_pot[key] = spare
    return {"combination": combination, "long_pot": long_pot}


def _snooker_presets() -> dict[str, dict[str, Point]]:
    on = table(Game.SNOOKER)
    w, l, R = on.width, on.length, on.R
    corner = (w, l)
    front = _toward(corner, (w / 2, l / 2), 0.3)
    black = (w / 2, l - 0.324)
    combination = {
        "red1": front,
        "red2": _toward(front, corner, -(2 * R + FROZEN)),
        "black": black,
        "cue": _toward(front, corner, -0.8),
    }
    long_pot = {
        "red1": _toward(corner, (0.0, 0.0), 0.35),
        "black": black,
        "cue": _toward(corner, (0.0, 0.0), 2.6),
    }
    return {"combination": combination, "long_pot": long_pot}


def _carom_presets() -> dict[str, dict[str, Point]]:
    on = table(Game.THREE_CUSHION)
    w, l = on.width, on.length
    # The "standard" around-the-table shot: the white near the long rail at the head end, the
    # yellow beside it nearer the short rail, the red at the far end: three rails the long way.
    standard = {
        "white": (0.78 * w, 0.3 * l),
        "yellow": (0.9 * w, 0.12 * l),
        "red": (0.3 * w, 0.8 * l),
    }
    return {"standard": standard}


def presets(game: Game, size: int = STANDARD_SIZE) -> dict[str, dict[str, Point]]:
    """The named practice positions of `game` on its `size` table, each checked (the game's
    own rack, "the break", is a re-rack and not among them): pool and snooker a frozen-ball
    combination into the top right pocket and a long pot down the table; three-cushion its
    standard around-the-table position. Pool's scale with the table."""
    if game in (Game.NINEBALL, Game.EIGHTBALL):
        found = _pool_presets(game, size)
    elif game is Game.SNOOKER:
        found = _snooker_presets()
    else:
        found = _carom_presets()
    return {name: check_position(game, balls, size) for name, balls in found.items()}

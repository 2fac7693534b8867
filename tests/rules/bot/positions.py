"""Random positions of each game, as the referee could meet them mid-game.

Each position places a random subset of the game's balls at random free points of the table,
with a random player to act and the game-specific fields drawn consistently (eight-ball
groups, snooker's ball on and free ball, a ball in hand, a choice pending, nine-ball's shot
after the break, when a push-out is allowed), so that the bot and its candidates can be tried
far from the few positions whole games reach.
"""

from __future__ import annotations

import random

from rules.game import Setup, start
from rules.racks import Game
from rules.referee import referee
from rules.snooker import COLOURS, is_red
from rules.spots import Point, in_region, is_free
from rules.state import State


def _scatter(names: list[str], state: State, rng: random.Random) -> dict[str, Point]:
    table = referee(state.game).TABLE
    balls: dict[str, Point] = {}
    for b in names:
        for _ in range(200):
            p = (rng.uniform(0, table.width), rng.uniform(0, table.length))
            if in_region(p, "anywhere", table) and is_free(p, balls, table.R):
                balls[b] = (round(p[0], 4), round(p[1], 4))
                break
    return balls


def _pool(state: State, rng: random.Random) -> State:
    objects = [b for b in state.balls if b != "cue"]
    keep = sorted(rng.sample(objects, rng.randint(1, len(objects))), key=lambda b: int(b))
    if state.game == Game.NINEBALL and "9" not in keep:
        keep.append("9")
    if state.game == Game.EIGHTBALL and "8" not in keep:
        keep.append("8")
    in_hand = rng.random() < 0.3
    balls = _scatter(keep if in_hand else ["cue", *keep], state, rng)
    fields: dict = {"ball_in_hand": "anywhere" if in_hand else None}
    if state.game == Game.EIGHTBALL and rng.random() < 0.6:
        fields["groups"] = ("solids", "stripes") if rng.random() < 0.5 else ("stripes", "solids")
    if state.game == Game.NINEBALL and not in_hand and rng.random() < 0.15:
        fields["pending"] = ("play_on", "play_again")
    elif state.game == Game.NINEBALL and rng.random() < 0.2:
        fields["shots"] = 1  # the shot after the break: a push-out is allowed
    return state.evolve(balls=balls, **fields)


def _snooker(state: State, rng: random.Random) -> State:
    reds = [b for b in state.balls if is_red(b)]
    n_reds = rng.randint(0, len(reds))
    colours = list(COLOURS[rng.randint(0, len(COLOURS) - 1) :]) if n_reds == 0 else list(COLOURS)
    balls = _scatter(["cue", *reds[:n_reds], *colours], state, rng)
    fields: dict = {"on": rng.choice(("red", "colour")) if n_reds else colours[0]}
    if rng.random() < 0.2:
        fields["pending"] = ("play_on", "play_again")
    elif rng.random() < 0.2:
        fields["free_ball"] = True
    return state.evolve(balls=balls, **fields)


def random_position(game: Game, seed: int) -> State:
    """A position of `game` mid-game (shots > 0), drawn from `seed`."""
    rng = random.Random(seed)
    state = start(Setup(game=game, seed=seed)).evolve(
        shots=rng.randint(2, 30), turn=rng.randint(0, 1), ball_in_hand=None
    )
    if game in (Game.NINEBALL, Game.EIGHTBALL):
        return _pool(state, rng)
    if game == Game.SNOOKER:
        return _snooker(state, rng)
    return state.evolve(balls=_scatter(list(state.balls), state, rng))

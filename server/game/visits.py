"""What a break *is*, independent of the record it came in: its position and its inputs.

A leaderboard that keyed breaks by their record's bytes counted one break many times: the
record cut after the best visit, or with one more input, or (three-cushion, whose start has
no randomness) the same inputs under another seed, were all "new" records. So a break is
identified by what was played: the position its visit started from and the inputs of the
visit up to the one that made its score (`break_key`). Two records whose best visits share
those are the same break, whatever precedes or follows them and whatever their setup says.

The position is the start state with what does not change the play left out: scores, best
breaks, shot and foul counts, the winner and the seed (which only placed the balls), and with
the per-player fields (`groups`) seen from the visiting player, so that the same visit by
player 1 is the same break as by player 0. Positions are quantised as the records' digests
quantise them (`rules.record`).
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import dataclass

import msgpack

from rules.inputs import PlayerInput
from rules.record import hashed_state
from rules.state import State

#: Bytes of a break key's digest (hex in storage keys).
KEY_BYTES = 16


@dataclass(frozen=True, slots=True)
class Visit:
    """A player's best visit: where it started (`first`, an index into the steps) and the
    index of the input that made its score (`last`)."""

    player: int
    first: int
    last: int


def position(state: State, player: int) -> object:
    """The part of `state` that decides how a visit by `player` plays (module docstring)."""
    groups = state.groups if player == 0 else state.groups[::-1]
    neutral = state.evolve(
        turn=0,
        scores=(0, 0),
        foul_streak=(0, 0),
        shots=min(state.shots, 1),  # the break has rules of its own; later shots do not
        visit=0,
        best=(0, 0),
        over=False,
        winner=None,
        groups=groups,
    )
    return hashed_state(neutral)


def best_visits(start: State, steps: Sequence[tuple[PlayerInput, State]]) -> list[Visit | None]:
    """Each player's best visit in a game played from `start` (None: no break scored).

    A visit starts at the first input of a run of inputs by the same player (the state
    before it has that player to act); its score is reached at the input after which the
    player's `best` last rose."""
    found: list[Visit | None] = [None, None]
    before, first, acting = start, 0, None
    for n, (_, after) in enumerate(steps):
        if before.turn != acting:
            first, acting = n, before.turn
        for seat in (0, 1):
            if after.best[seat] > before.best[seat]:
                found[seat] = Visit(seat, first if seat == acting else n, n)
        before = after
    return found


def break_key(
    game: str, start: State, steps: Sequence[tuple[PlayerInput, State]], visit: Visit
) -> str:
    """The identity of a break (module docstring): a digest of the game, the position the
    visit started from and its inputs up to the one that made its score."""
    before = start if visit.first == 0 else steps[visit.first - 1][1]
    inputs = [action.model_dump(mode="json") for action, _ in steps[visit.first : visit.last + 1]]
    packed = msgpack.packb([game, position(before, visit.player), inputs])
    return hashlib.blake2b(packed, digest_size=KEY_BYTES).hexdigest()


def break_keys(
    game: str, start: State, steps: Sequence[tuple[PlayerInput, State]]
) -> tuple[str | None, str | None]:
    """Each player's best break's key (None: no break)."""
    visits = best_visits(start, steps)
    keys = [None if v is None else break_key(game, start, steps, v) for v in visits]
    return keys[0], keys[1]

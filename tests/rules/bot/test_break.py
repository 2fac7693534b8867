"""The break (rules.bot.candidates): the strongest level's nine-ball breaks scratch less than
the harder set the lower levels and the search baseline keep, and still pot a ball."""

from __future__ import annotations

from rules.bot.candidates import BREAK_SPEEDS, FINE, Kind, break_candidates, candidates
from rules.bot.levels import STRONGEST, level
from rules.bot.mcts import BASELINE_LEVEL, BASELINE_STROKES
from rules.bot.noise import draws, perturb, tournament
from rules.game import Setup, play, start
from rules.racks import Game
from rules.spots import POOL_TABLE

RACKS = 12
DRAWS = 6


def speeds(found) -> set[float]:
    return {c.shot.strike.speed for c in found}


def test_the_strongest_level_breaks_with_its_own_set_and_the_baseline_with_the_old_one():
    state = start(Setup(game=Game.NINEBALL, seed=3))
    strongest = candidates(state, STRONGEST)
    assert {c.kind for c in strongest} == {Kind.BREAK}
    assert speeds(strongest) == set(FINE.breaks[Game.NINEBALL])
    assert speeds(candidates(state, level(1))) == set(BREAK_SPEEDS[Game.NINEBALL])
    baseline = candidates(state, BASELINE_LEVEL, BASELINE_STROKES)
    assert speeds(baseline) == set(BREAK_SPEEDS[Game.NINEBALL])


def _played(speed_set) -> tuple[int, int]:
    """(scratches, breaks that kept the table) over RACKS racks and DRAWS noise draws each."""
    scratched = kept = 0
    for seed in range(RACKS):
        state = start(Setup(game=Game.NINEBALL, seed=500 + seed))
        for c in break_candidates(state, speed_set):
            for d in draws(seed, DRAWS, "break test"):
                outcome = play(state, perturb(c.shot, tournament(1.0), d, POOL_TABLE.R))
                scratched += bool(outcome.decision.fouls)
                kept += not outcome.decision.fouls and outcome.state.turn == 0
    return scratched, kept


def test_the_soft_breaks_scratch_less_and_still_keep_the_table():
    soft_scratches, soft_kept = _played(FINE.breaks)
    hard_scratches, hard_kept = _played(BREAK_SPEEDS)
    assert soft_scratches < hard_scratches
    assert soft_kept >= hard_kept

"""Pool on 7, 8 and 9 ft tables: the bed, the rack, the spots, the head string and the
ball-in-hand regions scale with the table, and a game on a smaller table replays exactly."""

from __future__ import annotations

import itertools
import math

import pytest

import physics
from rules import compact
from rules.game import Setup, play, start
from rules.inputs import accept
from rules.pool import respot_on_foot_spot
from rules.racks import Game, rack, table
from rules.record import GameRecord, replay
from rules.referee import table_of
from rules.spots import POOL_SIZES, in_region, on_table

POOL = (Game.NINEBALL, Game.EIGHTBALL)
#: WPA playing surfaces (inches) of each size.
BEDS = {7: (39, 78), 8: (44, 88), 9: (50, 100)}
INCH = 0.0254


@pytest.mark.parametrize("size", sorted(POOL_SIZES))
def test_each_size_is_the_wpa_bed_with_the_same_balls_and_pockets(size: int) -> None:
    on = POOL_SIZES[size]
    w, l = BEDS[size]
    assert (on.width, on.length) == pytest.approx((w * INCH, l * INCH), abs=1e-4)
    assert on.R == POOL_SIZES[9].R and on.spec.corner_mouth == POOL_SIZES[9].spec.corner_mouth
    far = next(p for p in on.pockets if p.name == "top_right")
    assert math.dist(far.center, (on.width, on.length)) < 0.03  # the pockets move with the bed
    physics.tables.check_table(on.spec, on.R)


@pytest.mark.parametrize("game", POOL)
@pytest.mark.parametrize("size", sorted(POOL_SIZES))
def test_racks_scale_inside_the_bed_without_overlaps(game: Game, size: int) -> None:
    on = table(game, size)
    for seed, gap in itertools.product(range(6), (0.0, 0.0005)):
        balls = rack(game, seed, gap, size=size)
        assert all(on_table(p, on) for p in balls.values())
        for (a, p), (b, q) in itertools.combinations(balls.items(), 2):
            assert math.dist(p, q) >= 2 * on.R - 1e-12, (size, seed, a, b)
        # The apex on the foot spot, the cue ball on the head spot, of this table.
        objects = [b for b in balls if b != "cue"]
        apex = min(objects, key=lambda b: balls[b][1])
        assert balls[apex] == pytest.approx((on.width / 2, 3 * on.length / 4))
        assert balls["cue"] == pytest.approx((on.width / 2, on.length / 4))
        physics.parse_scene({"table": on.preset, "balls": balls})


def test_spots_lines_and_regions_scale_with_the_table() -> None:
    small, full = POOL_SIZES[7], POOL_SIZES[9]
    assert small.head_string == pytest.approx(small.length / 4)
    assert small.head_string < full.head_string
    behind_small = (small.width / 2, small.head_string - 0.01)
    past_small = (small.width / 2, small.head_string + 0.01)
    assert in_region(behind_small, "kitchen", small) and not in_region(past_small, "kitchen", small)
    assert in_region(past_small, "kitchen", full)  # the 9 ft head string lies further up
    assert respot_on_foot_spot({}, 7) == pytest.approx(small.foot_spot)
    assert respot_on_foot_spot({}, 9) == pytest.approx(full.foot_spot)
    # On the 7 ft table a ball beyond its foot cushion is off the table.
    assert not on_table((small.width / 2, full.length - 0.1), small)


def test_only_pool_has_other_sizes() -> None:
    with pytest.raises(ValueError, match="only pool"):
        Setup(game="snooker", seed=1, size=7)
    with pytest.raises(ValueError):
        Setup(game="nineball", seed=1, size=6)


@pytest.mark.parametrize("game", POOL)
def test_a_break_on_a_seven_foot_table_is_simulated_on_it_and_replays(game: Game) -> None:
    setup = Setup(game=game, seed=4, size=7)
    first = start(setup)
    assert first.size == 7 and table_of(first) is POOL_SIZES[7]
    shot = accept({"strike": {"ball": "cue", "speed": 7.0, "heading": 90.0}})
    outcome = play(first, shot)
    on = POOL_SIZES[7]
    assert all(on_table(p, on) or p[1] > 0 for p in outcome.state.balls.values())
    assert all(
        x <= on.width + 0.1 and y <= on.length + 0.1 for x, y in outcome.state.balls.values()
    )
    record = GameRecord.begin(setup).extend(shot, outcome.state)
    assert replay(record).final == outcome.state
    # The same break on the 9 ft table ends elsewhere: the table is not the same.
    nine = play(start(Setup(game=game, seed=4)), shot).state
    assert nine.balls != outcome.state.balls
    linked = compact.decode(compact.encode(record))
    assert linked == record and linked.setup.size == 7


def test_the_standard_table_hashes_as_before_sizes() -> None:
    """A 9 ft state's digest is the one records made before sizes existed carry."""
    from rules.record import hashed_state

    state = start(Setup(game="nineball", seed=1))
    assert "size" not in hashed_state(state)
    assert hashed_state(state.evolve(size=8))["size"] == 8

"""Starting layouts: on the table, never overlapping, per the standard, reproducible."""

from __future__ import annotations

import itertools
import math

import pytest

import physics
from rules.racks import CAROM_BREAK_OFFSET, REDS, SOLIDS, STRIPES, rack
from rules.spots import CAROM_TABLE, POOL_TABLE, SNOOKER, SNOOKER_SPOTS, on_table

TABLES = {
    "nineball": POOL_TABLE,
    "eightball": POOL_TABLE,
    "snooker": SNOOKER,
    "three_cushion": CAROM_TABLE,
}
GAPS = (0.0, 0.0005)


@pytest.mark.parametrize("game", TABLES)
@pytest.mark.parametrize("gap", GAPS)
def test_racks_are_on_the_table_without_overlaps_and_valid_scenes(game, gap):
    table = TABLES[game]
    for seed in range(10):
        balls = rack(game, seed, gap)
        assert all(on_table(p, table) for p in balls.values())
        for (a, p), (b, q) in itertools.combinations(balls.items(), 2):
            assert math.dist(p, q) >= 2 * table.R - 1e-12, (game, seed, a, b)
        physics.parse_scene({"table": table.preset, "balls": balls})


@pytest.mark.parametrize("game", TABLES)
def test_racks_are_reproducible_from_the_seed(game):
    assert rack(game, 7, 0.0003) == rack(game, 7, 0.0003)
    layouts = {tuple(sorted(rack(game, s, 0.0003).items())) for s in range(6)}
    assert len(layouts) > 1


@pytest.mark.parametrize("game", ["nineball", "eightball", "snooker"])
def test_gaps_are_small_and_realistic(game):
    gap, R = 0.0005, TABLES[game].R
    balls = {b: p for b, p in rack(game, 4, gap).items() if b != "cue" and b not in SNOOKER_SPOTS}
    for b, p in balls.items():
        nearest = min(math.dist(p, q) for c, q in balls.items() if c != b)
        assert 2 * R <= nearest <= 2 * R + 2 * gap + 1e-12
    tight = {b: p for b, p in rack(game, 4).items() if b in balls}
    for b, p in tight.items():
        assert min(math.dist(p, q) for c, q in tight.items() if c != b) == pytest.approx(2 * R)


def test_nineball_diamond_has_the_one_at_the_apex_and_the_nine_in_the_middle():
    for seed in range(10):
        balls = rack("nineball", seed)
        assert set(balls) == {"cue", *map(str, range(1, 10))}
        assert balls["1"] == POOL_TABLE.foot_spot
        centre = (
            POOL_TABLE.foot_spot[0],
            POOL_TABLE.foot_spot[1] + 2 * math.sqrt(3) * POOL_TABLE.R,
        )
        assert balls["9"] == pytest.approx(centre)
        assert balls["cue"] == POOL_TABLE.head_spot
    assert len({rack("nineball", s)["5"] for s in range(10)}) > 1


def test_eightball_triangle_has_the_eight_in_the_middle_and_mixed_back_corners():
    R = POOL_TABLE.R
    fx, fy = POOL_TABLE.foot_spot
    back_y = fy + 4 * math.sqrt(3) * R
    for seed in range(10):
        balls = rack("eightball", seed)
        assert set(balls) == {"cue", *SOLIDS, *STRIPES, "8"}
        assert balls["8"] == pytest.approx((fx, fy + 2 * math.sqrt(3) * R))
        corners = [b for b, p in balls.items() if p == pytest.approx((fx - 4 * R, back_y))] + [
            b for b, p in balls.items() if p == pytest.approx((fx + 4 * R, back_y))
        ]
        assert len(corners) == 2 and {corners[0] in SOLIDS, corners[1] in SOLIDS} == {True, False}
        assert fy in {p[1] for p in balls.values()}


def test_snooker_colours_on_their_spots_and_reds_behind_the_pink_not_touching():
    R = SNOOKER.R
    for seed in range(5):
        balls = rack("snooker", seed, 0.0002)
        assert {b: balls[b] for b in SNOOKER_SPOTS} == SNOOKER_SPOTS
        reds = [balls[r] for r in REDS]
        pink = SNOOKER_SPOTS["pink"]
        nearest = min(math.dist(pink, p) for p in reds)
        assert 2 * R < nearest < 2 * R + 0.001
        assert all(p[1] > pink[1] for p in reds)


def test_three_cushion_break_position():
    hx, hy = CAROM_TABLE.head_spot
    sides = set()
    for seed in range(10):
        balls = rack("three_cushion", seed)
        assert balls["yellow"] == (hx, hy) and balls["red"] == CAROM_TABLE.foot_spot
        assert balls["white"][1] == hy and abs(balls["white"][0] - hx) == pytest.approx(
            CAROM_BREAK_OFFSET
        )
        sides.add(balls["white"][0] > hx)
    assert sides == {True, False}


@pytest.mark.parametrize("gap", [-0.001, 0.01, math.nan])
def test_bad_gap_is_refused(gap):
    with pytest.raises(ValueError, match="gap"):
        rack("nineball", 1, gap)

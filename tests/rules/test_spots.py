"""Respots and placements on crowded tables: always on the table, never on another ball."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from rules.pool import respot_on_foot_spot
from rules.snooker import VALUES, respot_colours
from rules.spots import POOL_TABLE, SNOOKER, SNOOKER_SPOTS, Table, in_region, is_free, on_table


def layout(table: Table, near: tuple[float, float], spread: float):
    """Non-overlapping balls scattered around `near` (crowding the spots on purpose)."""
    point = st.tuples(
        st.floats(near[0] - spread, near[0] + spread), st.floats(near[1] - spread, near[1] + spread)
    )

    def keep(points):
        balls: dict[str, tuple[float, float]] = {}
        for p in points:
            if on_table(p, table) and is_free(p, balls, table.R):
                balls[f"b{len(balls)}"] = p
        return balls

    return st.lists(point, max_size=25).map(keep)


@settings(max_examples=150, deadline=None)
@given(layout(POOL_TABLE, POOL_TABLE.foot_spot, 0.3))
def test_pool_respot_is_free_on_the_table_and_on_the_long_string(balls):
    p = respot_on_foot_spot(balls)
    assert on_table(p, POOL_TABLE) and is_free(p, balls, POOL_TABLE.R)
    assert p[0] == POOL_TABLE.foot_spot[0]
    if is_free(POOL_TABLE.foot_spot, balls, POOL_TABLE.R):
        assert p == POOL_TABLE.foot_spot


@settings(max_examples=150, deadline=None)
@given(
    layout(SNOOKER, SNOOKER_SPOTS["pink"], 0.7),
    st.sets(st.sampled_from(sorted(VALUES)), min_size=1),
)
def test_snooker_respots_are_free_on_the_table_and_follow_the_order(balls, colours):
    positions = dict(balls)
    placed = respot_colours(sorted(colours), positions)
    assert set(placed) == colours
    for c, p in placed.items():
        others = {b: q for b, q in positions.items() if b != c}
        assert on_table(p, SNOOKER) and is_free(p, others, SNOOKER.R)
    # The highest colour is placed first: on its own spot whenever that was free.
    top = max(colours, key=VALUES.get)
    if is_free(SNOOKER_SPOTS[top], balls, SNOOKER.R):
        assert placed[top] == SNOOKER_SPOTS[top]


def test_regions():
    w, length = POOL_TABLE.width, POOL_TABLE.length
    assert in_region((w / 2, length / 4), "kitchen", POOL_TABLE)
    assert not in_region((w / 2, length / 4 + 0.01), "kitchen", POOL_TABLE)
    assert in_region((w / 2, length / 2), "anywhere", POOL_TABLE)
    assert not in_region((POOL_TABLE.R, POOL_TABLE.R), "anywhere", POOL_TABLE)  # in the pocket
    brown = SNOOKER_SPOTS["brown"]
    assert in_region(brown, "D", SNOOKER)
    assert not in_region((brown[0], brown[1] + 0.01), "D", SNOOKER)  # beyond the baulk line
    assert not in_region((brown[0] + 0.3, brown[1] - 0.01), "D", SNOOKER)  # outside the arc
    assert math.isclose(SNOOKER_SPOTS["yellow"][0] - brown[0], 0.292)

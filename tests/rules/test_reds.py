"""Snooker with six or ten reds: the rack, the referee and the records hold as with fifteen."""

from __future__ import annotations

import itertools
import math

import msgpack
import pytest
from pydantic import ValidationError

from rules.compact import decode, encode, pack, unpack
from rules.game import Setup, start
from rules.racks import Game, rack
from rules.record import replay
from rules.selfplay import selfplay
from rules.spots import SNOOKER


@pytest.mark.parametrize("reds", [6, 10, 15])
def test_a_rack_of_n_reds_is_a_triangle_behind_the_pink_that_touches_nothing(reds: int) -> None:
    balls = rack(Game.SNOOKER, 7, 0.0002, reds)
    assert sorted(b for b in balls if b.startswith("red")) == sorted(
        f"red{n}" for n in range(1, reds + 1)
    )
    for (a, p), (b, q) in itertools.combinations(balls.items(), 2):
        assert math.dist(p, q) >= 2 * SNOOKER.R, (a, b)
    apex = min(p[1] for b, p in balls.items() if b.startswith("red"))
    assert apex > balls["pink"][1]


def test_only_snooker_takes_fewer_reds_and_only_six_ten_or_fifteen() -> None:
    with pytest.raises(ValidationError, match="only snooker"):
        Setup(game="nineball", seed=1, reds=6)
    with pytest.raises(ValidationError):
        Setup(game="snooker", seed=1, reds=7)
    with pytest.raises(ValueError, match="reds"):
        rack(Game.SNOOKER, 1, 0.0, 7)


def test_a_six_red_frame_replays_from_its_link_and_full_frames_links_are_unchanged() -> None:
    setup = Setup(game="snooker", seed=4, reds=6)
    assert sum(b.startswith("red") for b in start(setup).balls) == 6
    record, _ = selfplay(setup, max_inputs=60)
    again = decode(encode(record))
    assert again == record and again.setup.reds == 6
    assert replay(again).final.scores == record.final.scores
    full = selfplay(Setup(game="snooker", seed=4), max_inputs=2)[0]
    assert len(msgpack.unpackb(pack(full))) == 12  # the format of links made before
    assert len(msgpack.unpackb(pack(record))) == 13
    assert unpack(pack(full)).setup.reds == 15

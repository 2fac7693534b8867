"""Set-up positions: checked against the game, started as a rack under way, carried exactly
by records and share links."""

from __future__ import annotations

import math

import msgpack
import pytest

from rules import compact
from rules.codes import Refusal, RuleError
from rules.game import Setup, play, start
from rules.inputs import accept
from rules.positions import SET_UP_SHOTS, canonical, check_position, check_start, presets
from rules.racks import Game
from rules.record import GameRecord, replay
from rules.spots import POOL_SIZES

W, L = POOL_SIZES[9].width, POOL_SIZES[9].length
#: A straight pot of the 9 into the top right pocket (the 9 is the lowest ball on the table).
POSITION = {"cue": (W - 0.5, L - 0.5), "9": (W - 0.2, L - 0.2)}


def test_a_position_starts_a_rack_under_way() -> None:
    first = start(Setup(game="nineball", seed=5, position=POSITION))
    assert first.balls == canonical(POSITION) and first.ball_in_hand is None
    assert first.shots == SET_UP_SHOTS and first.turn == 0 and first.scores == (0, 0)
    no_cue = {b: p for b, p in POSITION.items() if b != "cue"}
    assert start(Setup(game="nineball", seed=5, position=no_cue)).ball_in_hand == "anywhere"
    eight = start(Setup(game="eightball", seed=5, position={"8": (0.6, 1.8), "cue": (0.6, 1.0)}))
    assert eight.shots == SET_UP_SHOTS and eight.groups == (None, None)
    snooker = {"black": (0.9, 3.2), "pink": (0.9, 2.6), "cue": (0.9, 1.0)}
    first = start(Setup(game="snooker", seed=1, position=snooker))
    assert first.on == "pink" and first.ball_in_hand is None
    with_red = {**snooker, "red3": (0.5, 2.0)}
    assert start(Setup(game="snooker", seed=1, position=with_red)).on == "red"


@pytest.mark.parametrize(
    ("game", "balls", "why"),
    [
        (Game.NINEBALL, {"9": (0.5, 1.0), "10": (0.5, 1.5)}, "not a ball of nineball"),
        (Game.NINEBALL, {"9": (0.5, 1.0), "red1": (0.5, 1.5)}, "not a ball"),
        (Game.NINEBALL, {"9": (0.01, 1.0)}, "not on the table"),
        (Game.NINEBALL, {"9": (0.5, 2.6)}, "not on the table"),
        (Game.NINEBALL, {"9": (0.5, 1.8e308)}, "not on the table"),
        (Game.NINEBALL, {"9": (float("nan"), 1.0)}, "not on the table"),
        (Game.NINEBALL, {"9": (0.02, 0.02)}, "not on the table"),  # in the corner pocket
        (Game.NINEBALL, {"9": (0.5, 1.0), "1": (0.5, 1.05)}, "overlaps"),
        (Game.NINEBALL, {"1": (0.5, 1.0)}, "needs the 9"),
        (Game.EIGHTBALL, {"9": (0.5, 1.0)}, "needs the 8"),
        (Game.THREE_CUSHION, {"white": (0.5, 1.0), "red": (0.5, 2.0)}, "needs the yellow"),
        (Game.SNOOKER, {"black": (0.9, 3.2), "red11": (0.5, 2.0)}, "not a ball"),
    ],
)
def test_bad_positions_are_refused_with_the_reason(game: Game, balls: dict, why: str) -> None:
    reds = 10 if game is Game.SNOOKER else 15
    with pytest.raises(RuleError, match=why) as refused:
        check_position(game, balls, reds=reds)
    assert refused.value.code is Refusal.BAD_POSITION


def test_the_bed_is_the_tables_own() -> None:
    """A ball near the foot cushion of a 9 ft table lies off a 7 ft one."""
    far = {"9": (0.5, 2.3)}
    check_position(Game.NINEBALL, far)
    with pytest.raises(RuleError, match="not on the table"):
        check_position(Game.NINEBALL, far, size=7)


def test_a_players_position_is_canonical_and_a_left_one_exact() -> None:
    assert check_position(Game.NINEBALL, {"9": (0.123456789, 1.0)}) == {"9": (0.1235, 1.0)}
    # A position as a shot leaves it is kept to the bit, frozen balls and all: two balls
    # frozen as the engine leaves them (2R apart within its tolerance) are a player's overlap
    # once rounded to 0.1 mm, but a retake's start.
    R = POOL_SIZES[9].R
    frozen = {"9": (0.5, 1.0), "1": (0.5 + 2 * R - 5e-10, 1.0)}
    with pytest.raises(RuleError, match="overlaps"):
        check_position(Game.NINEBALL, frozen)
    assert list(check_start(Game.NINEBALL, frozen).items()) == list(frozen.items())
    setup = Setup(game="nineball", seed=3, position=frozen)
    assert setup.position == frozen and start(setup).balls == frozen
    rack = start(Setup(game="nineball", seed=3)).balls
    assert Setup(game="nineball", seed=3, position=rack).position == rack
    # A record's link keeps the position's doubles and order (the engine's results depend on
    # the order of frozen balls).
    record = GameRecord.begin(Setup(game="nineball", seed=3, position=rack))
    linked = compact.decode(compact.encode(record)).setup.position
    assert list(linked.items()) == list(rack.items())
    with pytest.raises(ValueError, match="overlap"):
        Setup(game="nineball", seed=3, position={**rack, "cue": rack["1"]})


def test_a_record_from_a_position_replays_exactly_and_links_carry_it() -> None:
    setup = Setup(game="nineball", seed=9, position=POSITION, size=9)
    first = start(setup)
    shot = accept({"strike": {"ball": "cue", "speed": 2.0, "heading": 45.0}})
    outcome = play(first, shot)
    assert "9" not in outcome.state.balls and outcome.state.winner == 0
    record = GameRecord.begin(setup).extend(shot, outcome.state)
    assert replay(record).final == outcome.state
    linked = compact.decode(compact.encode(record))
    assert linked == record and linked.setup.set_up
    # A record that claims the game's own rack does not replay the position's game.
    bare = record.model_copy(update={"setup": setup.model_copy(update={"position": None})})
    with pytest.raises(RuleError):
        replay(bare)


def test_a_shared_position_round_trips_and_is_checked_on_open() -> None:
    setup = Setup(game="nineball", seed=0, size=8, position={"9": (0.5, 1.0), "cue": (0.5, 0.3)})
    code = compact.encode_position(setup)
    assert len(code) < 60 and compact.decode_position(code) == setup
    for bad in ("", "!!", "AAAA", compact.encode(GameRecord.begin(Setup(game="nineball", seed=1)))):
        with pytest.raises(RuleError) as refused:
            compact.decode_position(bad)
        assert refused.value.code is Refusal.MALFORMED
    names = compact._names(setup)[0]
    overlapping = [names.index("9"), 5000, 10000, names.index("cue"), 5000, 10100]
    forged = compact._to_link(msgpack.packb([1, 0, 8, 15, overlapping]))
    with pytest.raises(RuleError, match="overlaps") as refused:
        compact.decode_position(forged)
    assert refused.value.code is Refusal.BAD_POSITION


@pytest.mark.parametrize("game", list(Game))
def test_named_positions_are_valid_on_every_size_and_scale_with_it(game: Game) -> None:
    sizes = sorted(POOL_SIZES) if game in (Game.NINEBALL, Game.EIGHTBALL) else [9]
    for size in sizes:
        found = presets(game, size)
        assert found and all(check_position(game, b, size) == b for b in found.values())
        first = start(Setup(game=game, seed=1, size=size, position=next(iter(found.values()))))
        assert first.shots == SET_UP_SHOTS
    if len(sizes) > 1:
        small, full = presets(game, 7)["combination"], presets(game, 9)["combination"]
        assert small["9"][1] < full["9"][1]  # nearer the foot of the shorter table
        # The combination's two balls are frozen (0.2 mm apart at most) on the 7 ft table too.
        gap = math.dist(small["1"], small["9"]) - 2 * POOL_SIZES[7].R
        assert 0 < gap <= 3e-4

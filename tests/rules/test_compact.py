"""The compact share-link form: a record survives it bit for bit, a shot takes at most 12
bytes before compression, and anything that is not a share link is refused with a code."""

from __future__ import annotations

import base64
import zlib

import msgpack
import pytest
from hypothesis import given
from hypothesis import strategies as st

from physics import ENGINE_VERSION
from rules.codes import Refusal
from rules.compact import decode, encode, pack, unpack
from rules.game import Setup
from rules.inputs import OPTIONS, Choice, Shot, Strike
from rules.racks import Game
from rules.record import Final, GameRecord, replay
from rules.selfplay import selfplay

from .script import refused

names = st.sampled_from(["cue", "yellow", "pink", "red7", "top_left", "stranger", "x"])
strikes = st.builds(
    Strike,
    ball=names,
    speed=st.floats(0.001, 12.0),
    heading=st.floats(-720.0, 720.0),
    elevation=st.sampled_from([0.0, 0.01, 30.0, 89.0]),
    a=st.sampled_from([0.0, 0.3, -0.001]),
    b=st.sampled_from([0.0, -0.1, 0.4]),
)
shots = st.builds(
    Shot,
    strike=strikes,
    place=st.none() | st.tuples(st.floats(-1.0, 4.0), st.floats(-1.0, 4.0)),
    push_out=st.booleans(),
    call=st.none() | names,
    nominate=st.none() | names,
)
inputs = st.lists(shots | st.builds(Choice, option=st.sampled_from(OPTIONS)), max_size=30)

#: Bytes a shot may take in the msgpack form, its digest included (the issue's goal).
SHOT_BYTES = 12


@pytest.fixture(scope="module")
def games() -> dict[str, GameRecord]:
    found = {}
    for game, seed in (("nineball", 1), ("snooker", 2), ("eightball", 3), ("three_cushion", 1)):
        setup = Setup(game=game, seed=seed, gap=0.0002, target=2)
        found[game] = selfplay(setup, max_inputs=120)[0]
    return found


def test_a_share_link_decodes_to_the_same_record_and_replays(games):
    for record in games.values():
        link = encode(record)
        assert set(link) <= set("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789-_")
        again = decode(link)
        assert again == record
        assert replay(again).final.over


def test_every_input_field_survives():
    strike = Strike(ball="cue", speed=4.321, heading=359.9999, elevation=12.5, a=-0.25, b=0.1)
    inputs = (
        Shot(strike=strike, place=(0.1234, 2.0001)),
        Shot(strike=strike, push_out=True),
        Shot(strike=strike.model_copy(update={"ball": "yellow"}), call="top_left"),
        Shot(strike=strike.model_copy(update={"ball": "mystery"}), nominate="pink", call="x"),
        Shot(strike=Strike(ball="cue", speed=0.001, heading=0.0), nominate="nobody"),
        *(Choice(option=o) for o in ("play_on", "play_again", "replace")),
    )
    record = GameRecord(
        engine=ENGINE_VERSION,
        setup=Setup(game="snooker", seed=2**62, gap=0.0001234, target=7),
        inputs=inputs,
        digests=tuple(range(0, 65536, 65536 // len(inputs)))[: len(inputs)],
        final=Final(scores=(147, 0), winner=0, digest="00ff00ff00ff00ff"),
    )
    assert unpack(pack(record)) == record
    assert decode(encode(record)) == record


@given(inputs=inputs, game=st.sampled_from(list(Game)))
def test_any_inputs_survive(inputs, game):
    record = GameRecord(
        engine=ENGINE_VERSION,
        setup=Setup(game=game, seed=5),
        inputs=inputs,
        digests=[k % 65536 for k in range(len(inputs))],
        final=Final(scores=(0, 3), digest="0123456789abcdef"),
    )
    assert unpack(pack(record)) == record


def per_shot(record: GameRecord) -> float:
    """msgpack bytes per shot of the inputs and their digests (the fixed header left out)."""
    empty = record.model_copy(update={"inputs": (), "digests": ()})
    shots = sum(isinstance(a, Shot) for a in record.inputs)
    return (len(pack(record)) - len(pack(empty))) / shots


@pytest.mark.parametrize("game", ["nineball", "snooker"])
def test_a_shot_takes_at_most_twelve_bytes_before_compression(games, game):
    assert per_shot(games[game]) <= SHOT_BYTES


def _link(doc) -> str:
    deflate = zlib.compressobj(9, zlib.DEFLATED, -15)
    data = deflate.compress(msgpack.packb(doc)) + deflate.flush()
    return base64.urlsafe_b64encode(data).decode()


#: A well-formed compact record of no shots, which the refused ones below alter.
EMPTY = [2, "1", 0, 1, 0, 0, 0, [], b"", [0, 0], None, b"\0" * 8]


def test_the_altered_document_is_well_formed():
    assert decode(_link(EMPTY)).setup == Setup(game="nineball", seed=1)


@pytest.mark.parametrize(
    "text",
    [
        "",
        "not a link!",
        "AAAA",
        _link([3, "1", 0, 1, 0, 0, 0, [], b"", [0, 0], None, b"\0" * 8]),  # another format
        _link([2, "1", 9, 1, 0, 0, 0, [], b"", [0, 0], None, b"\0" * 8]),  # no such game
        _link([2, "1", 0, 1, 0, 0, 0, [5 << 8], b"\0\0", [0, 0], None, b"\0" * 8]),  # cut short
        _link([2, "1", 0, 1, 0, 0, 0, [], b"\0", [0, 0], None, b"\0" * 8]),  # odd digests
        _link([2, "1", 0, 1, 0, 0, 0, [(5 << 8) | 1, 100, 0.5], b"\0\0", [0, 0], None, b"\0" * 8]),
        _link([2, "1", 0, "1", 0, 0, 0, [], b"", [0, 0], None, b"\0" * 8]),  # a string seed
        _link([2, "1", 0, 1, 0.5, 0, 0, [], b"", [0, 0], None, b"\0" * 8]),  # a float gap
        _link([2, "1", 0, 1, 0, 0, 2, [], b"", [0, 0], None, b"\0" * 8]),  # no such breaker
        _link([2, "1", 3, 1, 0, 0, 1, [], b"", [0, 0], None, b"\0" * 8]),  # carom's white
        _link({"inputs": []}),
        _link([*EMPTY[:7], [-1] * 5001, b"\0\0" * 5001, *EMPTY[9:]]),  # too many inputs
        "A" * (1 << 19),
        _link([[[[[]]]]] * 3),
        base64.urlsafe_b64encode(zlib.compress(b"\0" * 10_000_000)[2:-4]).decode(),  # a bomb
    ],
)
def test_what_is_not_a_share_link_is_refused_with_a_code(text):
    with refused(Refusal.MALFORMED):
        decode(text)

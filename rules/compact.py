"""The compact form of a game record, for share links: msgpack of fixed-point integers,
deflated, in base64url.

`pack`/`unpack` give and read the msgpack bytes, `encode`/`decode` the link text. The numbers
are the integers the inputs are canonical in (rules.inputs), so a decoded record is the
record, bit for bit. The msgpack document is one array:

    [FORMAT, engine, game, seed, gap, target, breaker, inputs, digests, scores, winner, digest]

and, for a game at other options than the standard ones, after the digest: the reds (snooker's
number, 15 otherwise), then the table size in feet (pool: 7, 8 or 9), then a set-up position's
flat [ball, x, y, ...] (ball: its index among the game's sorted names, x and y the doubles
they are: a retake's position is where a shot left the balls), each
present only when a later one is or it differs from the standard (so the links of standard
games read as before).

A set-up position alone (no record: a practice position to share) is the array

    [POSITION_FORMAT, game, size, reds, position]

(its x and y in 0.1 mm steps: a player's position is canonical in them), packed, deflated and
encoded the same way (`encode_position`, `decode_position`).

game: index in `Game`. gap: in 1e-7 m. breaker: the player who breaks (0 or 1). inputs: one
flat array of integers (and a string where a name is not one of the table's). digests: the
per-input 16-bit digests as one byte string. digest: the final 8-byte chain link. Each input
in `inputs` starts with a head integer:

- a choice: head = -1 - (index of the option in OPTIONS), nothing follows;
- a shot: head = heading * 256 + flags (heading in 1e-4 degree steps, in [0, 3,600,000)),
  then the speed (mm/s), then the values the flags announce, in the flags' order: elevation
  (0.01 degree), a, b (1e-3 R), place x, y (0.1 mm), call (pocket), nominate (ball), struck
  ball. Elevation, a, b and the struck ball are stored only when they differ from the previous
  shot's (before the first shot: the cue ball "cue", struck level at the centre). A ball or
  pocket is its index among the table's sorted names, or its name.

A shot with heading and speed only takes eight bytes, a choice one, each digest two more; see
bench/records.py.
"""

from __future__ import annotations

import base64
import binascii
import zlib
from typing import Any

import msgpack
from pydantic import ValidationError

from rules.codes import Refusal, RuleError
from rules.game import GAP_STEPS, Setup
from rules.inputs import (
    ELEVATION_STEPS,
    HEADING_STEPS,
    OPTIONS,
    PLACE_STEPS,
    SPEED_STEPS,
    TIP_STEPS,
    Choice,
    PlayerInput,
    Shot,
    Strike,
    fixed,
    heading_steps,
)
from rules.positions import check_position
from rules.racks import REDS_FULL, Game, rack
from rules.record import MAX_INPUTS, GameRecord
from rules.referee import referee
from rules.spots import STANDARD_SIZE, Point

FORMAT = 2
POSITION_FORMAT = 1
#: The standard values of the optional fields after a record's digest, in their order.
EXTRAS = (REDS_FULL, STANDARD_SIZE)
#: Fields of a record's array before them.
RECORD_FIELDS = 12
#: Largest compact record accepted, deflated and inflated (bytes): far above MAX_INPUTS shots.
MAX_INFLATED = 1 << 18

ELEVATION, A, B, PLACE, PUSH_OUT, CALL, NOMINATE, BALL = (1 << k for k in range(8))
FLAGS = 256
GAMES = tuple(Game)


def _names(setup: Setup) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The ball and pocket names a record's inputs may refer to by index."""
    pockets = tuple(sorted(p.name for p in referee(setup.game).TABLE.pockets))
    return tuple(sorted(rack(setup.game, setup.seed, setup.gap))), pockets


def _name(value: str, names: tuple[str, ...]) -> int | str:
    return names.index(value) if value in names else value


#: What a shot's repeated values are compared with before the first shot.
BEFORE = Strike(ball="cue", speed=1.0, heading=0.0)


def _shot_ints(shot: Shot, last: Strike, balls, pockets) -> list[int | str]:
    s = shot.strike
    optional = [
        (ELEVATION, s.elevation != last.elevation, [fixed(s.elevation, ELEVATION_STEPS)]),
        (A, s.a != last.a, [fixed(s.a, TIP_STEPS)]),
        (B, s.b != last.b, [fixed(s.b, TIP_STEPS)]),
        (PLACE, shot.place is not None, [fixed(v, PLACE_STEPS) for v in shot.place or ()]),
        (PUSH_OUT, shot.push_out, []),
        (CALL, shot.call is not None, [_name(shot.call or "", pockets)]),
        (NOMINATE, shot.nominate is not None, [_name(shot.nominate or "", balls)]),
        (BALL, s.ball != last.ball, [_name(s.ball, balls)]),
    ]
    flags, tail = 0, []
    for flag, present, values in optional:
        if present:
            flags |= flag
            tail += values
    return [heading_steps(s.heading) * FLAGS + flags, fixed(s.speed, SPEED_STEPS), *tail]


def _pack_inputs(record: GameRecord) -> list[int | str]:
    balls, pockets = _names(record.setup)
    out: list[int | str] = []
    last = BEFORE
    for action in record.inputs:
        if isinstance(action, Choice):
            out.append(-1 - OPTIONS.index(action.option))
        else:
            out += _shot_ints(action, last, balls, pockets)
            last = action.strike
    return out


def _pack_position(
    position: dict[str, Point], balls: tuple[str, ...], exact: bool = False
) -> list[Any]:
    """[ball, x, y, ...] in the position's order (which the engine's results depend on): x and
    y in 0.1 mm steps (a player's position), or (`exact`: a record's, which may be where a
    shot left the balls) as the doubles they are."""
    flat: list[Any] = []
    for ball, (x, y) in position.items():
        at = [x, y] if exact else [fixed(x, PLACE_STEPS), fixed(y, PLACE_STEPS)]
        flat += [_name(ball, balls), *at]
    return flat


def _unpack_position(flat: Any, balls: tuple[str, ...], exact: bool = False) -> dict[str, Point]:
    if not isinstance(flat, list) or len(flat) % 3 or len(flat) > 3 * len(balls):
        raise ValueError("a position is a flat array of [ball, x, y]")
    reader = _Reader(flat, balls=balls)
    position = {}
    while reader.at < len(flat):
        ball = reader.name(balls)
        if exact:
            x, y = reader.take(), reader.take()
            if type(x) is not float or type(y) is not float:
                raise ValueError("a record's position is in doubles")
            position[ball] = (x, y)
        else:
            position[ball] = (reader.number(PLACE_STEPS), reader.number(PLACE_STEPS))
    return position


def pack(record: GameRecord) -> bytes:
    """The record as msgpack (before compression)."""
    s, f = record.setup, record.final
    digests = b"".join(d.to_bytes(2, "big") for d in record.digests)
    doc = [FORMAT, record.engine, GAMES.index(s.game), s.seed, fixed(s.gap, GAP_STEPS), s.target]
    doc.append(s.breaker)
    doc += [_pack_inputs(record), digests, list(f.scores), f.winner, bytes.fromhex(f.digest)]
    extras: list[Any] = [s.reds, s.size]
    if s.position is not None:
        extras.append(_pack_position(s.position, _names(s)[0], exact=True))
    while len(extras) <= len(EXTRAS) and extras and extras[-1] == EXTRAS[len(extras) - 1]:
        extras.pop()
    return msgpack.packb(doc + extras)


def _to_link(data: bytes) -> str:
    """Raw deflate, base64url without padding."""
    deflate = zlib.compressobj(9, zlib.DEFLATED, -15)
    return base64.urlsafe_b64encode(deflate.compress(data) + deflate.flush()).rstrip(b"=").decode()


def encode(record: GameRecord) -> str:
    """The share-link text: pack, raw deflate, base64url without padding."""
    return _to_link(pack(record))


class _Reader:
    """Reads the flat input integers back into inputs."""

    def __init__(
        self, values: list[Any], setup: Setup | None = None, balls: tuple[str, ...] = ()
    ) -> None:
        self.values, self.at = values, 0
        self.balls, self.pockets = _names(setup) if setup is not None else (balls, ())

    def take(self) -> Any:
        if self.at >= len(self.values):
            raise ValueError("the inputs end inside a shot")
        self.at += 1
        return self.values[self.at - 1]

    def number(self, steps: int) -> float:
        value = self.take()
        if type(value) is not int:
            raise ValueError("a fixed-point value is not an integer")
        return value / steps

    def name(self, names: tuple[str, ...]) -> str:
        value = self.take()
        if type(value) is int and 0 <= value < len(names):
            return names[value]
        if isinstance(value, str):
            return value
        raise ValueError(f"bad name reference {value!r}")

    def inputs(self) -> list[PlayerInput]:
        found: list[PlayerInput] = []
        last = BEFORE
        while self.at < len(self.values):
            if len(found) == MAX_INPUTS:
                raise ValueError(f"more than {MAX_INPUTS} inputs")
            head = self.take()
            if type(head) is not int:
                raise ValueError("an input does not start with an integer")
            if head < 0:
                found.append(Choice(option=OPTIONS[-1 - head]))
                continue
            shot = self.shot(head, last)
            last = shot.strike
            found.append(shot)
        return found

    def shot(self, head: int, last: Strike) -> Shot:
        flags = head % FLAGS
        strike: dict[str, Any] = {
            "heading": head // FLAGS / HEADING_STEPS,
            "speed": self.number(SPEED_STEPS),
        }
        fields: dict[str, Any] = {"push_out": bool(flags & PUSH_OUT)}
        for flag, key, steps in (
            (ELEVATION, "elevation", ELEVATION_STEPS),
            (A, "a", TIP_STEPS),
            (B, "b", TIP_STEPS),
        ):
            strike[key] = self.number(steps) if flags & flag else getattr(last, key)
        if flags & PLACE:
            fields["place"] = (self.number(PLACE_STEPS), self.number(PLACE_STEPS))
        if flags & CALL:
            fields["call"] = self.name(self.pockets)
        if flags & NOMINATE:
            fields["nominate"] = self.name(self.balls)
        strike["ball"] = self.name(self.balls) if flags & BALL else last.ball
        return Shot.model_validate({"strike": strike, **fields})


def unpack(data: bytes) -> GameRecord:
    """A record from its msgpack bytes; raises RuleError (MALFORMED) for anything else."""
    try:
        doc = msgpack.unpackb(data, strict_map_key=True)
        if not isinstance(doc, list) or not RECORD_FIELDS <= len(doc) <= RECORD_FIELDS + 3:
            raise ValueError("not a compact record of this format")
        extras = doc[RECORD_FIELDS:]
        version, engine, game, seed, gap, target, breaker, ints, digests, scores, winner, last = (
            doc[:RECORD_FIELDS]
        )
        if version != FORMAT or type(game) is not int or not 0 <= game < len(GAMES):
            raise ValueError("not a compact record of this format")
        reds, size = (*extras[:2], *EXTRAS[len(extras[:2]) :])
        if not isinstance(digests, bytes) or len(digests) % 2 or not isinstance(last, bytes):
            raise ValueError("bad digests")
        if type(gap) is not int:
            raise ValueError("the gap is not an integer")
        fields = {
            "game": GAMES[game],
            "seed": seed,
            "gap": gap / GAP_STEPS,
            "target": target,
            "breaker": breaker,
            "reds": reds,
            "size": size,
        }
        if len(extras) == len(EXTRAS) + 1:
            names = _names(Setup(**fields))[0]
            fields["position"] = _unpack_position(extras[-1], names, exact=True)
        setup = Setup(**fields)
        if not isinstance(ints, list):
            raise ValueError("inputs must be an array")
        return GameRecord(
            engine=engine,
            setup=setup,
            inputs=_Reader(ints, setup).inputs(),
            digests=[int.from_bytes(digests[k : k + 2], "big") for k in range(0, len(digests), 2)],
            final={"scores": scores, "winner": winner, "digest": last.hex()},
        )
    except ValidationError as exc:
        first = exc.errors()[0]
        raise RuleError(Refusal.MALFORMED, f"compact record: {first['msg']}") from None
    except (ValueError, TypeError, IndexError, msgpack.ExtraData) as exc:
        raise RuleError(Refusal.MALFORMED, f"compact record: {exc}") from None


def _from_link(text: str, what: str) -> bytes:
    """The bytes of a share link's text; RuleError (MALFORMED) for anything else."""
    text = text.strip()
    if len(text) > MAX_INFLATED:
        raise RuleError(Refusal.MALFORMED, f"{what}: too long for a share link")
    try:
        raw = base64.urlsafe_b64decode(text + "=" * (-len(text) % 4))
        inflate = zlib.decompressobj(-15)
        data = inflate.decompress(raw, MAX_INFLATED)
        if inflate.unconsumed_tail or not inflate.eof:
            raise ValueError("too large or truncated")
    except (binascii.Error, zlib.error, ValueError) as exc:
        raise RuleError(Refusal.MALFORMED, f"{what}: not a share link ({exc})") from None
    return data


def decode(text: str) -> GameRecord:
    """A record from its share-link text; raises RuleError (MALFORMED) for anything else."""
    return unpack(_from_link(text, "compact record"))


def encode_position(setup: Setup) -> str:
    """The share-link text of a setup's position (game, size, reds and the balls)."""
    assert setup.position is not None
    balls = _pack_position(setup.position, _names(setup)[0])
    doc = [POSITION_FORMAT, GAMES.index(setup.game), setup.size, setup.reds, balls]
    return _to_link(msgpack.packb(doc))


def decode_position(text: str) -> Setup:
    """The setup (seed 0) of a shared position, checked as any set-up position is; RuleError:
    MALFORMED for a text that is no position link, BAD_POSITION for a position that cannot
    start a rack."""
    data = _from_link(text, "position")
    try:
        doc = msgpack.unpackb(data, strict_map_key=True)
        if not isinstance(doc, list) or len(doc) != 5 or doc[0] != POSITION_FORMAT:
            raise ValueError("not a position link of this format")
        _, game, size, reds, flat = doc
        if type(game) is not int or not 0 <= game < len(GAMES):
            raise ValueError("unknown game")
        bare = Setup(game=GAMES[game], seed=0, size=size, reds=reds)
        balls = _unpack_position(flat, _names(bare)[0])
    except ValidationError as exc:
        raise RuleError(Refusal.MALFORMED, f"position: {exc.errors()[0]['msg']}") from None
    except (ValueError, TypeError, IndexError, msgpack.ExtraData) as exc:
        raise RuleError(Refusal.MALFORMED, f"position: {exc}") from None
    position = check_position(bare.game, balls, bare.size, bare.reds)
    return Setup.model_validate({**bare.model_dump(), "position": position})

"""Validation of published bodies: JSON or msgpack, chosen by Content-Type.

The relay does not know what the game sends, but it refuses what no client could read: bodies
that do not parse, that hold NaN or infinities (not JSON), that are too large, or that nest
arrays and maps deeper than `MAX_DEPTH` (parsers recurse per level: a 60 KB `[[[...]]]` would
exhaust the interpreter's stack, here and in every subscriber). JSON-bodied text transports
(SSE) get msgpack messages converted to JSON text.
"""

from __future__ import annotations

import json
import math
import re
from typing import Any

import msgpack
import msgspec
from pydantic_core import from_json

JSON = "application/json"
MSGPACK = "application/msgpack"
_MSGPACK_ALIASES = {"application/msgpack", "application/x-msgpack", "application/vnd.msgpack"}
ACCEPTED_TYPES = (JSON, MSGPACK)
MAX_DEPTH = 64  # nested arrays/maps a body may hold
_EVENT_NAME = re.compile(r"[A-Za-z0-9_.:-]{1,64}")  # matched whole (see server.relay.ids)

_JSON_STRING = re.compile(rb'"(?:[^"\\]|\\.)*"')
_PAIR = b"[]"
_BRACKETS = bytes.maketrans(b"{}", b"[]")
_NOT_BRACKETS = bytes(byte for byte in range(256) if byte not in b"[]{}")
_JSON_DECODER = msgspec.json.Decoder()


class PayloadError(ValueError):
    """A body the relay refuses; the message says why."""


def media_type(content_type: str | None) -> str:
    """The canonical media type of a Content-Type header (parameters dropped)."""
    if content_type in ACCEPTED_TYPES:
        return content_type  # as almost every publisher sends it: nothing to take apart
    base = (content_type or "").split(";", 1)[0].strip().lower()
    if base in _MSGPACK_ALIASES:
        return MSGPACK
    return base


def _too_deep() -> PayloadError:
    return PayloadError(f"body nests arrays or maps deeper than {MAX_DEPTH} levels")


def _check_json_depth(data: bytes) -> None:
    """Raise if the JSON text nests deeper than MAX_DEPTH, before any parser recurses into it.

    A text with at most MAX_DEPTH opening brackets cannot nest deeper (two counts in C: the
    common case of a small message costs nothing more). Otherwise strings are blanked out (a
    bracket inside a string is not nesting), everything but the brackets is dropped, and
    innermost pairs `[]` are removed one level per pass: brackets left after MAX_DEPTH passes
    nest deeper than that.
    """
    if data.count(b"[") + data.count(b"{") <= MAX_DEPTH:
        return
    skeleton = _JSON_STRING.sub(b"", data).translate(_BRACKETS, delete=_NOT_BRACKETS)
    for _ in range(MAX_DEPTH):
        if _PAIR not in skeleton:
            return  # balanced and shallow enough, or unbalanced: the parser refuses that
        skeleton = skeleton.replace(_PAIR, b"")
    if _PAIR in skeleton:
        raise _too_deep()


def _json_error(data: bytes, error: msgspec.DecodeError) -> PayloadError:
    """Why a body that failed to parse is refused: NaN, infinities and numbers that overflow
    to infinity named as such."""
    if isinstance(error, msgspec.ValidationError):  # msgspec's "Number out of range"
        return PayloadError("JSON body holds a number that overflows to infinity")
    try:
        from_json(data, allow_inf_nan=True)
    except ValueError:
        return PayloadError(f"malformed JSON body: {error}")
    return PayloadError("JSON body holds NaN or Infinity, which is not a number")


def _decode_json(data: bytes) -> Any:
    """The value of a JSON body: well-formed UTF-8 JSON, no NaN or infinities, not too deep.

    msgspec's parser refuses in C everything the relay refuses but the depth: `NaN` and
    `Infinity`, a number that overflows a float, lone surrogate escapes, malformed UTF-8,
    trailing text. On the benchmark's small message it costs 0.4 us where pydantic-core's
    parser, which lets an overflowing number through as infinity, and the regular expression
    that looked for such numbers cost 2.3 us (`bench/relay.py`, docs/operations.md).
    """
    _check_json_depth(data)
    try:
        return _JSON_DECODER.decode(data)
    except msgspec.DecodeError as error:
        raise _json_error(data, error) from None


def _check_msgpack(value: Any, depth: int = 0) -> None:
    """Raise for what JSON could not carry: non-finite floats, bytes, non-string keys, and
    for nesting deeper than MAX_DEPTH."""
    if depth > MAX_DEPTH:
        raise _too_deep()
    if isinstance(value, float) and not math.isfinite(value):
        raise PayloadError("msgpack body holds a NaN or infinite float")
    if isinstance(value, bytes | bytearray | msgpack.ExtType):
        raise PayloadError("msgpack body holds raw bytes or an extension type")
    if isinstance(value, list):
        for item in value:
            _check_msgpack(item, depth + 1)
    elif isinstance(value, dict):
        for key, item in value.items():
            if not isinstance(key, str):
                raise PayloadError("msgpack map keys must be strings")
            _check_msgpack(item, depth + 1)


def decode(data: bytes, content_type: str) -> Any:
    """The value a JSON or msgpack body holds; PayloadError if it is not well-formed."""
    if content_type == JSON:
        return _decode_json(data)
    if content_type == MSGPACK:
        try:
            value = msgpack.unpackb(data, raw=False, strict_map_key=False)
        except msgpack.exceptions.StackError:
            raise _too_deep() from None
        except (msgpack.UnpackException, ValueError) as error:
            raise PayloadError(f"malformed msgpack body: {error}") from None
        _check_msgpack(value)
        return value
    raise PayloadError(
        f"unsupported content type {content_type!r}: send {' or '.join(ACCEPTED_TYPES)}"
    )


def as_text(data: bytes, content_type: str) -> str:
    """The body as text for text-only transports: msgpack becomes JSON."""
    if content_type == MSGPACK:
        return json.dumps(msgpack.unpackb(data, raw=False), separators=(",", ":"))
    return data.decode("utf-8", errors="replace")


class EventNameError(PayloadError):
    """The `X-EventSource-Event` name is not one a client may give."""


def check_message(canonical: str, data: bytes, event: str | None = None) -> None:
    """Raise PayloadError unless the event name and the body (of the canonical type, JSON or
    msgpack) are acceptable.

    A plain function that returns nothing: per publish a pydantic model with validators cost
    about as much as the parse itself, and even a named tuple of what the caller already
    holds cost a fifth of it."""
    if event is not None and _EVENT_NAME.fullmatch(event) is None:
        raise EventNameError(f"event names are 1 to 64 of A-Z a-z 0-9 _ . : -, not {event!r}")
    decode(data, canonical)

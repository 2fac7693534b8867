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
from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

JSON = "application/json"
MSGPACK = "application/msgpack"
_MSGPACK_ALIASES = {"application/msgpack", "application/x-msgpack", "application/vnd.msgpack"}
ACCEPTED_TYPES = (JSON, MSGPACK)
MAX_DEPTH = 64  # nested arrays/maps a body may hold
EVENT_NAME_PATTERN = r"^[A-Za-z0-9_.:-]{1,64}$"

_JSON_STRING = re.compile(rb'"(?:[^"\\]|\\.)*"')
_OPEN, _CLOSE = ord("["), ord("]")
_BRACKETS = bytes.maketrans(b"{}", b"[]")


class PayloadError(ValueError):
    """A body the relay refuses; the message says why."""


def media_type(content_type: str | None) -> str:
    """The canonical media type of a Content-Type header (parameters dropped)."""
    base = (content_type or "").split(";", 1)[0].strip().lower()
    if base in _MSGPACK_ALIASES:
        return MSGPACK
    return base


def _reject_constant(name: str) -> float:
    raise PayloadError(f"JSON body holds {name}, which is not a number")


def _finite_float(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise PayloadError(f"JSON number {text} overflows to infinity")
    return value


def _too_deep() -> PayloadError:
    return PayloadError(f"body nests arrays or maps deeper than {MAX_DEPTH} levels")


def _check_json_depth(data: bytes) -> None:
    """Raise if the JSON text nests deeper than MAX_DEPTH, before any parser recurses into it.

    Strings are blanked out first (a bracket inside a string is not nesting); what is left is
    scanned bracket by bracket, stopping at the first level too deep.
    """
    skeleton = _JSON_STRING.sub(b"", data).translate(_BRACKETS, delete=b'"')
    depth = 0
    for byte in skeleton:
        if byte == _OPEN:
            depth += 1
            if depth > MAX_DEPTH:
                raise _too_deep()
        elif byte == _CLOSE:
            depth -= 1


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
        _check_json_depth(data)
        try:
            return json.loads(
                data.decode("utf-8"), parse_constant=_reject_constant, parse_float=_finite_float
            )
        except (UnicodeDecodeError, json.JSONDecodeError) as error:
            raise PayloadError(f"malformed JSON body: {error}") from None
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


class IncomingMessage(BaseModel):
    """A message a client wants published, validated before anything is stored."""

    model_config = ConfigDict(frozen=True)

    content_type: str
    data: bytes
    event: str | None = Field(
        default=None,
        pattern=EVENT_NAME_PATTERN,
        description="EventSource event name (the publish's `X-EventSource-Event` header)",
    )

    @field_validator("content_type", mode="before")
    @classmethod
    def _canonical_type(cls, value: str) -> str:
        return media_type(value)

    @model_validator(mode="after")
    def _well_formed(self) -> IncomingMessage:
        decode(self.data, self.content_type)
        return self

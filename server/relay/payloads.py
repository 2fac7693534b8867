"""Validation of published bodies: JSON or msgpack, chosen by Content-Type.

The relay does not know what the game sends, but it refuses what no client could read: bodies
that do not parse, that hold NaN or infinities (not JSON), or that are too large. JSON-bodied
text transports (SSE) get msgpack messages converted to JSON text.
"""

from __future__ import annotations

import json
import math
from typing import Any

import msgpack
from pydantic import BaseModel, ConfigDict, field_validator, model_validator

JSON = "application/json"
MSGPACK = "application/msgpack"
_MSGPACK_ALIASES = {"application/msgpack", "application/x-msgpack", "application/vnd.msgpack"}
ACCEPTED_TYPES = (JSON, MSGPACK)


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


def _check_msgpack(value: Any) -> None:
    """Raise for what JSON could not carry: non-finite floats, bytes, non-string keys."""
    if isinstance(value, float) and not math.isfinite(value):
        raise PayloadError("msgpack body holds a NaN or infinite float")
    if isinstance(value, bytes | bytearray | msgpack.ExtType):
        raise PayloadError("msgpack body holds raw bytes or an extension type")
    if isinstance(value, list):
        for item in value:
            _check_msgpack(item)
    elif isinstance(value, dict):
        for key, item in value.items():
            if not isinstance(key, str):
                raise PayloadError("msgpack map keys must be strings")
            _check_msgpack(item)


def decode(data: bytes, content_type: str) -> Any:
    """The value a JSON or msgpack body holds; PayloadError if it is not well-formed."""
    if content_type == JSON:
        try:
            return json.loads(
                data.decode("utf-8"), parse_constant=_reject_constant, parse_float=_finite_float
            )
        except (UnicodeDecodeError, json.JSONDecodeError) as error:
            raise PayloadError(f"malformed JSON body: {error}") from None
    if content_type == MSGPACK:
        try:
            value = msgpack.unpackb(data, raw=False, strict_map_key=False)
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

    @field_validator("content_type", mode="before")
    @classmethod
    def _canonical_type(cls, value: str) -> str:
        return media_type(value)

    @model_validator(mode="after")
    def _well_formed(self) -> IncomingMessage:
        decode(self.data, self.content_type)
        return self

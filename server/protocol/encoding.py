"""JSON of a model some of whose fields are already JSON: each such field written once.

A shot's trajectory is most of its outcome's bytes (an eight-ball break's is some 25 KB of
JSON), and the outcome goes out three ways: published on the table's channel, stored in the
input log and (on Redis) in the table's document. Encoding the same trajectory for each cost
the server 20-170 us a time. So the worker that simulated the shot encodes the trajectory
once, beside its other work, and the server writes those bytes into every document that
holds it, encoding only the small rest.
"""

from __future__ import annotations

from collections.abc import Mapping, Set

from pydantic import BaseModel


def with_encoded(
    model: BaseModel, encoded: Mapping[str, bytes], exclude: Set[str] = frozenset()
) -> bytes:
    """`model`'s JSON, leaving out the fields in `exclude`, with each field named in
    `encoded` written from the JSON given for it (as is: the caller made it from that field's
    value) rather than encoded again. Those fields come last; JSON objects have no order."""
    body = type(model).__pydantic_serializer__.to_json(model, exclude=set(exclude) | set(encoded))
    fields = b",".join(b'"%s":%s' % (name.encode(), value) for name, value in encoded.items())
    if not fields:
        return body
    return body[:-1] + (b"," if body != b"{}" else b"") + fields + b"}"

"""Channel ids and message ids, validated in one place.

Channel ids are what nchan accepts in a URL path segment we care about: letters, digits, `_` and
`-`, 1 to 64 of them. Message ids follow nchan's `<unix seconds>:<tag>` form, where the tag
counts messages published within the same second (0, 1, 2, ...). Ids order by the pair
(seconds, tag) compared as integers, never as strings ("10:0" is after "9:5").

Both kinds of id are matched whole (`re.fullmatch`): a regular expression's `$` also matches
before a trailing newline, and `game1\n` must not pass for `game1`.
"""

from __future__ import annotations

import re
from typing import Annotated

from pydantic import StringConstraints

_CHANNEL = r"[A-Za-z0-9_-]{1,64}"
CHANNEL_PATTERN = f"^{_CHANNEL}$"  # for JSON Schema and pydantic, whose `$` is the very end
ChannelId = Annotated[str, StringConstraints(pattern=CHANNEL_PATTERN)]
_CHANNEL_RE = re.compile(_CHANNEL)
_MESSAGE_ID = r"(\d{1,12}):(\d{1,12})"
MESSAGE_ID_PATTERN = f"^{_MESSAGE_ID}$"
_MESSAGE_ID_RE = re.compile(_MESSAGE_ID)

MessageKey = tuple[int, int]


def is_channel_id(text: str) -> bool:
    """True when `text` is a valid channel id."""
    return _CHANNEL_RE.fullmatch(text) is not None


def parse_message_id(text: str) -> MessageKey:
    """(seconds, tag) of an id like `1700000000:3`; ValueError for anything else."""
    match = _MESSAGE_ID_RE.fullmatch(text)
    if match is None:
        raise ValueError(f"malformed message id {text!r}: expected '<unix seconds>:<tag>'")
    return int(match[1]), int(match[2])


def format_message_id(key: MessageKey) -> str:
    """The wire form of a (seconds, tag) pair."""
    return f"{key[0]}:{key[1]}"

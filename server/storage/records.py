"""What storage writes: versioned documents of the record types it keeps, and their migrations.

Storage keeps the game's own records (`TableRecord` with its `InputEntry`s, a player's
`Rating`, a rack's `ReplayView` and its `BreakEntry`s, `PlayerInfo`), each as one JSON
document that starts with the storage version it was written at: `{"_v": 2, ...}`. Reading a
document of an older version runs it through `MIGRATIONS` first, one version at a time, so a
stored table from before a change still reads as the record it was.

Those record types carry the referee's state and some wire models inside them, so a field
renamed there would change what is stored. That must never happen silently: `fingerprint()`
digests the JSON schema of every type stored, and tests/service/test_records.py holds it
against `FINGERPRINT`. A change that alters it fails that test until its author bumps
`STORAGE_VERSION`, adds the migration from the previous version (the identity when old
documents still read correctly, as for the versions so far, whose tables merely lack fields
that have defaults) and records the new fingerprint.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Mapping, Set
from typing import Any, TypeVar

from pydantic import BaseModel

from server.game.challenge_record import ChallengeRecord
from server.game.history import MatchResult
from server.game.ratings import Rating
from server.game.tables import InputEntry, TableRecord
from server.protocol.encoding import with_encoded
from server.protocol.models import BreakEntry, OutcomeMessage, PlayerInfo, ReplayView

STORAGE_VERSION = 5
#: The digest of the stored types' schemas at `STORAGE_VERSION` (see the module docstring).
FINGERPRINT = "ee9d333f02a2b7b3"
#: The record types storage keeps (and `fingerprint` digests).
STORED: tuple[type[BaseModel], ...] = (
    TableRecord,
    InputEntry,
    OutcomeMessage,
    Rating,
    ReplayView,
    BreakEntry,
    PlayerInfo,
    MatchResult,
    ChallengeRecord,
)

Document = dict[str, Any]
#: MIGRATIONS[v] turns a document of version v, of the given record type, into version v + 1.
MIGRATIONS: dict[int, Callable[[type[BaseModel], Document], Document]] = {
    # 1 -> 2: tables gained `started` (None: presence counts from their creation).
    1: lambda _kind, document: document,
    # 2 -> 3: tables gained how they `ended`, their racks' `replays` (none known before) and
    # the options `reds` and `target` (the defaults they were played with); match results are
    # stored, and challenges; a replay's rack setup may carry snooker's `reds` (15 before).
    2: lambda _kind, document: document,
    # 3 -> 4: tables gained the option `size` (pool's table, 9 ft before), a practice table's
    # set-up `position` and the balls of its last shot (`retake`), none before; a state and a
    # replay's rack setup may carry `size` and (setup) `position`, absent before. Leaderboard
    # answers say which options they rank (not stored).
    3: lambda _kind, document: document,
    # 4 -> 5: match results say whether the table was `private` (False before: profiles list
    # the tables of results stored earlier, as they did).
    4: lambda _kind, document: document,
}

M = TypeVar("M", bound=BaseModel)
_PREFIX = f'{{"_v":{STORAGE_VERSION},'


def dump(
    record: BaseModel,
    encoded: Mapping[str, bytes] | None = None,
    exclude: Set[str] = frozenset(),
) -> str:
    """The document of `record` at the current version, leaving out the fields in `exclude`,
    the fields named in `encoded` written from the JSON given for them (their values' own JSON,
    made once elsewhere: server.protocol.encoding)."""
    return document(with_encoded(record, encoded or {}, exclude).decode())


def document(body: str) -> str:
    """The stored document of a record whose JSON is `body`: it, marked with the current
    version."""
    return _PREFIX + body[1:] if body != "{}" else _PREFIX[:-1] + "}"


def load(kind: type[M], document: str | bytes) -> M:
    """The record a stored document holds, migrated from its version if it is older."""
    text = document.decode() if isinstance(document, bytes) else document
    if text.startswith(_PREFIX):  # the current version: validated straight from the JSON
        return kind.model_validate_json("{" + text[len(_PREFIX) :])
    data = json.loads(text)
    version = data.pop("_v", 1)
    if version > STORAGE_VERSION:
        raise ValueError(f"a {kind.__name__} of storage version {version}: upgrade the server")
    for step in range(version, STORAGE_VERSION):
        data = MIGRATIONS[step](kind, data)
    return kind.model_validate(data)


def fingerprint() -> str:
    """A digest of the JSON schemas of every stored type."""
    schemas = {kind.__name__: kind.model_json_schema() for kind in STORED}
    return hashlib.sha256(json.dumps(schemas, sort_keys=True).encode()).hexdigest()[:16]

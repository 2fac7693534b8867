"""Stored documents: versioned, migrated when old, and never changed silently."""

from __future__ import annotations

import json

import pytest

from server.game.ratings import Rating
from server.game.tables import TableRecord
from server.storage import records
from tests.service.conftest import a_table


def test_a_stored_type_changes_only_with_a_new_storage_version() -> None:
    assert records.fingerprint() == records.FINGERPRINT, (
        "a type storage keeps has changed: bump STORAGE_VERSION, add the migration from the "
        "previous version to MIGRATIONS, and record the new FINGERPRINT (server/storage/records.py)"
    )
    assert set(records.MIGRATIONS) == set(range(1, records.STORAGE_VERSION))


def test_documents_carry_their_version_and_read_back_as_written() -> None:
    table = a_table()
    document = records.dump(table)
    assert json.loads(document)["_v"] == records.STORAGE_VERSION
    assert records.load(TableRecord, document) == table
    assert records.load(Rating, records.dump(Rating()).encode()) == Rating()


def test_a_document_from_before_versions_is_migrated() -> None:
    table = a_table()
    old = json.loads(table.model_dump_json(exclude={"started"}))  # as version 1 wrote it
    assert records.load(TableRecord, json.dumps(old)) == table.model_copy(update={"started": None})


def test_a_document_from_a_newer_server_is_refused() -> None:
    newer = json.dumps(
        {"_v": records.STORAGE_VERSION + 1, **json.loads(Rating().model_dump_json())}
    )
    with pytest.raises(ValueError, match="upgrade the server"):
        records.load(Rating, newer)

"""The token signing key lives in a file only the server's user can read (before: in the
SQLite file's `secrets` table, in a file created 0644)."""

from __future__ import annotations

import os
import sqlite3
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from server.storage.signing_key import KeyFileError, signing_key


def test_a_new_key_file_is_0600_whatever_the_umask(tmp_path: Path) -> None:
    previous = os.umask(0)
    try:
        key = signing_key(tmp_path / "game.key")
    finally:
        os.umask(previous)
    assert stat.S_IMODE((tmp_path / "game.key").stat().st_mode) == 0o600
    assert len(key) == 64 and signing_key(tmp_path / "game.key") == key


@pytest.mark.parametrize("mode", [0o644, 0o640, 0o604, 0o660])
def test_a_key_file_others_can_read_stops_the_start(tmp_path: Path, mode: int) -> None:
    path = tmp_path / "game.key"
    signing_key(path)
    path.chmod(mode)
    with pytest.raises(KeyFileError, match=f"chmod 600 {path}"):
        signing_key(path)


def test_the_key_of_an_older_database_moves_out_of_it(tmp_path: Path) -> None:
    database = tmp_path / "game.sqlite3"
    old = "ab" * 32
    with sqlite3.connect(database) as db:
        db.execute("CREATE TABLE secrets (name TEXT PRIMARY KEY, value TEXT)")
        db.execute("INSERT INTO secrets VALUES ('tokens', ?)", (old,))
    db.close()
    assert signing_key(tmp_path / "game.key", database) == old  # tokens stay valid
    assert old.encode() not in database.read_bytes()
    assert signing_key(tmp_path / "game.key", database) == old


def test_serve_refuses_a_loose_key_file_in_one_line(tmp_path: Path) -> None:
    key = tmp_path / "game.sqlite3.key"  # the default: the database's path + .key
    signing_key(key)
    key.chmod(0o644)
    database = str(tmp_path / "game.sqlite3")
    command = [sys.executable, "-m", "server.cli", "serve", "--db", database, "--port", "0"]
    done = subprocess.run(command, capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 1
    assert done.stderr.strip() == (
        f"token key {key} is readable or writable by others (mode 644): chmod 600 {key}, "
        "and rotate the key if others may have read it"
    )

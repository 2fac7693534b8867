"""The token signing key: a file only the server's user can read.

Whoever has the key can sign a token of any player, or a server token that publishes on
`public-lobby`. It used to live in the SQLite database's `secrets` table, in a file created
with the default 0644: readable by everyone on the machine and copied into every backup of the
data. Now it lives in a file of its own (`billiards serve --key-file`, by default the database
path plus `.key`), created 0600 (whatever the umask: `os.open` with mode 0600 and O_EXCL) and
checked at every start: a key file that its group or others may read or write, or that
another user owns, stops the server with the `chmod`/`chown` that fixes it. A database still
holding the old key gives it to the new file (so players' tokens stay valid) and forgets it.

Rotation: stop the server, delete the key file (or move it away), start again. A new key is
made; every token signed with the old one is refused (401), and clients register again (the
web client does so by itself on 401). Replicas that share Redis get their key from
`BILLIARDS_RELAY_SECRET` instead, rotated by changing it on all of them at once.
"""

from __future__ import annotations

import os
import secrets
import stat
from pathlib import Path

from server.storage.sqlite import take_legacy_token_key

#: Random bytes of a new key (hex in the file: 64 characters).
KEY_BYTES = 32


class KeyFileError(SystemExit):
    """The key file cannot be trusted or read: the message says what to do."""


def check_private(path: Path) -> None:
    """KeyFileError unless `path` is a regular file of this user that nobody else can use."""
    info = path.lstat()
    if not stat.S_ISREG(info.st_mode):
        raise KeyFileError(f"token key {path} is not a regular file")
    if info.st_uid != os.getuid():
        raise KeyFileError(f"token key {path} belongs to another user: chown it to this one")
    if info.st_mode & 0o077:
        mode = stat.S_IMODE(info.st_mode)
        raise KeyFileError(
            f"token key {path} is readable or writable by others (mode {mode:o}): "
            f"chmod 600 {path}, and rotate the key if others may have read it"
        )


def signing_key(path: Path, database: Path | None = None) -> str:
    """The key in `path`, made (0600) on first use, from `database`'s old key if it has one."""
    if path.exists() or path.is_symlink():
        check_private(path)
        key = path.read_text().strip()
        if len(key) < 2 * KEY_BYTES:
            raise KeyFileError(f"token key {path} holds {len(key)} characters, not 64")
        return key
    key = (take_legacy_token_key(database) if database else None) or secrets.token_hex(KEY_BYTES)
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(descriptor, "w") as file:
        file.write(key + "\n")
    return key

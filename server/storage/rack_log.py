"""The played inputs of each table's rack under way, kept in memory by a storage that alone
owns its database (server/storage/sqlite.py), so that a rack's end need not read them back.

A rack's end reads every input of the rack with its outcome (its replay and its breaks are
made from them): from the log, one row per shot, each document parsed again into the models
the server had made when it played the shot. In `bench/match_load.py` (nine-ball racks of
about ten shots) that read was about a twelfth of the server's CPU per shot. So the storage
keeps, per table, the entries it logged in the rack under way, the very models it was given.

Kept only where they are known whole. A table's rack is begun empty when this process
creates the table or stores a record that moves it to another rack (a rack number is used
once: an input is logged under the rack its table was at when it was accepted, and an input
pending blocks every other change, so a new rack has no input logged yet). A rack read whole
from the database is kept from then on. A table whose last record this process does not
know (evicted, or stored before a restart) has nothing kept until its rack is read or
changes; an input logged under another rack than the one kept drops what is kept. The
entries are bounded in all (`limit`), the least recently used tables' dropped first, so
memory stays bounded whatever the racks' lengths.
"""

from __future__ import annotations

from collections import OrderedDict

from server.game.tables import InputEntry


class RackLog:
    """Per table: the rack under way and its played inputs, in the order they were played."""

    def __init__(self, limit: int) -> None:
        self._limit = limit
        self._racks: OrderedDict[str, tuple[int, list[InputEntry]]] = OrderedDict()
        self._size = 0

    def get(self, table_id: str, rack: int) -> list[InputEntry] | None:
        """The inputs played in `rack` of the table, if they are kept (a new list)."""
        kept = self._racks.get(table_id)
        if kept is None or kept[0] != rack:
            return None
        self._racks.move_to_end(table_id)
        return list(kept[1])

    def begin(self, table_id: str, rack: int, played: list[InputEntry] | None = None) -> None:
        """Keep `rack` as the table's rack under way, with the inputs `played` in it so far
        (none: a rack just begun)."""
        self.forget(table_id)
        entries = [] if played is None else list(played)
        self._racks[table_id] = (rack, entries)
        self._size += len(entries)
        self._trim()

    def logged(self, table_id: str, entry: InputEntry) -> None:
        """An input logged as played (its outcome without the motion): kept if its rack is."""
        kept = self._racks.get(table_id)
        if kept is None:
            return
        if kept[0] != entry.rack:
            self.forget(table_id)
            return
        kept[1].append(entry)
        self._size += 1
        self._racks.move_to_end(table_id)
        self._trim()

    def forget(self, table_id: str) -> None:
        kept = self._racks.pop(table_id, None)
        if kept is not None:
            self._size -= len(kept[1])

    def _trim(self) -> None:
        while self._size > self._limit and self._racks:
            _, (_, entries) = self._racks.popitem(last=False)
            self._size -= len(entries)

"""The worker pool: simulation off the event loop, surviving a worker's death."""

from __future__ import annotations

import os
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

import pytest

from server import refereeing
from server.storage.sqlite import SqliteStorage, token_key
from server.workers import WorkerPool


async def test_a_dead_worker_is_replaced_and_the_next_shot_is_played() -> None:
    pool = WorkerPool(1)
    try:
        state = refereeing.new_rack("nineball", 4, 0)
        action = refereeing.bot_input(state, "picker")
        first = await pool.referee(state, action)
        with pytest.raises(BrokenProcessPool):
            await pool._run(os._exit, 1)  # the worker dies mid-call (twice: call and retry)
        again = await pool.referee(state, action)
        assert again.state == first.state  # deterministic, whichever process plays it
        assert again.trajectory == first.trajectory
    finally:
        pool.close()


async def test_the_token_key_lives_in_the_database(tmp_path: Path) -> None:
    path = tmp_path / "game.sqlite3"
    key = token_key(path)
    assert len(key) == 64 and token_key(path) == key
    storage = await SqliteStorage.open(path)  # the same file serves the game
    await storage.close()
    assert token_key(path) == key

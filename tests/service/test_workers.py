"""The worker pool: simulation off the event loop, surviving a worker's death."""

from __future__ import annotations

import asyncio
import os
import time
from concurrent.futures.process import BrokenProcessPool

import pytest

from server.game import refereeing
from server.game.workers import WorkerPool


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


async def test_an_error_in_a_call_is_raised_and_the_worker_goes_on() -> None:
    pool = WorkerPool(1)
    try:
        before = pool._all[0].process.pid
        with pytest.raises(ValueError):
            await pool._run(int, "not a number")
        assert await pool._run(int, "42") == 42
        assert pool._all[0].process.pid == before  # the same worker
    finally:
        pool.close()


async def test_a_call_given_up_does_not_answer_the_next_one() -> None:
    """A cancelled call's late answer must not be taken for the next call's."""
    pool = WorkerPool(1)
    try:
        before = pool._all[0].process.pid
        slow = asyncio.create_task(pool._run(time.sleep, 0.5))
        await asyncio.sleep(0.1)
        slow.cancel()
        with pytest.raises(asyncio.CancelledError):
            await slow
        assert await pool._run(abs, -3) == 3
        assert pool._all[0].process.pid != before  # replaced, not waited for
    finally:
        pool.close()


async def test_calls_beyond_the_workers_wait_their_turn() -> None:
    pool = WorkerPool(2)
    try:
        values = await asyncio.gather(*(pool._run(abs, -n) for n in range(10)))
        assert values == list(range(10))
    finally:
        pool.close()

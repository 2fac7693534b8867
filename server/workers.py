"""The pool of worker processes that simulate and judge shots, off the event loop.

A break takes 10-20 ms of pure-Python physics; on the event loop that would stall the relay and
every other table. The match owners hand each input to this pool and await the result. Workers
are started by a fork server that has already imported the engine and the referees, so a new
worker costs a fork, not an import. A worker that dies breaks a `ProcessPoolExecutor`: the pool
is then rebuilt once and the call retried (the engine is deterministic, so a retry is safe).
"""

from __future__ import annotations

import asyncio
import multiprocessing
import os
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from typing import TypeVar

from server import refereeing, replays
from server.refereeing import GameRecord, PlayerInput, State

T = TypeVar("T")


def default_workers() -> int:
    """One worker per core the process may use."""
    return max(1, len(os.sched_getaffinity(0)))


def _context() -> multiprocessing.context.BaseContext:
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["server.refereeing", "server.replays"])
    return context


class WorkerPool:
    """The rules' work in worker processes: `await pool.referee(state, action)`,
    `await pool.bot_input(state, bot)`, and the rest below."""

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self._executor = self._start()

    def _start(self) -> ProcessPoolExecutor:
        return ProcessPoolExecutor(max_workers=self.workers, mp_context=_context())

    async def _run(self, function: Callable[..., T], *args: object) -> T:
        loop = asyncio.get_running_loop()
        try:
            return await loop.run_in_executor(self._executor, function, *args)
        except BrokenProcessPool:
            self._executor.shutdown(wait=False, cancel_futures=True)
            self._executor = self._start()
            return await loop.run_in_executor(self._executor, function, *args)

    async def referee(self, state: State, action: PlayerInput) -> refereeing.Refereed:
        return await self._run(refereeing.referee, state, action)

    async def bot_input(self, state: State, bot: str) -> PlayerInput:
        return await self._run(refereeing.bot_input, state, bot)

    async def verify(self, record_json: bytes) -> refereeing.Verified:
        return await self._run(refereeing.verify, record_json)

    async def replay_shots(self, replay_id: str, record: GameRecord) -> bytes:
        return await self._run(replays.shots_json, replay_id, record)

    def close(self) -> None:
        self._executor.shutdown(wait=True, cancel_futures=True)

"""The pool of worker processes that simulate and judge shots, off the event loop.

A break takes 10-20 ms of physics; on the event loop that would stall the relay and every other
table. The table actors hand each input to this pool and await the result, and so each rack's
archive (its record's chain of hashed states and its best breaks' keys: half a millisecond a
nine-ball rack, several for a long snooker frame).

Each worker is a process with one Unix socket to the server, which the event loop reads and
writes itself (asyncio streams): a call is one pickled `(function, args)` frame out and one
pickled result frame back, with no thread in between. (`ProcessPoolExecutor`, used before,
moves every call through a manager thread and a queue-feeder thread, four thread wake-ups a
call: measured here, 1.0-1.5 ms of the server's CPU per sequential call against 0.6-0.9 ms
with this pool, on top of the worker's own.) A worker runs one call at a time; calls queue
for the next idle worker.

Workers are started, all at once when the pool is made, by a fork server that has already
imported the engine and the referees, so a worker costs a fork, not an import, and the first
shot waits for nothing. A worker that dies mid-call (its socket ends) is replaced and the call
retried once on the new worker (the engine is deterministic, so a retry is safe); a second
death raises `BrokenProcessPool`. A call whose caller is cancelled takes its worker with it
(the worker is replaced): its late answer must not be read as the next call's.
"""

from __future__ import annotations

import asyncio
import multiprocessing
import os
import pickle
import socket
import struct
from collections.abc import Callable
from concurrent.futures.process import BrokenProcessPool
from typing import Any, TypeVar

from server.game import refereeing, replays
from server.game.refereeing import GameRecord, PlayerInput, State

T = TypeVar("T")

#: A frame's header: the length of the pickled payload that follows.
_HEADER = struct.Struct("!Q")


def default_workers() -> int:
    """One worker per core the process may use."""
    return max(1, len(os.sched_getaffinity(0)))


def _context() -> multiprocessing.context.BaseContext:
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(
        ["server.game.refereeing", "server.game.replays", "server.game.workers"]
    )
    return context


def _receive(sock: socket.socket) -> bytes | None:
    """One frame's payload from a blocking socket; None at its end."""
    header = b""
    while len(header) < _HEADER.size:
        chunk = sock.recv(_HEADER.size - len(header))
        if not chunk:
            return None
        header += chunk
    (size,) = _HEADER.unpack(header)
    payload = bytearray()
    while len(payload) < size:
        chunk = sock.recv(min(size - len(payload), 1 << 20))
        if not chunk:
            return None
        payload += chunk
    return bytes(payload)


def _serve(sock: socket.socket, nice: int) -> None:
    """A worker's life: answer each call on `sock` until the server closes it (at the
    scheduling priority `nice` lower than the server's)."""
    if nice:
        os.nice(nice)
    while (frame := _receive(sock)) is not None:
        function, args = pickle.loads(frame)
        try:
            answer = pickle.dumps((True, function(*args)))
        except Exception as error:
            try:
                answer = pickle.dumps((False, error))
            except Exception:  # an exception that does not pickle: its text does
                answer = pickle.dumps((False, RuntimeError(f"{type(error).__name__}: {error}")))
        try:
            sock.sendall(_HEADER.pack(len(answer)) + answer)
        except OSError:  # the server closed its end (shutdown, or it gave up on this call)
            return


class _Worker:
    """One worker process and the event loop's end of its socket."""

    def __init__(self, context: multiprocessing.context.BaseContext, nice: int = 0) -> None:
        mine, theirs = socket.socketpair()
        self.process = context.Process(target=_serve, args=(theirs, nice), daemon=True)
        self.process.start()
        theirs.close()
        self._socket = mine
        self._streams: tuple[asyncio.StreamReader, asyncio.StreamWriter] | None = None

    async def call(self, function: Callable[..., T], args: tuple[object, ...]) -> T:
        """The function's result in the worker; its exception re-raised here;
        BrokenProcessPool if the worker died."""
        if self._streams is None:
            self._streams = await asyncio.open_unix_connection(sock=self._socket)
        reader, writer = self._streams
        payload = pickle.dumps((function, args))
        try:
            writer.write(_HEADER.pack(len(payload)) + payload)
            await writer.drain()
            (size,) = _HEADER.unpack(await reader.readexactly(_HEADER.size))
            ok, value = pickle.loads(await reader.readexactly(size))
        except (asyncio.IncompleteReadError, ConnectionError) as error:
            raise BrokenProcessPool("a worker process died mid-call") from error
        if not ok:
            raise value
        return value

    def stop(self, wait: float) -> None:
        """Close its socket (an idle worker then ends) and reap it, killed if it is still
        running after `wait` seconds."""
        if self._streams is not None:
            self._streams[1].close()
        self._socket.close()
        self.process.join(timeout=wait)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()


class WorkerPool:
    """The rules' work in worker processes: `await pool.referee(state, action)`,
    `await pool.bot_input(state, bot)`, and the rest below. `nice`: how much lower than the
    server the workers are scheduled (the background pool's, for work nobody waits on at a
    table: claims and replays, so that they take no CPU the matches' shots want)."""

    def __init__(self, workers: int, nice: int = 0) -> None:
        self.workers = workers
        self._nice = nice
        self._context = _context()
        self._all = [_Worker(self._context, nice) for _ in range(workers)]
        self._idle: asyncio.Queue[_Worker] | None = None

    def _queue(self) -> asyncio.Queue[_Worker]:
        if self._idle is None:  # made on first use, inside the event loop
            self._idle = asyncio.Queue()
            for worker in self._all:
                self._idle.put_nowait(worker)
        return self._idle

    def _replace(self, worker: _Worker) -> _Worker:
        worker.stop(wait=0)  # dead already, or busy with a call nobody awaits any more
        fresh = _Worker(self._context, self._nice)
        self._all[self._all.index(worker)] = fresh
        return fresh

    async def _run(self, function: Callable[..., Any], *args: object) -> Any:
        idle = self._queue()
        worker = await idle.get()
        try:
            try:
                return await worker.call(function, args)
            except BrokenProcessPool:
                worker = self._replace(worker)
                return await worker.call(function, args)
        except BaseException as error:
            if isinstance(error, BrokenProcessPool | asyncio.CancelledError):
                worker = self._replace(worker)
            raise
        finally:
            idle.put_nowait(worker)

    async def referee(self, state: State, action: PlayerInput) -> refereeing.Refereed:
        return await self._run(refereeing.referee_for_table, state, action)

    async def rack_archive(
        self, setup: refereeing.Setup, played: list[tuple[PlayerInput, State]]
    ) -> refereeing.RackArchive:
        return await self._run(refereeing.rack_archive, setup, played)

    async def bot_input(self, state: State, bot: str) -> PlayerInput:
        return await self._run(refereeing.bot_input, state, bot)

    async def verify(self, record_json: bytes) -> refereeing.Verified:
        return await self._run(refereeing.verify, record_json)

    async def replay_shots(
        self, replay_id: str, record: GameRecord, first: int, count: int
    ) -> list[bytes]:
        return await self._run(replays.shots_pages, replay_id, record, first, count)

    async def diagram(self, function: Callable[..., bytes], args: tuple[object, ...]) -> bytes:
        """A diagrams page's answer, computed and encoded in the worker (server/game/diagrams)."""
        return await self._run(function, *args)

    def close(self) -> None:
        for worker in self._all:
            worker.stop(wait=5)

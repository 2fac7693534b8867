"""The diagrams page's heavier physics, computed in the background worker and bounded per client.

The shot families (physics.diagram_families: some forty shots each, a few hundred ms) and the
recorded real shots (physics.real_shots: a shipped fit drawn, or a refit of up to
`MAX_REFIT_SIMULATIONS` simulations) are too much for the event loop. Their guarantees, as
replays' (server/game/replays.py):

1. Nothing is computed on the event loop: each answer is computed and encoded in the
   background worker (`WorkerPool.diagram`), at most `MAX_RUNNING` at once per process; a
   request for another one past that is refused (429 `rate_limited`), while one for an answer
   being computed waits for that computation.
2. Computing costs the asker: each client address may have at most `DIAGRAM_SECONDS` of worker
   time per minute spent on answers it asked for and that were not kept (429 with the wait
   once spent, before any work); a kept answer costs nothing.
3. Answers that depend only on their query (families, a shipped fit drawn) are kept in a
   least-recently-used cache of at most `CACHE_BYTES` bytes; refits are not (a refit stopped
   by its CPU bound depends on the machine).
4. One refit does at most `MAX_REFIT_SIMULATIONS` simulations and `MAX_REFIT_SECONDS` of CPU,
   whatever it asks for (physics.real_shots.Bound).
"""

from __future__ import annotations

import asyncio
import itertools
import json
from collections import OrderedDict
from collections.abc import Callable
from functools import cache
from typing import TYPE_CHECKING, Any

from physics import ENGINE_VERSION
from physics.real_shots import Bound, Refit, fits, refit
from server.game.budget import WorkBudget
from server.protocol.errors import ErrorCode, ServiceError
from server.protocol.real_shots import (
    MAX_REFIT_SECONDS,
    MAX_REFIT_SIMULATIONS,
    RealModels,
    RealShotEntry,
    RealShotFit,
    RealShotFitRequest,
    RealShotList,
    RealStrike,
)

if TYPE_CHECKING:
    from server.game.workers import WorkerPool

#: Answers being computed at once per process (the background worker does one at a time, the
#: others queue): a page loading, a refit and another visitor's page.
MAX_RUNNING = 4
#: Seconds of worker time per minute one client address may spend on the diagrams.
DIAGRAM_SECONDS = 20.0
#: Bytes of answers kept per process (a family's answer is some 100 KB).
CACHE_BYTES = 16 * 1024 * 1024
#: Where the shipped recordings come from, in the list's words (physics/data/README.md).
SOURCE = (
    "91 three-cushion shots recorded on a real carom table (tracked ball positions), "
    "published with the open-source tailuge/billiards project; fitted with the default "
    "constants and models by bench/real_shots.py"
)


def encoded(function: Callable[..., Any], args: tuple[Any, ...]) -> bytes:
    """`function(*args)` as JSON bytes (run in the worker, which also encodes it)."""
    return json.dumps(function(*args), separators=(",", ":")).encode()


def _track(rows) -> list[tuple[float, float, float]]:
    return [(round(t, 3), round(x, 4), round(y, 4)) for t, x, y in rows.tolist()]


def real_shot_json(shot_id: int, request: RealShotFitRequest, refine: bool) -> bytes:
    """A `RealShotFit` of one shot as JSON (run in the worker)."""
    bound = Bound(min(request.simulations, MAX_REFIT_SIMULATIONS), MAX_REFIT_SECONDS)
    strike = None if request.strike is None else request.strike.model_dump()
    models = request.models.model_dump()
    r: Refit = refit(shot_id, strike, models, bound, refine)
    return (
        RealShotFit(
            id=r.id,
            cue=r.cue,
            strike=RealStrike(**r.strike),
            models=request.models,
            rmse_cm=r.rmse_cm,
            rmse_all_cm=r.rmse_all_cm,
            simulations=r.simulations,
            seconds=r.seconds,
            stopped=r.stopped,
            recorded={k: _track(v) for k, v in r.recorded.items()},
            simulated={k: _track(v) for k, v in r.simulated.items()},
        )
        .model_dump_json()
        .encode()
    )


@cache
def real_shot_list() -> RealShotList:
    """The shipped shots and their fits' figures, from the fits' file alone (the server
    process never loads the recordings: the worker does)."""
    shipped = fits()
    return RealShotList(
        shots=[
            RealShotEntry(**{k: s[k] for k in RealShotEntry.model_fields}) for s in shipped["shots"]
        ],
        median_rmse_cm=shipped["median_rmse_cm"],
        engine_version=shipped["engine_version"],
        source=SOURCE,
    )


class DiagramWork:
    """`await work.answer(key, function, args, asker, keep)`: the JSON of `function(*args)`,
    computed in the background worker under the guarantees above."""

    def __init__(self, pool: WorkerPool) -> None:
        self._pool = pool
        self._kept: OrderedDict[str, bytes] = OrderedDict()
        self._kept_bytes = 0
        self._running: dict[str, asyncio.Task[bytes]] = {}
        self.budget = WorkBudget(DIAGRAM_SECONDS, "your diagrams")
        self._refits = itertools.count()

    def _keep(self, key: str, data: bytes) -> None:
        if len(data) > CACHE_BYTES:
            return
        self._kept[key] = data
        self._kept_bytes += len(data)
        while self._kept_bytes > CACHE_BYTES:
            self._kept_bytes -= len(self._kept.popitem(last=False)[1])

    async def _compute(
        self, key: str, function: Callable[..., bytes], args: tuple, asker: str, keep: bool
    ) -> bytes:
        began = self.budget.clock()
        try:
            data = await self._pool.diagram(function, args)
        finally:
            del self._running[key]
            self.budget.charge(self.budget.clock() - began, asker)
        if keep:
            self._keep(key, data)
        return data

    async def answer(
        self, key: str, function: Callable[..., bytes], args: tuple, asker: str, keep: bool
    ) -> bytes:
        if key not in self._running:
            if (kept := self._kept.get(key)) is not None:
                self._kept.move_to_end(key)
                return kept
            self.budget.check(asker)
            if len(self._running) >= MAX_RUNNING:
                raise ServiceError(ErrorCode.RATE_LIMITED, "diagrams are being computed")
            task = asyncio.ensure_future(self._compute(key, function, args, asker, keep))
            self._running[key] = task
        # Shielded: a client that goes away does not cancel the others' computation.
        return await asyncio.shield(self._running[key])

    async def real_shot(
        self, shot_id: int, request: RealShotFitRequest, refine: bool, asker: str
    ) -> bytes:
        """A shot's fit drawn (the shipped one: kept) or refitted (not kept)."""
        if shot_id not in {s.id for s in real_shot_list().shots}:
            raise ServiceError(ErrorCode.NOT_FOUND, f"no recorded shot {shot_id}")
        if refine:  # each refit its own computation, never shared or kept
            key = f"refit:{next(self._refits)}"
        else:
            key = f"shot:{ENGINE_VERSION}:{shot_id}:{request.model_dump_json()}"
        return await self.answer(key, real_shot_json, (shot_id, request, refine), asker, not refine)


#: The shipped fit drawn: a request with the default models and no strike of its own.
SHIPPED = RealShotFitRequest(simulations=1, models=RealModels())

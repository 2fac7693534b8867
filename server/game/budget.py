"""Seconds of worker time per holder: the bound on what one player or address can make the
server compute for it (claims replayed, replays' shots computed).

A request rate alone does not bound work: one claim of a long record costs a worker a second
or more, one of a short record milliseconds. So each holder has a bucket of worker seconds
(`seconds` per minute, at most `seconds` at once). A request is refused before any work while
its holder's bucket is empty, and the work it did is charged after it ran (its wall time on
the worker, queueing included: the holder pays for what it kept the worker from doing). A
holder can therefore spend at most `seconds` per minute plus the one request that emptied its
bucket.
"""

from __future__ import annotations

import time
from collections.abc import Callable

from server.protocol.errors import ErrorCode, ServiceError

#: Buckets kept before full ones are forgotten (a full bucket holds no information).
KEPT = 100_000


class WorkBudget:
    def __init__(
        self, seconds: float, what: str, clock: Callable[[], float] = time.monotonic
    ) -> None:
        self.seconds = seconds
        self._what = what
        #: The clock that refills buckets, and that callers time their work with.
        self.clock = clock
        self._buckets: dict[str, tuple[float, float]] = {}  # holder -> (seconds left, at)

    def _left(self, holder: str, now: float) -> float:
        left, then = self._buckets.get(holder, (self.seconds, now))
        return min(self.seconds, left + (now - then) * self.seconds / 60.0)

    def check(self, *holders: str) -> None:
        """RATE_LIMITED (with the wait) if any of `holders` has spent its worker time."""
        now = self.clock()
        for holder in holders:
            left = self._left(holder, now)
            if left <= 0:
                wait = -left * 60.0 / self.seconds + 1.0
                raise ServiceError(
                    ErrorCode.RATE_LIMITED,
                    f"{self._what} used this minute's worker time: retry in {wait:.0f} s",
                )

    def charge(self, seconds: float, *holders: str) -> None:
        """Take `seconds` of worker time from each of `holders` (it may go below zero)."""
        now = self.clock()
        for holder in holders:
            self._buckets[holder] = (self._left(holder, now) - seconds, now)
        if len(self._buckets) > KEPT:
            self._buckets = {
                holder: (left, then)
                for holder, (left, then) in self._buckets.items()
                if self._left(holder, now) < self.seconds
            }

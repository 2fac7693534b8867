"""Publish rate limiting: a token bucket per publisher (the token's subject).

Checked before a body is read, so an over-rate publish changes nothing. The clock is
injectable (monotonic seconds) so that tests need not sleep.
"""

from __future__ import annotations

import time
from collections.abc import Callable


class RateLimiter:
    """`rate` publishes per second on average, up to `burst` at once, per key."""

    def __init__(
        self, rate: float, burst: int, clock: Callable[[], float] = time.monotonic
    ) -> None:
        self.rate = rate
        self.burst = burst
        self._full = float(burst)  # a full bucket's tokens
        self._clock = clock
        self._buckets: dict[str, tuple[float, float]] = {}  # key -> (tokens, time)

    def allow(self, key: str) -> float:
        """Take one publish for `key`: 0.0 if allowed, else the seconds to wait."""
        now = self._clock()
        bucket = self._buckets.get(key)
        full = self._full
        if bucket is None:
            tokens = full
        else:
            tokens = bucket[0] + (now - bucket[1]) * self.rate
            if tokens > full:
                tokens = full
        if tokens < 1.0:
            self._buckets[key] = (tokens, now)
            return (1.0 - tokens) / self.rate
        self._buckets[key] = (tokens - 1.0, now)
        if len(self._buckets) > 100_000:
            self._forget_full(now)
        return 0.0

    def _forget_full(self, now: float) -> None:
        """Drop buckets that have refilled: they hold no information."""
        full = [
            key
            for key, (tokens, then) in self._buckets.items()
            if tokens + (now - then) * self.rate >= self.burst
        ]
        for key in full:
            del self._buckets[key]

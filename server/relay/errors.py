"""The error types the transports turn into an HTTP status or a WebSocket close."""

from __future__ import annotations


class RelayError(Exception):
    """A request the relay refuses, with the HTTP status that says why (nothing was changed)."""

    def __init__(self, status: int, reason: str) -> None:
        super().__init__(reason)
        self.status = status
        self.reason = reason


class Unavailable(RelayError):
    """The backend's store cannot be reached: 503, and when to try again (`Retry-After`).

    Nothing was stored, so a publisher may safely send the same message again after
    `retry_after` seconds.
    """

    def __init__(self, reason: str, retry_after: int = 1) -> None:
        super().__init__(503, reason)
        self.retry_after = retry_after

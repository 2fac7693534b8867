"""The one error type the transports turn into an HTTP status or a WebSocket close."""

from __future__ import annotations


class RelayError(Exception):
    """A request the relay refuses, with the HTTP status that says why (nothing was changed)."""

    def __init__(self, status: int, reason: str) -> None:
        super().__init__(reason)
        self.status = status
        self.reason = reason

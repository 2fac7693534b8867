"""The game service's refusals: one exception, one enum of codes, one HTTP status per code.

Every refusal reaches the client as `ApiError {code, reason, rule}` JSON (docs/protocol.md,
Errors) and changes nothing. Clients branch on `code`; `reason` is for people.
"""

from __future__ import annotations

from enum import StrEnum


class ErrorCode(StrEnum):
    BAD_REQUEST = "bad_request"
    BODY_TOO_LARGE = "body_too_large"
    UNSUPPORTED_MEDIA_TYPE = "unsupported_media_type"
    UNAUTHORIZED = "unauthorized"
    FORBIDDEN = "forbidden"
    NOT_FOUND = "not_found"
    NAME_TAKEN = "name_taken"
    TABLE_FULL = "table_full"
    ALREADY_SEATED = "already_seated"
    NOT_YOUR_TURN = "not_your_turn"
    STALE_VERSION = "stale_version"
    WRONG_PHASE = "wrong_phase"
    ILLEGAL_INPUT = "illegal_input"
    CLAIM_MISMATCH = "claim_mismatch"
    BAD_POSITION = "bad_position"
    SET_UP_POSITION = "set_up_position"
    DUPLICATE = "duplicate"
    TOO_MANY_TABLES = "too_many_tables"
    RATE_LIMITED = "rate_limited"
    REQUEST_TIMEOUT = "request_timeout"
    UNAVAILABLE = "unavailable"


STATUS: dict[ErrorCode, int] = {
    ErrorCode.BAD_REQUEST: 400,
    ErrorCode.BODY_TOO_LARGE: 413,
    ErrorCode.UNSUPPORTED_MEDIA_TYPE: 415,
    ErrorCode.UNAUTHORIZED: 401,
    ErrorCode.FORBIDDEN: 403,
    ErrorCode.NOT_FOUND: 404,
    ErrorCode.NAME_TAKEN: 409,
    ErrorCode.TABLE_FULL: 409,
    ErrorCode.ALREADY_SEATED: 409,
    ErrorCode.NOT_YOUR_TURN: 409,
    ErrorCode.STALE_VERSION: 409,
    ErrorCode.WRONG_PHASE: 409,
    ErrorCode.ILLEGAL_INPUT: 422,
    ErrorCode.CLAIM_MISMATCH: 422,
    ErrorCode.BAD_POSITION: 422,
    ErrorCode.SET_UP_POSITION: 422,
    ErrorCode.DUPLICATE: 409,
    ErrorCode.TOO_MANY_TABLES: 409,
    ErrorCode.RATE_LIMITED: 429,
    ErrorCode.REQUEST_TIMEOUT: 408,
    ErrorCode.UNAVAILABLE: 503,
}


class ServiceError(Exception):
    """A request the game service refuses; nothing was changed.

    rule: the referee's own code for an ILLEGAL_INPUT, when the rules give one.
    """

    def __init__(self, code: ErrorCode, reason: str, rule: str | None = None) -> None:
        super().__init__(reason)
        self.code = code
        self.reason = reason
        self.rule = rule

    @property
    def status(self) -> int:
        return STATUS[self.code]

"""Bad requests are the client's error: one log line each, never the server's traceback.

aiohttp logs a request it cannot parse (a bad method, header or version: `BadHttpMessage`)
with the parser's traceback, a dozen lines per connection anyone can open. `OneLineBadRequests`
rewrites those records, on the `aiohttp.server` logger, into one line that says who sent what;
every other record (a real server error) keeps its traceback.
"""

from __future__ import annotations

import logging

from aiohttp.http_exceptions import HttpProcessingError

LOGGER = "aiohttp.server"


class OneLineBadRequests(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        error = record.exc_info[1] if record.exc_info else None
        if isinstance(error, HttpProcessingError):
            reason = " ".join(str(error.message).split())[:200]
            record.msg = f"{record.getMessage()}: bad request ({error.code}): {reason}"
            record.args = ()
            record.exc_info = None
            record.exc_text = None
        return True


def one_line_bad_requests() -> None:
    """Install the filter (once per process; creating several apps installs it once)."""
    logger = logging.getLogger(LOGGER)
    if not any(isinstance(f, OneLineBadRequests) for f in logger.filters):
        logger.addFilter(OneLineBadRequests())

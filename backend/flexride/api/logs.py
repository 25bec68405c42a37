"""The service's log: one format, and no raw control character from a request in it.

A request can put any byte into its path, query or body (``%00``, ``%1b[31m``, ``%0a`` that
would forge a log line); what the service logs of a request is its method and its path
percent-encoded (:func:`request_line`, as uvicorn's access log writes it), and the formatter
of the service's handler escapes whatever control character still reaches a message
(:class:`SafeFormatter`), so a log line is one line of printable text.
"""

from __future__ import annotations

import logging
from urllib.parse import quote

from starlette.requests import Request

FORMAT = "%(asctime)s %(levelname)s %(name)s: %(message)s"
"""Format of the service's log lines."""

_CONTROL = {c: f"\\x{c:02x}" for c in (*range(0x20), *range(0x7F, 0xA0))
            if chr(c) not in "\n\t"}
"""C0 and C1 control characters (but newline and tab, which tracebacks need) → ``\\xNN``."""


def escape_controls(text: str) -> str:
    r"""``text`` with its control characters (but newline and tab) written as ``\xNN``.

    Examples
    --------
    >>> escape_controls("GET /jobs/\x00\x1b[31m")
    'GET /jobs/\\x00\\x1b[31m'
    """
    return text.translate(_CONTROL)


class SafeFormatter(logging.Formatter):
    """A formatter whose messages carry no raw control character (newlines in a message
    are escaped too; a traceback keeps its lines).
    """

    def formatMessage(self, record: logging.LogRecord) -> str:
        """The message part, with control characters (newlines included) escaped."""
        record.message = escape_controls(record.message).replace("\n", "\\n")
        return super().formatMessage(record)

    def formatException(self, ei) -> str:
        """The traceback, with control characters other than newlines escaped."""
        return escape_controls(super().formatException(ei))


def configure_logging(level: str) -> None:
    """Log to standard error through :class:`SafeFormatter` at ``level``, unless logging is
    already set up (a host application's configuration is left alone).
    """
    root = logging.getLogger()
    if root.handlers:
        return
    handler = logging.StreamHandler()
    handler.setFormatter(SafeFormatter(FORMAT))
    root.addHandler(handler)
    root.setLevel(level.upper())


def request_line(request: Request) -> str:
    """``METHOD /percent-encoded/path`` of a request, for a log line."""
    path = request.scope.get("root_path", "") + request.scope.get("path", "")
    return f"{request.method} {quote(path, safe='/:@!$&()*+,;=-._~')}"

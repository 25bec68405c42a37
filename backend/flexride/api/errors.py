"""Errors of the API and their JSON responses.

* :class:`~flexride.errors.StabilityError` → 422 naming ``solver.dt`` with a step that works;
* other :class:`~flexride.errors.FlexrideError` (invalid scenario, unknown preset, analysis
  input) → 422 with one item per located problem of the error (``loc`` = field path, ``msg``
  with the allowed range), no text parsed back;
* request validation → 422 in the same shape (``loc`` = ``["query", name]`` etc., ``msg`` with the
  violated bound as ``(allowed: ≤ 500)``); :class:`NotFound` → 404; :class:`Conflict` → 409;
* storage faults (:class:`~flexride.errors.StorageError`, a database error whose code means it
  cannot take writes now — read-only, no privilege, full, connection lost, busy after
  retries —, a read-only or full disk) → 503 ``storage unavailable: <reason>`` with
  ``Retry-After``, the reason without server paths (:mod:`flexride.store.probe`), one line
  in the log;
* a body that stopped coming (the client went, or the server's time limit closed the
  connection) → 400, which nobody reads, and nothing in the log;
* anything else → 500 with a JSON body (and the traceback in the log).

Responses are JSON without NaN (non-finite numbers become null).
"""

from __future__ import annotations

import json
import logging
import math
import time
from typing import Any

from fastapi import FastAPI, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from sqlalchemy.exc import SQLAlchemyError
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.requests import ClientDisconnect

from flexride.api.logs import request_line
from flexride.errors import (
    ErrorItem,
    FlexrideError,
    ResultsFileError,
    StabilityError,
    StorageError,
)
from flexride.scenario.scenario import allowed_range
from flexride.store.probe import db_fault, is_storage_oserror, os_fault

log = logging.getLogger(__name__)

RETRY_AFTER_S = 30
"""``Retry-After`` of a 503 for a storage fault (s)."""


class NotFound(Exception):
    """A job, study, preset or file that does not exist (404)."""


class Conflict(Exception):
    """The resource exists but is not in a state that allows the request (409)."""


def _finite(obj: Any) -> Any:
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_finite(v) for v in obj]
    return obj


class SafeJSONResponse(JSONResponse):
    """JSON response that writes non-finite floats as null instead of failing."""

    def render(self, content: Any) -> bytes:
        """JSON of ``content`` with non-finite floats written as null."""
        try:
            text = json.dumps(content, ensure_ascii=False, allow_nan=False,
                              separators=(",", ":"))
        except ValueError:
            text = json.dumps(_finite(content), ensure_ascii=False, allow_nan=False,
                              separators=(",", ":"))
        return text.encode("utf-8")


def _error(status: int, detail: Any, message: str | None = None, **extra: Any) -> JSONResponse:
    body = {"detail": detail, "message": message, **extra}
    return SafeJSONResponse(status_code=status, content=body)


def recent_storage_fault(app: FastAPI) -> str | None:
    """The reason of a write that failed within ``STORAGE_FAULT_MEMORY_S``, if any."""
    fault = getattr(app.state, "storage_fault", None)
    if fault is None or time.monotonic() - fault[0] > STORAGE_FAULT_MEMORY_S:
        return None
    return f"a write failed {time.monotonic() - fault[0]:.0f} s ago: {fault[1]}"


async def _flexride_error(request: Request, exc: Exception) -> JSONResponse:
    if isinstance(exc, StorageError):
        return _unavailable(request, str(exc))
    if isinstance(exc, StabilityError):
        item = {"loc": ["scenario", "solver", "dt"], "msg": str(exc), "type": "stability",
                "ctx": {"dt": exc.dt, "dt_max": exc.dt_max, "dt_suggested": exc.dt_suggested}}
        return _error(422, [item], str(exc), dt_suggested=exc.dt_suggested)
    if isinstance(exc, ResultsFileError):
        return _error(404, str(exc), str(exc))
    kind = type(exc).__name__
    located = getattr(exc, "items", ()) or [ErrorItem((), str(exc))]
    items = [{"loc": list(it.loc), "msg": it.msg, "type": kind} for it in located]
    return _error(422, items, str(exc))


async def _validation_error(_request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, RequestValidationError)
    items = []
    parts: list[str] = []
    for err in exc.errors():
        ctx = err.get("ctx")
        loc = [p if isinstance(p, int) else str(p) for p in err.get("loc", ())]
        msg = str(err.get("msg", "")) + allowed_range(ctx)
        items.append({
            "loc": loc,
            "msg": msg,
            "type": str(err.get("type", "validation")),
            "ctx": {k: v if isinstance(v, int | float | str | bool) or v is None else str(v)
                    for k, v in ctx.items()} if ctx else None,
        })
        parts.append(f"{'.'.join(map(str, loc))}: {msg}")
    message = "; ".join(parts)
    return _error(422, items, message)


async def _not_found(_request: Request, exc: Exception) -> JSONResponse:
    return _error(404, str(exc), str(exc))


async def _conflict(_request: Request, exc: Exception) -> JSONResponse:
    return _error(409, str(exc), str(exc))


async def _http_error(_request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, StarletteHTTPException)
    detail = exc.detail if isinstance(exc.detail, str) else json.dumps(exc.detail)
    return SafeJSONResponse(status_code=exc.status_code,
                            content={"detail": detail, "message": detail},
                            headers=getattr(exc, "headers", None))


STORAGE_FAULT_MEMORY_S = 60.0
"""Seconds after a failed write during which health reports the storage as not writable."""


def _unavailable(request: Request, reason: str) -> JSONResponse:
    request.app.state.storage_fault = (time.monotonic(), reason)
    msg = f"storage unavailable: {reason}"
    return SafeJSONResponse(status_code=503, headers={"Retry-After": str(RETRY_AFTER_S)},
                            content={"detail": msg, "message": msg})


async def _database_error(request: Request, exc: Exception) -> JSONResponse:
    reason = db_fault(exc)
    if reason is None:
        return await _internal_error(request, exc)
    log.error("storage unavailable on %s: %s (%s)", request_line(request), reason,
              type(getattr(exc, "orig", exc)).__name__)
    return _unavailable(request, reason)


async def _os_error(request: Request, exc: Exception) -> JSONResponse:
    assert isinstance(exc, OSError)
    if not is_storage_oserror(exc):
        return await _internal_error(request, exc)
    log.error("storage unavailable on %s: %s", request_line(request), os_fault(exc))
    return _unavailable(request, os_fault(exc))


async def _client_gone(_request: Request, _exc: Exception) -> JSONResponse:
    # the body stopped coming (the client went, or the server's time limit closed the
    # connection, flexride.api.server): nobody reads this answer, and it is no fault here
    return _error(400, "the client closed the connection", "the client closed the connection")


async def _internal_error(request: Request, exc: Exception) -> JSONResponse:
    log.error("internal error on %s", request_line(request), exc_info=exc)
    return _error(500, f"internal error ({type(exc).__name__}); see the service log",
                  f"internal error ({type(exc).__name__})")


def install_error_handlers(app: FastAPI) -> None:
    """Register the handlers above on ``app``."""
    app.add_exception_handler(FlexrideError, _flexride_error)
    app.add_exception_handler(RequestValidationError, _validation_error)
    app.add_exception_handler(NotFound, _not_found)
    app.add_exception_handler(Conflict, _conflict)
    app.add_exception_handler(StarletteHTTPException, _http_error)
    app.add_exception_handler(SQLAlchemyError, _database_error)
    app.add_exception_handler(OSError, _os_error)
    app.add_exception_handler(ClientDisconnect, _client_gone)
    app.add_exception_handler(Exception, _internal_error)


ERROR_RESPONSES: dict[int | str, dict[str, Any]] = {
    400: {"description": "Malformed request (e.g. a body that is not UTF-8 text)"},
    404: {"description": "Unknown id or name"},
    408: {"description": "The request's headers or body did not arrive in time (the "
          "server's limits, docs/service.md); the connection is closed"},
    413: {"description": "Request body too large"},
    422: {"description": "Invalid input: field paths and allowed ranges"},
    429: {"description": "Too many connections from this client address at once"},
    503: {"description": "Storage unavailable (a database or disk that cannot take writes "
          "now): `storage unavailable: <reason>`, Retry-After"},
}
"""Documented error responses shared by the routers (model added in :mod:`.main`)."""

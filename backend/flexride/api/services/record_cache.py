"""Rendered answers of job records (the job list, a job's detail), kept while nothing in the
database changes.

The answer is keyed by the endpoint, its parameters and the database's change counter
(:meth:`flexride.store.JobStore.data_version`, one SQLite pragma): any committed change by any
process (a submission, a worker's progress, a deletion) gives a new counter, so an answer is
never served after its records changed. Only *settled* answers are kept: ones whose jobs are
all finished (succeeded, failed or cancelled), because a queued or running job's times
(``queue_time_s``, ``run_time_s``) move with the clock. Where the database has no counter
(PostgreSQL) nothing is kept and every request reads the records.

The JSON is written by Pydantic from the same response model FastAPI would use, with the
gzip encoding of :mod:`flexride.api.services.result_cache`.
"""

from __future__ import annotations

import threading
import weakref
from collections.abc import Callable, Hashable
from typing import TypeVar

from fastapi import Request, Response
from pydantic import BaseModel

from flexride.api.deps import Services
from flexride.api.schemas import JobList, JobOut
from flexride.api.services.result_cache import (
    Rendered,
    accepts_gzip,
    gzip_settings,
    render_body,
)
from flexride.store import JobStore
from flexride.store.lru import ByteLRU
from flexride.store.models import FINAL_STATUSES

M = TypeVar("M", bound=BaseModel)

MAX_BYTES = 16 * 1024 * 1024
"""Bound of the answers kept per store (bytes)."""
MAX_ENTRIES = 1024
"""Bound of their number (answers of an older counter are never asked for again and age
out)."""

_CACHES: weakref.WeakKeyDictionary[JobStore, ByteLRU] = weakref.WeakKeyDictionary()
_LOCK = threading.Lock()


def _cache(store: JobStore) -> ByteLRU:
    with _LOCK:
        lru = _CACHES.get(store)
        if lru is None:
            lru = _CACHES[store] = ByteLRU(MAX_BYTES, MAX_ENTRIES)
        return lru


def settled(answer: BaseModel) -> bool:
    """Whether an answer depends only on the records (no queued or running job in it)."""
    if isinstance(answer, JobOut):
        return answer.status in FINAL_STATUSES
    if isinstance(answer, JobList):
        return all(job.status in FINAL_STATUSES for job in answer.items)
    return False


def cached_record(request: Request, svc: Services, endpoint: str, params: Hashable,
                  build: Callable[[], M]) -> M | Response:
    """The answer of a record endpoint: kept JSON when the database is unchanged since it was
    made, else ``build()`` (kept when settled).

    Parameters
    ----------
    request : fastapi.Request
        The request (its ``Accept-Encoding`` and the app's gzip settings decide the body).
    svc : Services
        The app's services.
    endpoint : str
        Name of the endpoint (part of the key).
    params : hashable
        Every request parameter that changes the answer (part of the key).
    build : callable
        ``build() -> model`` reads the records (exceptions propagate; nothing is kept).

    Returns
    -------
    pydantic.BaseModel or fastapi.Response
        The model (FastAPI serialises it) when the database has no change counter or the
        answer is not settled; otherwise the rendered answer.
    """
    version = svc.store.data_version()
    if version is None:
        return build()

    def make() -> tuple[Rendered, int]:
        answer = build()
        if not settled(answer):
            raise _Unsettled(answer)
        rendered = _render(answer, gzip_settings(request.app))
        return rendered, rendered.nbytes

    try:  # concurrent requests after a change build the answer once
        rendered = _cache(svc.store).get_or_make((endpoint, params, version), make)
    except _Unsettled as unsettled:
        return unsettled.answer  # type: ignore[return-value]
    return rendered.response(accepts_gzip(request))


class _Unsettled(Exception):
    """An answer that must not be kept (it has queued or running jobs)."""

    def __init__(self, answer: BaseModel):
        super().__init__("unsettled")
        self.answer = answer


def _render(answer: BaseModel, gz: tuple[int, int] | None) -> Rendered:
    return render_body(answer.model_dump_json(by_alias=True).encode(),
                       None if gz is None else gz[0])

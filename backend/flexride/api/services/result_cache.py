"""Rendered answers of the results endpoints, kept in memory.

A finished job's results never change, so the JSON of a results request (summary, channel
list, decimated series, spectra, spectrogram, Sperling breakdown, correlation) is rendered
once and kept, with its gzip encoding, in a bounded LRU (:class:`~flexride.store.lru.ByteLRU`)
per application:

* **key**: job id, result file name, the file's identity (device, inode, size, modification
  time; the summary, which comes from the database, has none), the endpoint and its request
  parameters (channel order included);
* **every request** checks that the job still has its results before the cache is looked
  at: the first request of a job asks the database (one query of one column,
  :meth:`flexride.store.JobStore.result_file_of`: a deleted job is 404, an unfinished one
  409) and remembers the file name of the finished job; later requests only check that this
  file is still there (one ``stat``). That is enough because results never change and a
  deletion sets the file aside before it deletes the record (:func:`flexride.api.services.
  jobs.delete_records_and_files`), so a deleted job's file is gone first; a vanished file
  sends the request to the database again, and a replaced one changes the key;
* **invalidation**: :func:`forget_job` drops a job's entries (answers and file contents) at
  once; besides, at most every :data:`SWEEP_INTERVAL_S` the entries of files that were deleted
  or replaced (by any process) are dropped;
* **gzip** as the app's ``GZipMiddleware`` would answer: the gzip body (compressed once) when
  the request accepts gzip and the body is at least the middleware's ``minimum_size``, with
  ``Content-Encoding: gzip`` and ``Vary: Accept-Encoding`` (the middleware passes an encoded
  answer through); otherwise the plain body, which the middleware handles as before.
"""

from __future__ import annotations

import gzip
import inspect
import threading
import time
import weakref
from collections.abc import Callable, Hashable, Mapping
from dataclasses import dataclass
from typing import Any

from fastapi import Request, Response
from starlette.middleware.gzip import GZipMiddleware

from flexride.api.deps import Services
from flexride.api.errors import SafeJSONResponse
from flexride.api.services.results import result_file
from flexride.errors import ResultsFileError
from flexride.store import ResultFiles
from flexride.store.files import FileToken
from flexride.store.lru import ByteLRU

DEFAULT_MAX_BYTES = 64 * 1024 * 1024
"""Default bound of the rendered answers kept per application (bytes)."""
DEFAULT_MAX_ENTRIES = 4096
"""Default bound of their number."""
SWEEP_INTERVAL_S = 10.0
"""Least time between two sweeps for deleted or replaced files (s)."""
GZIP_LEVEL = 6
"""Compression level of the kept gzip bodies (compressed once, so a better level than the
middleware's per-request one is affordable)."""
_ENTRY_OVERHEAD = 256


@dataclass(frozen=True)
class Rendered:
    """One rendered answer.

    Attributes
    ----------
    body : bytes
        The JSON body.
    gzipped : bytes or None
        Its gzip encoding; None when the body is below the gzip middleware's minimum size
        or the app has no gzip middleware.
    """

    body: bytes
    gzipped: bytes | None

    @property
    def nbytes(self) -> int:
        """Bytes accounted to the cache."""
        return len(self.body) + len(self.gzipped or b"") + _ENTRY_OVERHEAD

    def response(self, accepts_gzip: bool) -> Response:
        """The HTTP answer for a request that does or does not accept gzip."""
        if accepts_gzip and self.gzipped is not None:
            return Response(self.gzipped, media_type="application/json",
                            headers={"Content-Encoding": "gzip", "Vary": "Accept-Encoding"})
        return Response(self.body, media_type="application/json")


class ResponseCache:
    """Rendered results answers of one application and the sweep for vanished files.

    Parameters
    ----------
    files : ResultFiles
        The app's result files (their cache of contents is swept along).
    max_bytes, max_entries : int
        Bounds of the cache (bytes, entries).
    """

    def __init__(self, files: ResultFiles, max_bytes: int = DEFAULT_MAX_BYTES,
                 max_entries: int = DEFAULT_MAX_ENTRIES):
        self.files = files
        self.lru = ByteLRU(max_bytes, max_entries)
        self.max_entries = max_entries
        self._finished: dict[str, str] = {}  # job id -> result file name, in order of use
        self._finished_lock = threading.Lock()
        self._swept = time.monotonic()
        self._sweeping = threading.Lock()

    def result_file(self, svc: Services, job_id: str) -> tuple[str, FileToken]:
        """Name and identity of the result file of finished job ``job_id``: remembered and
        checked with one ``stat``, or read from the database (:class:`NotFound` /
        :class:`Conflict` when the job has no results).
        """
        with self._finished_lock:
            name = self._finished.get(job_id)
        if name is not None:
            try:
                return name, self.files.token(name)
            except ResultsFileError:  # deleted (or being deleted): ask the database
                self._forget_file(job_id)
        name = result_file(svc, job_id)
        token = self.files.token(name)
        with self._finished_lock:
            self._finished.pop(job_id, None)
            self._finished[job_id] = name
            while len(self._finished) > self.max_entries:
                del self._finished[next(iter(self._finished))]
        return name, token

    def _forget_file(self, job_id: str) -> None:
        with self._finished_lock:
            self._finished.pop(job_id, None)

    def forget(self, job_id: str) -> int:
        """Drop the answers and file contents of job ``job_id``; return the entries dropped."""
        self._forget_file(job_id)
        n = self.lru.discard(lambda key: key[0] == job_id)
        return n + self.files.forget(f"{job_id}.h5")

    def sweep(self, force: bool = False) -> int:
        """Drop entries of result files that were deleted or replaced since they were read
        (at most every :data:`SWEEP_INTERVAL_S` unless ``force``); return how many.
        """
        now = time.monotonic()
        if not force and now - self._swept < SWEEP_INTERVAL_S:
            return 0
        if not self._sweeping.acquire(blocking=False):
            return 0
        try:
            self._swept = now
            current = {name: self._token(name) for name in self._names()}
            stale = self.lru.discard(lambda k: _stale(current, k[1], k[2]))
            return stale + self.files.cache.discard(lambda k: _stale(current, k[1], k[2]))
        finally:
            self._sweeping.release()

    def _names(self) -> set[str]:
        return {k[1] for k in self.lru.keys()} | {k[1] for k in self.files.cache.keys()}

    def _token(self, name: str) -> tuple[int, ...] | None:
        try:
            return self.files.token(name)
        except ResultsFileError:  # deleted: its entries go
            return None


def _stale(current: Mapping[Any, Any], name: Any, token: Any) -> bool:
    """Whether an entry of file ``name`` read at version ``token`` is out of date (the file
    is gone, or was replaced when the entry depends on its contents).
    """
    now = current.get(name)
    return now is None or (token is not None and token != now)


_CACHES: weakref.WeakKeyDictionary[ResultFiles, ResponseCache] = weakref.WeakKeyDictionary()
_CACHES_LOCK = threading.Lock()


def response_cache(svc: Services) -> ResponseCache:
    """The answer cache of the application of ``svc`` (created on first use; its bound is
    ``settings.response_cache_mb`` when the settings have it, else 64 MB).
    """
    with _CACHES_LOCK:
        cache = _CACHES.get(svc.files)
        if cache is None:
            mb = getattr(svc.settings, "response_cache_mb", None)
            size = DEFAULT_MAX_BYTES if mb is None else int(float(mb) * 1024 * 1024)
            cache = _CACHES[svc.files] = ResponseCache(svc.files, size)
        return cache


def replace_response_cache(svc: Services, max_bytes: int,
                           max_entries: int = DEFAULT_MAX_ENTRIES) -> ResponseCache:
    """Give the application of ``svc`` a new, empty answer cache with these bounds (bytes,
    entries) and return it.
    """
    with _CACHES_LOCK:
        cache = _CACHES[svc.files] = ResponseCache(svc.files, max_bytes, max_entries)
        return cache


def forget_job(svc: Services, job_id: str) -> int:
    """Drop what is cached of job ``job_id`` (call when it is deleted); entries dropped."""
    return response_cache(svc).forget(job_id)


_GZIP: weakref.WeakKeyDictionary[Any, tuple[int, int] | None] = weakref.WeakKeyDictionary()


def gzip_settings(app: Any) -> tuple[int, int] | None:
    """``(minimum_size, compresslevel)`` of the app's ``GZipMiddleware``, None without one."""
    try:
        return _GZIP[app]
    except KeyError:
        pass
    found = None
    for mw in getattr(app, "user_middleware", ()):
        if mw.cls is GZipMiddleware:
            bound = inspect.signature(GZipMiddleware).bind(None, *mw.args, **mw.kwargs)
            bound.apply_defaults()
            found = (int(bound.arguments["minimum_size"]), int(bound.arguments["compresslevel"]))
    _GZIP[app] = found
    return found


def accepts_gzip(request: Request) -> bool:
    """Whether the request accepts gzip, tested as ``GZipMiddleware`` tests it."""
    return "gzip" in request.headers.get("accept-encoding", "")


def render(content: Any, gzip_min: int | None) -> Rendered:
    """JSON of ``content`` (non-finite numbers as null) and its gzip encoding when the body
    has at least ``gzip_min`` bytes (None: never).
    """
    return render_body(bytes(SafeJSONResponse(content).body), gzip_min)


def render_body(body: bytes, gzip_min: int | None) -> Rendered:
    """A JSON ``body`` and its gzip encoding when it has at least ``gzip_min`` bytes (None:
    never).
    """
    gz = None
    if gzip_min is not None and len(body) >= gzip_min:
        gz = gzip.compress(body, compresslevel=GZIP_LEVEL, mtime=0)
    return Rendered(body, gz)


def cached_answer(request: Request, svc: Services, job_id: str, endpoint: str,
                  params: Hashable, build: Callable[[], Any], *,
                  from_file: bool = True) -> Response:
    """The answer of a results endpoint: from the cache, or built, rendered and kept.

    Parameters
    ----------
    request : fastapi.Request
        The request (its ``Accept-Encoding`` and the app's gzip settings decide the body).
    svc : Services
        The app's services.
    job_id : str
        The job; must have succeeded (404 / 409 with the reason otherwise).
    endpoint : str
        Name of the endpoint (part of the key).
    params : hashable
        Every request parameter that changes the answer (part of the key).
    build : callable
        ``build() -> content`` computes the answer (a JSON-able object) on a miss.
    from_file : bool
        Whether the answer is derived from the result file (keyed by its identity), not only
        from the job record.
    """
    cache = response_cache(svc)
    cache.sweep()
    name, file_token = cache.result_file(svc, job_id)
    token = file_token if from_file else None
    gz = gzip_settings(request.app)

    def make() -> tuple[Rendered, int]:
        r = render(build(), None if gz is None else gz[0])
        return r, r.nbytes

    rendered = cache.lru.get_or_make((job_id, name, token, endpoint, params), make)
    return rendered.response(accepts_gzip(request))

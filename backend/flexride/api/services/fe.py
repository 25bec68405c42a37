"""FE meshes and mode shapes for the browser (``GET /fe/{kind}``, ``GET /jobs/{id}/fe/{kind}``).

An export (:mod:`flexride.fem.export`) is served from its file under
``<cache_dir>/fe-export-<version>/<key>.json`` when it exists. Otherwise :class:`FEBuilds`
starts its build in a separate process — spawned on first use and then kept, so the API's
event loop and threads stay free while a car body is built (about a minute at 0.2 m) — and the
request waits a little (``wait_s``, enough for a body already in the FE cache) before it is
answered 202 with the build's state. A content key is built once at a time however often it is
requested; builds of different keys run one after another in that process, at most
``max_pending`` waiting. A failed build is remembered for ``failure_ttl_s`` and reported to every
request for its key (422 when the parameters give no model, 503 when the build process failed);
after that a request tries again.
"""

from __future__ import annotations

import logging
import multiprocessing
import threading
import time
from collections.abc import Callable
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from concurrent.futures import wait as wait_futures
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from fastapi.responses import FileResponse, Response

from flexride import __version__
from flexride.api.errors import Conflict, SafeJSONResponse
from flexride.errors import ScenarioError
from flexride.fem.export import BODY_FIELDS, ExportSpec, init_build_process, run_export_job
from flexride.model.bodies import BodyModel
from flexride.model.vehicle import Vehicle
from flexride.settings import API_PREFIX

log = logging.getLogger(__name__)

#: Seconds a client is asked to wait before asking again (``Retry-After``).
RETRY_AFTER_S = 3
_LABEL = {"carbody": "car body", "frame": "bogie frame"}


@dataclass
class FEState:
    """Where the export of one key stands.

    Attributes
    ----------
    status : {"ready", "queued", "building", "failed"}
        ``ready``: ``path`` holds the export; ``queued``: waiting for another build;
        ``building``: being built; ``failed``: the last build failed (``error``).
    key : str
        Content key of the export.
    path : pathlib.Path, optional
        The export file (ready).
    elapsed_s : float
        Seconds since the build was requested (queued, building).
    error, error_type : str, optional
        What went wrong (failed).
    model_error : bool
        True when the parameters give no FE model (the build raised a FlexrideError), False
        when the build process failed.
    retry_after_s : int
        When to ask again (s).
    """

    status: Literal["ready", "queued", "building", "failed"]
    key: str
    path: Path | None = None
    elapsed_s: float = 0.0
    error: str | None = None
    error_type: str | None = None
    model_error: bool = False
    retry_after_s: int = RETRY_AFTER_S


@dataclass
class _Pending:
    future: Future
    requested_at: float = field(default_factory=time.monotonic)


@dataclass
class _Failure:
    error: str
    error_type: str
    model_error: bool
    at: float = field(default_factory=time.monotonic)


def _process_executor(cache_dir: Path) -> Executor:
    return ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn"),
                               initializer=init_build_process, initargs=(str(cache_dir),))


class FEBuilds:
    """Exports of FE bodies for the API: served from files, built in the background.

    Parameters
    ----------
    cache_dir : pathlib.Path
        The service's cache directory (``Settings.cache_dir``): the FE cache of the build
        process and ``fe-export-<version>/`` for the export files.
    wait_s : float
        How long a request for an export that is not ready waits for its build (s) before it
        is answered with the build's state.
    failure_ttl_s : float
        How long a failed build is reported before a request tries again (s).
    max_pending : int
        Most builds started or waiting at once; more requests for new keys get 503.
    executor_factory : callable, optional
        Makes the executor of the builds (default: one spawned process).
    build : callable, optional
        ``build(spec, dest) -> {"ok": True, ...} | {"ok": False, "error", "type"}`` run by the
        executor (default :func:`flexride.fem.export.run_export_job`).
    """

    def __init__(self, cache_dir: Path, *, wait_s: float = 3.0, failure_ttl_s: float = 300.0,
                 max_pending: int = 4,
                 executor_factory: Callable[[], Executor] | None = None,
                 build: Callable[[ExportSpec, str], dict[str, Any]] = run_export_job) -> None:
        self.cache_dir = Path(cache_dir)
        self.export_dir = self.cache_dir / f"fe-export-{__version__}"
        self.wait_s = float(wait_s)
        self.failure_ttl_s = float(failure_ttl_s)
        self.max_pending = int(max_pending)
        self._factory = executor_factory or (lambda: _process_executor(self.cache_dir))
        self._build = build
        self._executor: Executor | None = None
        self._pending: dict[str, _Pending] = {}
        self._failures: dict[str, _Failure] = {}
        self._lock = threading.RLock()  # a done callback may run inside _start
        self._stopped = False
        self.builds_started = 0

    def path_for(self, key: str) -> Path:
        """The export file of ``key``."""
        return self.export_dir / f"{key}.json"

    def state(self, spec: ExportSpec, wait_s: float | None = None,
              may_start: bool = True) -> FEState:
        """The state of ``spec``'s export, starting its build if needed and waiting up to
        ``wait_s`` (default :attr:`wait_s`, s) for it to finish.

        Parameters
        ----------
        spec : ExportSpec
            The export wanted.
        wait_s : float, optional
            Seconds to wait for a running build.
        may_start : bool
            Whether a new build may be started (the caller holds the API token, if any);
            otherwise an export that is neither ready nor being built is ``unauthorized``.

        Returns
        -------
        FEState
        """
        key = spec.key
        path = self.path_for(key)
        with self._lock:
            if path.is_file():
                return FEState("ready", key, path=path)
            failed = self._failure(key)
            if failed is not None:
                return failed
            pending = self._pending.get(key)
            if pending is None:
                if not may_start:
                    return FEState("failed", key, error=(
                        "building a new FE model needs the API token (Authorization: Bearer "
                        "<token>); models already built are served without it"),
                        error_type="Unauthorized")
                if self._stopped:
                    return FEState("failed", key, error="the service is stopping",
                                   error_type="Stopping", retry_after_s=30)
                if len(self._pending) >= self.max_pending:
                    return FEState("failed", key, error=(
                        f"{len(self._pending)} FE builds are already queued; try again later"),
                        error_type="Busy", retry_after_s=30)
                started = self._start(spec, key, path)
                if isinstance(started, FEState):
                    return started
                pending = started
        wait = self.wait_s if wait_s is None else wait_s
        if wait > 0:
            wait_futures([pending.future], timeout=wait)
        if pending.future.done():
            self._finished(key, pending.future)
            if path.is_file():
                return FEState("ready", key, path=path)
            with self._lock:
                failed = self._failure(key)
            if failed is not None:
                return failed
        status: Literal["queued", "building"] = (
            "building" if pending.future.running() or pending.future.done() else "queued")
        return FEState(status, key, elapsed_s=time.monotonic() - pending.requested_at)

    def _failure(self, key: str) -> FEState | None:
        f = self._failures.get(key)
        if f is None:
            return None
        left = self.failure_ttl_s - (time.monotonic() - f.at)
        if left <= 0:
            del self._failures[key]
            return None
        return FEState("failed", key, error=f.error, error_type=f.error_type,
                       model_error=f.model_error, retry_after_s=max(1, int(left + 0.999)))

    def _start(self, spec: ExportSpec, key: str, path: Path) -> _Pending | FEState:
        """Submit the build of ``key`` (a failure to start it is a failed build)."""
        fut: Future | None = None
        for _attempt in range(2):  # a pool that broke since the last build: one new pool
            try:
                if self._executor is None:
                    self._executor = self._factory()
                fut = self._executor.submit(self._build, spec, str(path))
                break
            except (BrokenProcessPool, RuntimeError, OSError) as exc:
                self._executor = None
                error = exc
        if fut is None:
            log.error("FE export %s: cannot start the build process", key, exc_info=error)
            self._failures[key] = _Failure(
                f"cannot start the FE build process: {type(error).__name__}: {error}",
                type(error).__name__, False)
            return self._failure(key)  # type: ignore[return-value]
        pending = _Pending(fut)
        self._pending[key] = pending
        self.builds_started += 1
        log.info("FE export %s: building %s", key, spec.parameters())
        fut.add_done_callback(lambda f: self._finished(key, f))
        return pending

    def _finished(self, key: str, fut: Future) -> None:
        """Record the outcome of a finished build (idempotent)."""
        with self._lock:
            pending = self._pending.get(key)
            if pending is None or pending.future is not fut:
                return
            del self._pending[key]
            if fut.cancelled():
                return
            exc = fut.exception()
            if exc is None:
                res = fut.result()
                if res.get("ok"):
                    log.info("FE export %s: done in %.1f s", key, res.get("seconds", 0.0))
                    return
                self._failures[key] = _Failure(str(res.get("error")),
                                               str(res.get("type", "FEModelError")), True)
                return
            if isinstance(exc, BrokenProcessPool):
                msg = ("the FE build process died (killed, or out of memory); "
                       "see the service log")
                self._executor = None
            else:
                msg = f"building the FE model failed: {type(exc).__name__}: {exc}"
            log.error("FE export %s: %s", key, msg, exc_info=exc)
            self._failures[key] = _Failure(msg, type(exc).__name__, False)

    def start(self) -> None:
        """Accept builds (again); the build process itself starts with the first build."""
        with self._lock:
            self._stopped = False

    def stop(self) -> None:
        """Cancel waiting builds and end the build process (a build in progress is lost; its
        file is never half written); builds are refused until :meth:`start`."""
        with self._lock:
            self._stopped = True
            ex, self._executor = self._executor, None
        if ex is None:
            return
        procs = list((getattr(ex, "_processes", None) or {}).values())
        ex.shutdown(wait=False, cancel_futures=True)
        for p in procs:
            if p.is_alive():
                p.terminate()
        for p in procs:
            p.join(timeout=5)


# -- requests ------------------------------------------------------------------------------------


def preset_vehicle(preset: str) -> Vehicle:
    """The vehicle of preset ``preset``; a 422 naming ``query.preset`` when there is none."""
    from flexride.model.presets import PRESETS, load_preset

    if preset not in PRESETS:
        raise ScenarioError.at(("query", "preset"), f"unknown preset {preset!r} "
                               f"(allowed: {', '.join(PRESETS)})", "GET /fe")
    return load_preset(preset).vehicle


def job_spec(svc: Any, job_id: str, kind: str, max_modes: int) -> ExportSpec:
    """The export spec of a job's flexible body ``kind`` (its vehicle and its
    ``bodies.carbody`` / ``bodies.frames`` settings).

    Raises
    ------
    NotFound
        No such job.
    Conflict
        The job models that body as rigid.
    """
    from flexride.api.services.jobs import get_job
    from flexride.model.scenario import scenario_from_dict

    job = get_job(svc, job_id, scenario=True)
    scenario = scenario_from_dict(dict(job.scenario or {}), source=f"job {job_id}")
    fld = BODY_FIELDS[kind]
    body: BodyModel = getattr(scenario.bodies, fld)
    if body.model != "flexible":
        raise Conflict(f"job {job_id} models the {_LABEL[kind]} as rigid (bodies.{fld}.model = "
                       f"rigid): it has no FE model; {API_PREFIX}/fe/{kind} serves the default")
    return ExportSpec.create(kind, scenario.vehicle, body, max_modes)


def respond(builds: FEBuilds, spec: ExportSpec, may_start: bool = True) -> Response:
    """The HTTP answer for ``spec``: 200 with the export, 202 while it is built, 401 when a
    build would start without the API token, 422 when the parameters give no FE model, 503
    when the build failed or too many are queued."""
    st = builds.state(spec, may_start=may_start)
    if st.status == "ready" and st.path is not None:
        return FileResponse(st.path, media_type="application/json",
                            headers={"Cache-Control": "no-cache"})
    retry = {"Retry-After": str(st.retry_after_s), "Cache-Control": "no-store"}
    if st.status == "failed" and st.error_type == "Unauthorized":
        return SafeJSONResponse(status_code=401, headers={"WWW-Authenticate": "Bearer"},
                                content={"detail": st.error, "message": st.error})
    if st.status == "failed":
        msg = st.error or "the FE build failed"
        if st.model_error:
            return SafeJSONResponse(status_code=422, content={
                "detail": [{"loc": [], "msg": msg, "type": st.error_type or "FEModelError"}],
                "message": msg})
        return SafeJSONResponse(status_code=503, headers=retry,
                                content={"detail": msg, "message": msg})
    what = _LABEL[spec.kind]
    first = ("waiting for another FE build to finish" if st.status == "queued"
             else f"building the FE model of the {what}")
    return SafeJSONResponse(status_code=202, headers=retry, content={
        "status": st.status, "key": st.key, "parameters": spec.parameters(),
        "elapsed_s": round(st.elapsed_s, 1), "retry_after_s": st.retry_after_s,
        "message": f"{first} (first time only; about a minute for the 0.2 m car body): "
                   f"ask again in {st.retry_after_s} s"})

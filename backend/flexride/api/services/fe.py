"""FE meshes and mode shapes for the browser (``GET /fe/{kind}``, ``GET /jobs/{id}/fe/{kind}``).

An export (:mod:`flexride.fem.export`) is served from its file under
``<cache_dir>/fe-export-<version>/<key>.json`` when it exists. Otherwise it is built by a job of
kind ``fe_export`` that the service's job runner runs like a simulation (embedded worker
processes or Celery workers, :func:`flexride.study.run_job.run_fe_export`): the API never builds
an export itself, it only reads the file and the job's record.

A request for an export that is not on file looks up the newest FE job of its content key:

* queued or running → 202 with the job's state, after waiting up to ``wait_s`` for it (polling
  the file and the store, not holding a process);
* failed less than ``failure_ttl_s`` ago → 422 when the parameters give no FE model (the build
  raised a :class:`~flexride.errors.FlexrideError`), 503 otherwise (internal error, worker
  lost, storage);
* succeeded less than ``failure_ttl_s`` ago but its file is not here → 503 (the API and the
  workers do not share the cache directory);
* none, cancelled, failed or succeeded longer ago (its file gone) → a new job is submitted
  (:meth:`flexride.study.submit.Submitter.submit_fe_export`: one per key while one is queued
  or running), which needs the API token when the service has one (401 otherwise), and at most
  ``max_pending`` FE jobs wait or run at once (503 beyond).
"""

from __future__ import annotations

import json
import logging
import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
from fastapi.responses import FileResponse, Response

from flexride.api.errors import Conflict, SafeJSONResponse
from flexride.errors import ErrorItem, FEModelError, ScenarioError
from flexride.fem.export import BODY_FIELDS, BODY_LABELS, ExportSpec, export_path
from flexride.fem.mode_types import UNCLASSIFIED
from flexride.fem.pairing import ModelModes, pair_targets
from flexride.fem.targets import ModeTarget, parse_targets
from flexride.scenario.bodies import BodyModel
from flexride.scenario.vehicle import Vehicle
from flexride.settings import API_PREFIX
from flexride.store import Job, JobStore, now
from flexride.study.submit import Submitter

log = logging.getLogger(__name__)

#: Seconds a client is asked to wait before asking again (``Retry-After``).
RETRY_AFTER_S = 3
#: Job kind of the FE export builds.
FE_KIND = "fe_export"
_FIRST_TIME = ("first time only; about a minute of computing for the 0.2 m car body, several "
               "minutes on a busy machine")


@dataclass
class FEState:
    """Where the export of one key stands.

    Attributes
    ----------
    status : {"ready", "queued", "building", "failed", "new"}
        ``ready``: ``path`` holds the export; ``queued``: its job waits for a worker;
        ``building``: its job runs; ``failed``: the last build failed (``error``) or cannot
        be started; ``new``: no job is building it (one has to be submitted).
    key : str
        Content key of the export.
    path : pathlib.Path, optional
        The export file (ready).
    job : Job, optional
        The FE job of the key (queued, building, failed).
    elapsed_s : float
        Seconds since the job was submitted (queued, building).
    error, error_type : str, optional
        What went wrong (failed).
    model_error : bool
        True when the parameters give no FE model (the build raised a FlexrideError), False
        when the build failed otherwise.
    retry_after_s : int
        When to ask again (s).
    """

    status: Literal["ready", "queued", "building", "failed", "new"]
    key: str
    path: Path | None = None
    job: Job | None = None
    elapsed_s: float = 0.0
    error: str | None = None
    error_type: str | None = None
    model_error: bool = False
    retry_after_s: int = RETRY_AFTER_S


class FEExports:
    """Exports of FE bodies for the API: served from files, built by ``fe_export`` jobs.

    Parameters
    ----------
    store : JobStore
        The job store (the FE jobs' records).
    submitter : Submitter
        Submits the FE jobs to the service's runner.
    cache_dir : pathlib.Path
        The service's cache directory (``Settings.cache_dir``), shared with the workers:
        ``fe-export-<version>/`` holds the export files.
    wait_s : float
        How long a request for an export that is not ready waits for its build (s) before it
        is answered with the build's state (``FLEXRIDE_FE_WAIT_S``).
    failure_ttl_s : float
        How long a failed build is reported before a request submits a new one (s).
    max_pending : int
        Most FE jobs queued or running at once; a request that would submit another one gets
        503.
    poll_s : float
        Interval of the file and store checks while a request waits (s).
    """

    def __init__(self, store: JobStore, submitter: Submitter, cache_dir: Path, *,
                 wait_s: float = 3.0, failure_ttl_s: float = 300.0, max_pending: int = 4,
                 poll_s: float = 0.2) -> None:
        self.store, self.submitter = store, submitter
        self.cache_dir = Path(cache_dir)
        self.wait_s = float(wait_s)
        self.failure_ttl_s = float(failure_ttl_s)
        self.max_pending = int(max_pending)
        self.poll_s = float(poll_s)

    def path_for(self, key: str) -> Path:
        """The export file of ``key``."""
        return export_path(self.cache_dir, key)

    def state(self, spec: ExportSpec, wait_s: float | None = None,
              may_start: bool = True) -> FEState:
        """The state of ``spec``'s export, submitting its build if needed and waiting up to
        ``wait_s`` (default :attr:`wait_s`, s) for it to finish.

        Parameters
        ----------
        spec : ExportSpec
            The export wanted.
        wait_s : float, optional
            Seconds to wait for a queued or running build.
        may_start : bool
            Whether a new build may be submitted (the caller holds the API token, if any);
            otherwise an export that is neither ready nor being built is ``Unauthorized``.

        Returns
        -------
        FEState
            ``ready``, ``queued``, ``building`` or ``failed``.
        """
        key = spec.key
        wait = self.wait_s if wait_s is None else float(wait_s)
        deadline = time.monotonic() + wait
        submitted: Job | None = None
        while True:
            st = self.of_job(key, self.store.latest_job(FE_KIND, key))
            if st.status == "new":
                if submitted is not None:  # cancelled or deleted since this request sent it
                    return FEState("failed", key, error=(
                        f"the FE build (job {submitted.id}) was cancelled or deleted; ask "
                        "again to start another one"), error_type="Cancelled")
                refused = self._refusal(key, may_start)
                if refused is not None:
                    return refused
                submitted, _created = self.submitter.submit_fe_export(spec)
                st = self.of_job(key, submitted)
            if st.status in ("ready", "failed"):
                return st
            left = deadline - time.monotonic()
            if left <= 0:
                return st
            time.sleep(min(self.poll_s, left))

    def of_job(self, key: str, job: Job | None) -> FEState:
        """The state of the export ``key`` given the newest FE job of that key (or None)."""
        path = self.path_for(key)
        if path.is_file():
            return FEState("ready", key, path=path, job=job)
        if job is None or job.status == "cancelled":
            return FEState("new", key, job=job)
        t = now()
        if job.status in ("queued", "running"):
            return FEState("queued" if job.status == "queued" else "building", key, job=job,
                           elapsed_s=max(0.0, t - job.created_at))
        left = self.failure_ttl_s - (t - (job.finished_at or job.updated_at))
        if left <= 0:  # failed, or succeeded and its file was removed since: build it again
            return FEState("new", key, job=job)
        if job.status == "succeeded":  # its worker wrote the file where this API does not look
            return FEState("failed", key, job=job, error_type="ExportMissing", error=(
                "the build succeeded but its export is not in this API's cache directory: the "
                "API and the workers must share FLEXRIDE_CACHE_DIR"),
                retry_after_s=max(1, math.ceil(left)))
        meta = job.run_meta or {}
        return FEState("failed", key, job=job, error=job.error or job.message,
                       error_type=str(meta.get("error_type") or "WorkerLost"),
                       model_error=meta.get("error_origin") == "input",
                       retry_after_s=max(1, math.ceil(left)))

    def _refusal(self, key: str, may_start: bool) -> FEState | None:
        """Why a new build of ``key`` may not be submitted now, or None."""
        if not may_start:
            return FEState("failed", key, error=(
                "building a new FE model needs the API token (Authorization: Bearer <token>); "
                "models already built are served without it"), error_type="Unauthorized")
        pending = self.store.count_active(FE_KIND)
        if pending >= self.max_pending:
            return FEState("failed", key, error=(
                f"{pending} FE builds are already queued or running; try again later"),
                error_type="Busy", retry_after_s=30)
        return None


# -- requests ------------------------------------------------------------------------------------


def preset_vehicle(preset: str) -> Vehicle:
    """The vehicle of preset ``preset``; a 422 naming ``query.preset`` when there is none."""
    from flexride.scenario.presets import PRESETS, load_preset

    if preset not in PRESETS:
        raise ScenarioError.at(("query", "preset"), f"unknown preset {preset!r} "
                               f"(allowed: {', '.join(PRESETS)})", "GET /fe")
    return load_preset(preset).vehicle


def job_spec(svc: Any, job_id: str, kind: str, max_modes: int) -> ExportSpec:
    """The export spec of a simulation job's flexible body ``kind`` (its vehicle and its
    ``bodies.carbody`` / ``bodies.frames`` settings).

    Raises
    ------
    NotFound
        No such job.
    Conflict
        The job models that body as rigid, or is not a simulation.
    """
    from flexride.api.services.jobs import get_job
    from flexride.scenario.scenario import scenario_from_dict

    job = get_job(svc, job_id, scenario=True)
    if job.kind != "simulation":
        raise Conflict(f"job {job_id} is a job of kind {job.kind}, not a simulation: it has no "
                       f"bodies; {API_PREFIX}/fe/{kind} serves FE models by their parameters")
    scenario = scenario_from_dict(dict(job.scenario or {}), source=f"job {job_id}")
    fld = BODY_FIELDS[kind]
    body: BodyModel = getattr(scenario.bodies, fld)
    if body.model != "flexible":
        raise Conflict(f"job {job_id} models the {BODY_LABELS[kind]} as rigid (bodies.{fld}.model "
                       f"= rigid): it has no FE model; {API_PREFIX}/fe/{kind} serves the default")
    return ExportSpec.create(kind, scenario.vehicle, body, max_modes)


def _building_message(st: FEState, what: str) -> str:
    """What a 202 says: waiting for a worker, or the build's last progress message."""
    headline = f"building the FE model of the {what}"
    if st.status == "queued" or st.job is None:
        text = f"waiting for a free worker to build the FE model of the {what}"
    else:
        step = st.job.message or ""
        text = step if step.startswith(headline) else f"{headline} ({step})" if step else headline
    return f"{text} ({_FIRST_TIME}): ask again in {st.retry_after_s} s"


def respond(exports: FEExports, spec: ExportSpec, may_start: bool = True) -> Response:
    """The HTTP answer for ``spec``: 200 with the export, 202 while its job is queued or
    running, 401 when a build would be submitted without the API token, 422 when the
    parameters give no FE model, 503 when the build failed otherwise or too many are
    queued.
    """
    st = exports.state(spec, may_start=may_start)
    if st.status == "ready" and st.path is not None:
        return FileResponse(st.path, media_type="application/json",
                            headers={"Cache-Control": "no-cache"})
    retry = {"Retry-After": str(st.retry_after_s), "Cache-Control": "no-store"}
    if st.status == "failed" and st.error_type == "Unauthorized":
        return SafeJSONResponse(status_code=401, headers={"WWW-Authenticate": "Bearer"},
                                content={"detail": st.error, "message": st.error})
    what = BODY_LABELS[spec.kind]
    if st.status == "failed":
        msg = st.error or "the FE build failed"
        job_id = st.job.id if st.job is not None else None
        if st.model_error:
            return SafeJSONResponse(status_code=422, headers={"Cache-Control": "no-store"},
                                    content={"detail": [{
                                        "loc": [], "msg": msg,
                                        "type": st.error_type or "FEModelError",
                                        "ctx": {"parameters": spec.parameters(),
                                                "job_id": job_id}}],
                                        "message": msg})
        if st.job is not None:
            msg = f"building the FE model of the {what} failed (job {job_id}): {msg}"
        return SafeJSONResponse(status_code=503, headers=retry,
                                content={"detail": msg, "message": msg})
    job = st.job
    return SafeJSONResponse(status_code=202, headers=retry, content={
        "status": st.status, "key": st.key, "parameters": spec.parameters(),
        "job_id": job.id if job is not None else None,
        "progress": job.progress if job is not None else 0.0,
        "elapsed_s": round(st.elapsed_s, 1), "retry_after_s": st.retry_after_s,
        "message": _building_message(st, what)})


def respond_pairing(exports: FEExports, spec: ExportSpec, targets_text: str,
                    may_start: bool = True) -> Response:
    """The pairing of ``spec``'s exported modes with the targets ``targets_text`` (the
    spelling of ``flexride fe calibrate --targets``): 200 once the export is on file, else
    the export's own answer (202 while it is built, 401, 422, 503: :func:`respond`).

    Raises
    ------
    ScenarioError
        Targets that do not parse (located at ``query.targets``).
    """
    targets = parse_query_targets(targets_text)
    st = exports.state(spec, may_start=may_start)
    if st.status != "ready" or st.path is None:
        return respond(exports, spec, may_start=may_start)
    export = json.loads(Path(st.path).read_text())
    modes = ModelModes(np.array([m["frequency_hz"] for m in export["modes"]], dtype=float),
                       [m["classification"] or UNCLASSIFIED for m in export["modes"]])
    pairs = pair_targets(targets, modes)
    return SafeJSONResponse({"pairs": [p.to_dict() for p in pairs],
                             "modes_considered": len(export["modes"]),
                             "model": export["model"]},
                            headers={"Cache-Control": "no-cache"})


def parse_query_targets(text: str) -> list[ModeTarget]:
    """Targets from the ``targets`` query parameter, or :class:`ScenarioError` located there."""
    try:
        return parse_targets(text)
    except FEModelError as exc:
        raise ScenarioError(f"query: targets: {exc}",
                            [ErrorItem(("query", "targets"), str(exc))]) from exc

"""Run one job end to end: the only place that does, shared by the embedded runner's worker
processes and the Celery task.

Claim the record → run the job's kind (:data:`HANDLERS`) with progress written to the store
and cancellation read from it → mark the job succeeded, failed (with the error text) or
cancelled. A heartbeat thread keeps the record fresh during long phases without progress
(assembly, FE reduction), so a lost worker is told apart from a slow one.

* ``simulation``: validate the scenario → simulate → write ``<results>/<job_id>.h5``
  atomically → analyse → store the summary.
* ``fe_export``: the job's scenario is an :class:`~flexride.fem.export.ExportSpec`; build the
  body (through the FE cache) and write its browser export atomically to
  ``<cache_dir>/fe-export-<version>/<key>.json``, which the API serves.

A failed job records what failed in ``run_meta``: ``error_type`` (the exception's class) and
``error_origin`` — ``input`` (a :class:`~flexride.errors.FlexrideError`: the scenario or the
model parameters), ``storage`` (:class:`~flexride.errors.StorageError`) or ``internal``.
"""

from __future__ import annotations

import logging
import os
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from flexride.errors import FlexrideError, SimulationCancelled, StorageError
from flexride.jobs.presence import Presence, worker_is_dead
from flexride.settings import Settings
from flexride.store import Claim, Job, JobStore, ResultFiles, now

if TYPE_CHECKING:
    from flexride.fem.export import ExportSpec

log = logging.getLogger(__name__)

PROGRESS_INTERVAL_S = 0.5
"""Least time between two progress writes (and two cancellation reads) of a running job."""

FEBuild = Callable[["ExportSpec", Callable[[float, str], None]], dict[str, Any]]
"""``build(spec, progress) -> export``: what an ``fe_export`` job runs to get the export
(default :func:`flexride.fem.export.build_export`)."""


@dataclass
class JobContext:
    """What a worker needs to run jobs.

    Attributes
    ----------
    store : JobStore
        The job store.
    files : ResultFiles
        The results directory.
    settings : Settings
        Heartbeat interval and timeout.
    worker : str
        This worker's name (``<kind>-<pid>@<host>``).
    presence : Presence or None
        The worker's presence reporter (told the current job).
    fe_build : callable or None
        What ``fe_export`` jobs run to build an export (:data:`FEBuild`); None: the real
        build, :func:`flexride.fem.export.build_export` (tests give a quick stand-in).
    """

    store: JobStore
    files: ResultFiles
    settings: Settings
    worker: str
    presence: Presence | None = None
    fe_build: FEBuild | None = field(default=None, repr=False)

    @classmethod
    def from_settings(cls, settings: Settings, worker: str) -> JobContext:
        """Context of a worker process configured by ``settings``.

        Also points this process's FE cache (``$FLEXRIDE_CACHE_DIR``, read by
        :mod:`flexride.fem.cache`) at ``settings.cache_dir``: the service's cache, where the
        API finds the exports and where jobs share reduced bodies.
        """
        from flexride.fileio import CACHE_ENV

        os.environ[CACHE_ENV] = str(settings.cache_dir)
        store = JobStore.from_url(settings.effective_database_url, create=True)
        return cls(store=store, files=ResultFiles(settings.results_dir), settings=settings,
                   worker=worker)


class _Heartbeat(threading.Thread):
    def __init__(self, ctx: JobContext, job_id: str):
        super().__init__(name=f"heartbeat-{job_id[:8]}", daemon=True)
        self.ctx, self.job_id = ctx, job_id
        self.halt = threading.Event()
        self.lost = False

    def run(self) -> None:
        while not self.halt.wait(self.ctx.settings.heartbeat_interval_s):
            try:
                if not self.ctx.store.heartbeat(self.job_id, self.ctx.worker):
                    self.lost = True  # cancelled, deleted or taken over
            except Exception as exc:
                log.warning("job %s: heartbeat failed: %s", self.job_id, exc)


class Reporter:
    """Throttled progress writes and cancellation reads of a running job (the ``progress`` and
    ``cancel`` of :func:`flexride.solver.simulate`, given to every :data:`JobHandler`).
    """

    def __init__(self, ctx: JobContext, job_id: str, heartbeat: _Heartbeat):
        self.ctx, self.job_id, self.hb = ctx, job_id, heartbeat
        self.last_write = 0.0
        self.last_check = time.monotonic()
        self.stop = False

    def progress(self, fraction: float, message: str, force: bool = False) -> None:
        """Record progress, at most every :data:`PROGRESS_INTERVAL_S` unless ``force`` (or
        done).
        """
        t = time.monotonic()
        if t - self.last_write < PROGRESS_INTERVAL_S and fraction < 1.0 and not force:
            return
        self.last_write = t
        try:
            if not self.ctx.store.report_progress(self.job_id, self.ctx.worker, fraction,
                                                  message):
                self.stop = True
        except Exception as exc:
            log.warning("job %s: progress not recorded: %s", self.job_id, exc)

    def cancel(self, immediately: bool = False) -> bool:
        """Whether the run must stop (cancelled, deleted, taken over); the store is read at
        most every :data:`PROGRESS_INTERVAL_S` unless ``immediately``.
        """
        if self.stop or self.hb.lost:
            return True
        t = time.monotonic()
        if immediately or t - self.last_check >= PROGRESS_INTERVAL_S:
            self.last_check = t
            try:
                self.stop = self.ctx.store.should_stop(self.job_id, self.ctx.worker)
            except Exception as exc:
                log.warning("job %s: cannot read cancellation: %s", self.job_id, exc)
        return self.stop


@dataclass
class Outcome:
    """What a job kind's run produced.

    Attributes
    ----------
    values : dict
        Columns stored with the ``succeeded`` state (``summary``, ``result_file``,
        ``run_meta``...).
    written : str or None
        The job's own result file, removed when the record was deleted during the run.
    """

    values: dict[str, Any]
    written: str | None = None


JobHandler = Callable[[Job, JobContext, Reporter], Outcome]
"""Runs a claimed job of one kind; raises to fail it (:class:`SimulationCancelled` cancels)."""


def claim_and_run(job_id: str, ctx: JobContext) -> str:
    """Claim job ``job_id`` for ``ctx.worker`` and run it.

    Returns
    -------
    str
        The final status, or why the job was not run (``missing``, ``running elsewhere``...).
    """
    claim = ctx.store.claim(job_id, ctx.worker,
                            stale_before=now() - ctx.settings.heartbeat_timeout_s,
                            dead=worker_is_dead)
    if not claim.claimed:
        log.info("job %s not run by %s: %s", job_id, ctx.worker, claim.reason)
        return claim.reason
    return run_claimed(claimed_job(claim), ctx)


def claimed_job(claim: Claim) -> Job:
    """The job record of a successful claim (the store always returns it with the claim)."""
    if claim.job is None:
        raise FlexrideError(f"the job store granted a claim without its job ({claim.reason})")
    return claim.job


def run_claimed(job: Job, ctx: JobContext) -> str:
    """Run a job already claimed by ``ctx.worker`` (its scenario loaded); return its status."""
    job_id = job.id
    log.info("job %s (%s, %s) started by %s, attempt %d", job_id, job.kind, job.name,
             ctx.worker, job.attempts)
    if ctx.presence is not None:
        ctx.presence.current_job = job_id
        ctx.presence.report()
    hb = _Heartbeat(ctx, job_id)
    hb.start()
    rep = Reporter(ctx, job_id, hb)
    t0 = time.perf_counter()
    status = "failed"
    try:
        handler = HANDLERS.get(job.kind)
        if handler is None:
            raise FlexrideError(f"unknown job kind {job.kind!r} (this worker runs "
                                f"{', '.join(HANDLERS)})")
        out = handler(job, ctx, rep)
        status = "succeeded"
        done = ctx.store.finish(job_id, ctx.worker, status, wall_time_s=time.perf_counter() - t0,
                                progress=1.0, message="done", **out.values)
        if not done:
            status = _not_ours(ctx, job_id, out.written)
    except SimulationCancelled as exc:
        status = "cancelled"
        if not ctx.store.finish(job_id, ctx.worker, status, message=str(exc),
                                wall_time_s=time.perf_counter() - t0):
            status = _not_ours(ctx, job_id, None)
    except FlexrideError as exc:
        status = "failed"
        origin = "storage" if isinstance(exc, StorageError) else "input"
        if not ctx.store.finish(job_id, ctx.worker, status, error=str(exc),
                                message=f"failed: {type(exc).__name__}",
                                run_meta=_failure(exc, origin),
                                wall_time_s=time.perf_counter() - t0):
            status = _not_ours(ctx, job_id, None)
    except Exception as exc:  # a bug, a time limit, or the database: record it
        log.exception("job %s failed", job_id)
        status = "failed"
        try:
            ctx.store.finish(job_id, ctx.worker, status,
                             error=f"internal error: {type(exc).__name__}: {exc}",
                             message="failed: internal error",
                             run_meta=_failure(exc, "internal"),
                             wall_time_s=time.perf_counter() - t0)
        except Exception:
            log.exception("job %s: cannot record the failure", job_id)
    finally:
        hb.halt.set()
        if ctx.presence is not None:
            ctx.presence.current_job = None
            ctx.presence.report()
    log.info("job %s %s in %.2f s", job_id, status, time.perf_counter() - t0)
    return status


def _failure(exc: BaseException, origin: str) -> dict[str, Any]:
    """``run_meta`` of a failed job: the exception's class and where the fault lies."""
    return {"error_type": type(exc).__name__, "error_origin": origin}


def run_simulation(job: Job, ctx: JobContext, rep: Reporter) -> Outcome:
    """A ``simulation`` job: simulate its scenario, write the results file, analyse them."""
    from flexride.analysis._common import jsonable
    from flexride.results import run_timings
    from flexride.scenario.scenario import scenario_from_dict
    from flexride.solver import simulate
    from flexride.store.probe import dir_problem
    from flexride.store.uploads import UploadStore
    from flexride.study.sections import job_summary

    scenario = scenario_from_dict(job.scenario, source=f"job {job.id}")
    problem = dir_problem(ctx.files.root)
    if problem:  # fail now, not after the run
        raise StorageError(f"storage unavailable: results directory not writable: {problem}")
    results = simulate(scenario, progress=rep.progress, cancel=rep.cancel,
                       sources=UploadStore(ctx.settings.uploads_dir).sources,
                       max_steps=ctx.settings.max_steps)
    rep.progress(1.0, "writing results")
    name = ctx.files.name_for(job.id)
    t_write = time.perf_counter()
    results.write_hdf5(ctx.files.path(name))
    t_analyze = time.perf_counter()
    section = (job.run_meta or {}).get("section")
    summary = job_summary(results, section)
    meta = jsonable(results.meta)
    if section:
        meta["section"] = section
    meta["timings"] = run_timings(results.meta, t_analyze - t_write,
                                  time.perf_counter() - t_analyze)
    return Outcome({"summary": summary, "result_file": name, "run_meta": meta}, written=name)


def run_fe_export(job: Job, ctx: JobContext, rep: Reporter) -> Outcome:
    """An ``fe_export`` job: build the body of its :class:`~flexride.fem.export.ExportSpec`
    (through the FE cache) and write the export atomically where the API serves it
    (:func:`~flexride.fem.export.export_path` under ``settings.cache_dir``).

    The build itself cannot be interrupted: a cancellation (or a take-over) during it is
    obeyed before the file is written.
    """
    from flexride import __version__
    from flexride.fem.export import (
        BODY_LABELS,
        ExportSpec,
        build_export,
        export_path,
        write_json_atomic,
    )
    from flexride.store.probe import dir_problem, is_storage_oserror, os_fault

    spec = ExportSpec.from_dict(job.scenario or {})
    if spec.key != job.scenario_hash:
        raise RuntimeError(f"the export's content key {spec.key} is not the job's "
                           f"{job.scenario_hash}: this worker runs flexride {__version__}, "
                           "the job was submitted by another version")
    dest = export_path(ctx.settings.cache_dir, spec.key)
    problem = dir_problem(dest.parent)
    if problem:  # fail now, not after the build
        raise StorageError(f"storage unavailable: FE export directory not writable: {problem}")

    def progress(fraction: float, message: str) -> None:  # a build reports a few steps: all kept
        rep.progress(fraction, message, force=True)

    progress(0.0, f"building the FE model of the {BODY_LABELS[spec.kind]}")
    build = ctx.fe_build or build_export
    data = build(spec, progress)
    if rep.cancel(immediately=True):
        raise SimulationCancelled("cancelled while the FE model was built (no export written)")
    progress(0.95, "writing the export")
    try:
        write_json_atomic(dest, data)
    except OSError as exc:
        if is_storage_oserror(exc):
            raise StorageError(f"storage unavailable: FE export not written: "
                               f"{os_fault(exc)}") from exc
        raise
    model = data.get("model") or {}
    return Outcome({"run_meta": {"export": dest.name, "from_cache": model.get("from_cache"),
                                 "n_elastic_modes": model.get("n_elastic_modes"),
                                 "build_seconds": model.get("build_seconds")}})


def run_paper_report(job: Job, ctx: JobContext, rep: Reporter) -> Outcome:
    """A ``paper_report`` job: the report of a paper report study
    (:func:`flexride.study.report.run_paper_report`).
    """
    from flexride.study.report import run_paper_report as run

    return run(job, ctx, rep)


HANDLERS: dict[str, JobHandler] = {"simulation": run_simulation, "fe_export": run_fe_export,
                                   "paper_report": run_paper_report}
"""How each job kind (:data:`flexride.store.models.JOB_KINDS`) runs."""


def _not_ours(ctx: JobContext, job_id: str, written: str | None) -> str:
    """The record changed under us: deleted (remove our file) or taken over."""
    job = ctx.store.get_job(job_id)
    if job is None:
        ctx.files.delete(written)
        return "deleted"
    return job.status

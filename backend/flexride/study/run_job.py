"""Run one job end to end: the only place that does, shared by the embedded runner's worker
processes and the Celery task.

Claim the record → validate its scenario → simulate with progress written to the store and
cancellation read from it → write ``<results>/<job_id>.h5`` atomically → analyse → store the
summary → mark the job succeeded, failed (with the error text) or cancelled. A heartbeat
thread keeps the record fresh during long phases without progress (assembly, FE reduction),
so a lost worker is told apart from a slow one.
"""

from __future__ import annotations

import logging
import threading
import time
from dataclasses import dataclass
from typing import Any

from flexride.errors import FlexrideError, SimulationCancelled, StorageError
from flexride.jobs.presence import Presence, worker_is_dead
from flexride.settings import Settings
from flexride.store import Claim, Job, JobStore, ResultFiles, now

log = logging.getLogger(__name__)

PROGRESS_INTERVAL_S = 0.5
"""Least time between two progress writes (and two cancellation reads) of a running job."""


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
    """

    store: JobStore
    files: ResultFiles
    settings: Settings
    worker: str
    presence: Presence | None = None

    @classmethod
    def from_settings(cls, settings: Settings, worker: str) -> JobContext:
        """Context of a worker process configured by ``settings``."""
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


class _Reporter:
    """Throttled progress writes and cancellation reads for :func:`flexride.solver.simulate`."""

    def __init__(self, ctx: JobContext, job_id: str, heartbeat: _Heartbeat):
        self.ctx, self.job_id, self.hb = ctx, job_id, heartbeat
        self.last_write = 0.0
        self.last_check = time.monotonic()
        self.stop = False

    def progress(self, fraction: float, message: str) -> None:
        t = time.monotonic()
        if t - self.last_write < PROGRESS_INTERVAL_S and fraction < 1.0:
            return
        self.last_write = t
        try:
            if not self.ctx.store.report_progress(self.job_id, self.ctx.worker, fraction,
                                                  message):
                self.stop = True
        except Exception as exc:
            log.warning("job %s: progress not recorded: %s", self.job_id, exc)

    def cancel(self) -> bool:
        if self.stop or self.hb.lost:
            return True
        t = time.monotonic()
        if t - self.last_check >= PROGRESS_INTERVAL_S:
            self.last_check = t
            try:
                self.stop = self.ctx.store.should_stop(self.job_id, self.ctx.worker)
            except Exception as exc:
                log.warning("job %s: cannot read cancellation: %s", self.job_id, exc)
        return self.stop


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
    from flexride.analysis import analyze
    from flexride.analysis._common import jsonable
    from flexride.model.scenario import scenario_from_dict
    from flexride.solver import simulate
    from flexride.store.probe import dir_problem
    from flexride.store.uploads import UploadStore

    job_id = job.id
    log.info("job %s (%s) started by %s, attempt %d", job_id, job.name, ctx.worker, job.attempts)
    if ctx.presence is not None:
        ctx.presence.current_job = job_id
        ctx.presence.report()
    hb = _Heartbeat(ctx, job_id)
    hb.start()
    rep = _Reporter(ctx, job_id, hb)
    t0 = time.perf_counter()
    status = "failed"
    try:
        scenario = scenario_from_dict(job.scenario, source=f"job {job_id}")
        problem = dir_problem(ctx.files.root)
        if problem:  # fail now, not after the run
            raise StorageError(f"storage unavailable: results directory not writable: "
                               f"{problem}")
        results = simulate(scenario, progress=rep.progress, cancel=rep.cancel,
                           sources=UploadStore(ctx.settings.uploads_dir).sources)
        rep.progress(1.0, "writing results")
        name = ctx.files.name_for(job_id)
        results.write_hdf5(ctx.files.path(name))
        try:
            summary: dict[str, Any] = analyze(results).to_dict()
        except FlexrideError as exc:
            summary = {"error": f"{type(exc).__name__}: {exc}"}
        meta = jsonable(results.meta)
        status = "succeeded"
        done = ctx.store.finish(job_id, ctx.worker, status, summary=summary, result_file=name,
                                wall_time_s=time.perf_counter() - t0, run_meta=meta,
                                progress=1.0, message="done")
        if not done:
            status = _not_ours(ctx, job_id, name)
    except SimulationCancelled as exc:
        status = "cancelled"
        if not ctx.store.finish(job_id, ctx.worker, status, message=str(exc),
                                wall_time_s=time.perf_counter() - t0):
            status = _not_ours(ctx, job_id, None)
    except FlexrideError as exc:
        status = "failed"
        if not ctx.store.finish(job_id, ctx.worker, status, error=str(exc),
                                message=f"failed: {type(exc).__name__}",
                                wall_time_s=time.perf_counter() - t0):
            status = _not_ours(ctx, job_id, None)
    except Exception as exc:  # a bug, a time limit, or the database: record it
        log.exception("job %s failed", job_id)
        status = "failed"
        try:
            ctx.store.finish(job_id, ctx.worker, status,
                             error=f"internal error: {type(exc).__name__}: {exc}",
                             message="failed: internal error",
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


def _not_ours(ctx: JobContext, job_id: str, written: str | None) -> str:
    """The record changed under us: deleted (remove our file) or taken over."""
    job = ctx.store.get_job(job_id)
    if job is None:
        ctx.files.delete(written)
        return "deleted"
    return job.status

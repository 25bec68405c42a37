"""Job operations: create (resolve, check, reuse or queue), read, list, cancel, delete."""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import asdict
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, TypeVar

from flexride.api.deps import Services
from flexride.api.errors import Conflict, NotFound
from flexride.api.schemas import JobCreate, JobList, JobOut, JobSubmitted
from flexride.scenario.loading import resolve_scenario
from flexride.store import Job

T = TypeVar("T")

DELETING_PREFIX = ".deleting-"
"""Prefix of a result file whose job is being deleted."""


def iso(t: float | None) -> datetime | None:
    """Epoch seconds as an aware UTC datetime."""
    return None if t is None else datetime.fromtimestamp(t, tz=UTC)


def job_out(job: Any, *, operator: bool = True) -> JobOut:
    """The API view of a job record (a :class:`Job` or a row of its list columns); the
    ``worker`` that runs or ran it (its host and process id) is shown to operators only
    (requests with the API token, or any on a service without one).
    """
    out = JobOut.model_validate(job)
    return out if operator or out.worker is None else out.model_copy(update={"worker": None})


def create_job(svc: Services, body: JobCreate) -> JobSubmitted:
    """Validate, check and queue a job (or finish it at once from reused results)."""
    scenario = resolve_scenario(body.scenario, body.preset, body.overrides)
    if body.name:
        scenario = scenario.model_copy(update={"name": body.name[:80]})
    preset = body.preset or (body.scenario or {}).get("preset")
    sub = svc.submitter.submit_job(scenario, name=body.name or scenario.name,
                                   preset=preset if isinstance(preset, str) else None,
                                   reuse=body.reuse)
    return JobSubmitted.model_validate(sub.job).model_copy(
        update={"reused": sub.reused, "preflight": sub.preflight})


def validate_job(svc: Services, body: JobCreate) -> dict[str, Any]:
    """Validate and check a job request exactly as :func:`create_job` does, without creating
    anything: 200 with the run's size and the submission check, or the same 422 as a
    submission.
    """
    scenario = resolve_scenario(body.scenario, body.preset, body.overrides)
    est = svc.submitter.admit(scenario)
    return {"valid": True, "estimate": asdict(est), "preflight": svc.submitter.check(scenario)}


def get_job(svc: Services, job_id: str, *, scenario: bool = False,
            summary: bool = False) -> Job:
    """The job or :class:`NotFound`."""
    job = svc.store.get_job(job_id, scenario=scenario, summary=summary)
    if job is None:
        raise NotFound(f"no job {job_id!r}")
    return job


def finished_job(svc: Services, job_id: str, *, summary: bool = False) -> Job:
    """A job with results, or :class:`NotFound` / :class:`Conflict` saying why not."""
    job = get_job(svc, job_id, summary=summary)
    if job.status != "succeeded" or not job.result_file:
        state = {"queued": "is queued", "running": f"is running ({job.progress:.0%})",
                 "failed": "failed", "cancelled": "was cancelled"}.get(job.status, job.status)
        raise Conflict(f"job {job_id} {state}: it has no results")
    return job


def list_jobs(svc: Services, status: str | None, study_id: str | None, limit: int,
              offset: int, kind: str = "simulation", *, operator: bool = True) -> JobList:
    """A page of jobs of one kind (``all``: every kind); see :func:`job_out`."""
    items, total = svc.store.list_jobs(status=status, study_id=study_id,
                                       kind=None if kind == "all" else kind, limit=limit,
                                       offset=offset)
    return JobList(items=[job_out(j, operator=operator) for j in items], total=total,
                   limit=limit, offset=offset)


def cancel_job(svc: Services, job_id: str) -> JobOut:
    """Cancel a queued or running job (a finished one is left as it is)."""
    job = svc.store.request_cancel(job_id)
    if job is None:
        raise NotFound(f"no job {job_id!r}")
    if job.status in ("queued", "running", "cancelled"):
        svc.runner.cancel(job_id)
    return job_out(job)


def delete_job(svc: Services, job_id: str) -> None:
    """Delete a job's record and its result file (a running job is cancelled); see
    :func:`delete_records_and_files`.
    """
    job = get_job(svc, job_id)
    deleted = delete_records_and_files(svc, [job.result_file],
                                       lambda: svc.store.delete_job(job_id))
    if deleted is None:
        raise NotFound(f"no job {job_id!r}")
    if deleted.status in ("queued", "running"):
        svc.runner.cancel(job_id)
    forget_cached(svc, [job_id])


def delete_records_and_files(svc: Services, names: list[str | None],
                             delete_records: Callable[[], T]) -> T:
    """Delete records and their result files without ever leaving a record without its file
    or a file without its record: the files are first renamed aside (a read-only results
    directory fails here, with nothing changed), then the records are deleted (a refusing
    database puts the files back), then the files are removed (a crash before that leaves
    only ``.deleting-`` files, swept at the next start).
    """
    aside: list[tuple[Path, Path]] = []
    try:
        for name in names:
            pair = _set_aside(svc, name)
            if pair is not None:
                aside.append(pair)
        result = delete_records()
    except BaseException:
        for original, renamed in aside:
            os.replace(renamed, original)
        raise
    for _, renamed in aside:
        renamed.unlink(missing_ok=True)
    return result


def forget_cached(svc: Services, job_ids: list[str]) -> None:
    """Free what the read caches hold of deleted jobs (they would be dropped at the next
    sweep anyway; a deleted job is never served from them).
    """
    from flexride.api.services.result_cache import forget_job

    for job_id in job_ids:
        forget_job(svc, job_id)


def _set_aside(svc: Services, name: str | None) -> tuple[Path, Path] | None:
    """Rename result file ``name`` to ``.deleting-<name>``: (original, moved), or None when
    there is no file.
    """
    if not name or not svc.files.exists(name):
        return None
    path = svc.files.path(name)
    aside = path.with_name(f"{DELETING_PREFIX}{path.name}")
    os.replace(path, aside)
    return path, aside


def sweep_deleted(svc: Services) -> int:
    """Remove result files left aside by deletions that did not finish; return how many."""
    n = 0
    for p in svc.files.root.glob(f"{DELETING_PREFIX}*.h5"):
        p.unlink(missing_ok=True)
        n += 1
    return n

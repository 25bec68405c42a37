"""Routes of jobs: submit, list, detail, scenario, cancel, delete."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query, Request, Response

from flexride.api.deps import AUTH, ServicesDep, TokenOk
from flexride.api.params import JobId, StudyFilter
from flexride.api.schemas import JobCreate, JobList, JobOut, JobStatus, JobSubmitted
from flexride.api.services import jobs as svc_jobs
from flexride.api.services.record_cache import cached_record

router = APIRouter(prefix="/jobs", tags=["jobs"])


@router.post("", status_code=201, response_model=JobSubmitted, dependencies=AUTH,
             summary="Submit a simulation job",
             responses={401: {"description": "Bearer token missing or wrong"}})
def submit_job(body: JobCreate, svc: ServicesDep) -> JobSubmitted:
    """Submit ``{"scenario": {...}}`` or ``{"preset": NAME, "overrides": {...}}``.

    The scenario is validated (422 with field paths and allowed ranges) and checked for
    time-step stability (422 with ``dt_suggested``). An identical scenario that already ran
    is answered from its stored results (``reused: true``) unless ``reuse`` is false.
    """
    return svc_jobs.create_job(svc, body)


@router.post("/validate", response_model=dict[str, Any], dependencies=AUTH,
             summary="Validate a job request",
             responses={401: {"description": "Bearer token missing or wrong"},
                        422: {"description": "Invalid scenario, a run beyond the service's "
                              "limits or an unstable time step"}})
def validate_job(body: JobCreate, svc: ServicesDep) -> dict[str, Any]:
    """Check a job request as ``POST /jobs`` would (field validation, measured data, the
    service's limits and time-step stability), without creating a job:
    ``{"valid": true, "estimate": {...}, "preflight": {...}}`` or the same 422 as a
    submission (field paths, allowed ranges, ``dt_suggested``). Needs the token when the
    service has one (it costs CPU).
    """
    return svc_jobs.validate_job(svc, body)


@router.get("", response_model=JobList, summary="List jobs")
def list_jobs(
    request: Request,
    svc: ServicesDep,
    operator: TokenOk,
    status: Annotated[JobStatus | None, Query(description="Only jobs in this state")] = None,
    study_id: StudyFilter = None,
    kind: Annotated[Literal["simulation", "fe_export", "all"], Query(
        description="Only jobs of this kind: simulation (the default), fe_export (builds of "
        "FE exports for GET /fe) or all")] = "simulation",
    limit: Annotated[int, Query(ge=1, le=500)] = 50,
    offset: Annotated[int, Query(ge=0, le=1_000_000_000)] = 0,
) -> Any:
    """Jobs newest first, filtered by status, study and kind (simulations unless asked),
    a page at a time. ``worker`` (its host and process) needs the API token.
    """
    return cached_record(
        request, svc, "list", (status, study_id, kind, limit, offset, operator),
        lambda: svc_jobs.list_jobs(svc, status, study_id, limit, offset, kind,
                                   operator=operator))


@router.get("/{job_id}", response_model=JobOut, summary="Job detail")
def get_job(request: Request, job_id: JobId, svc: ServicesDep, operator: TokenOk) -> Any:
    """Status, progress and message, timings, attempts, error text; ``worker`` (its host
    and process) needs the API token.
    """
    return cached_record(
        request, svc, "detail", (job_id, operator),
        lambda: svc_jobs.job_out(svc_jobs.get_job(svc, job_id), operator=operator))


@router.get("/{job_id}/scenario", response_model=dict[str, Any], summary="Scenario of a job")
def get_scenario(job_id: JobId, svc: ServicesDep) -> dict[str, Any]:
    """The full validated scenario the job runs."""
    return svc_jobs.get_job(svc, job_id, scenario=True).scenario


@router.post("/{job_id}/cancel", response_model=JobOut, dependencies=AUTH,
             summary="Cancel a job",
             responses={401: {"description": "Bearer token missing or wrong"}})
def cancel_job(job_id: JobId, svc: ServicesDep) -> JobOut:
    """A queued job is cancelled at once, a running one within about a second."""
    return svc_jobs.cancel_job(svc, job_id)


@router.delete("/{job_id}", status_code=204, dependencies=AUTH, summary="Delete a job",
               responses={401: {"description": "Bearer token missing or wrong"}})
def delete_job(job_id: JobId, svc: ServicesDep) -> Response:
    """Delete the record and the result file (a running job is cancelled)."""
    svc_jobs.delete_job(svc, job_id)
    return Response(status_code=204)

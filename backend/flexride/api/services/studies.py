"""Study operations: expand and submit, read with aggregated tables, list, cancel, delete."""

from __future__ import annotations

from typing import Any

from flexride.api.deps import Services
from flexride.api.errors import NotFound
from flexride.api.schemas import StudyCreate, StudyDetail, StudyJobOut, StudyOut, StudyTables
from flexride.store import FINAL_STATUSES, Study
from flexride.study.aggregate import study_tables
from flexride.study.expand import expand_study
from flexride.study.presets import STUDY_PRESETS


def study_status(counts: dict[str, int]) -> str:
    """One word for a study from the number of its jobs per status."""
    n = sum(counts.values())
    if n == 0:
        return "empty"
    active = counts.get("queued", 0) + counts.get("running", 0)
    if active:
        return "queued" if counts.get("queued", 0) == n else "running"
    for status in FINAL_STATUSES:
        if counts.get(status, 0) == n:
            return status
    return "partial"


def study_out(study: Study, counts: dict[str, int], progress: float) -> StudyOut:
    """The API view of a study with the state of its jobs."""
    return StudyOut.model_validate(study).with_jobs_state(study_status(counts), progress,
                                                          counts)


def _progress(jobs: list[Any]) -> float:
    if not jobs:
        return 0.0
    return sum(1.0 if j.status in FINAL_STATUSES else j.progress for j in jobs) / len(jobs)


def create_study(svc: Services, body: StudyCreate) -> StudyDetail:
    """Expand the request into its job matrix, check and queue every job."""
    plan = expand_study(body.model_dump(mode="json", exclude_unset=True) | {"reuse": body.reuse},
                        svc.settings.max_study_jobs)
    study, _ = svc.submitter.submit_study(plan)
    return study_detail(svc, study.id)


def get_study(svc: Services, study_id: str) -> Study:
    """The study or :class:`NotFound`."""
    study = svc.store.get_study(study_id)
    if study is None:
        raise NotFound(f"no study {study_id!r}")
    return study


def study_detail(svc: Services, study_id: str) -> StudyDetail:
    """A study with its jobs and tables (Sperling and peaks against speed, flexible/rigid)."""
    study = get_study(svc, study_id)
    jobs = svc.store.study_jobs(study_id, summary=True)
    counts: dict[str, int] = {}
    for j in jobs:
        counts[j.status] = counts.get(j.status, 0) + 1
    tables = study_tables([{"id": j.id, "axes": j.axes or {}, "speed_kmh": j.speed_kmh,
                            "status": j.status, "summary": j.summary} for j in jobs])
    return StudyDetail.model_validate(study).with_jobs_state(
        study_status(counts), _progress(jobs), counts).model_copy(update={
            "jobs": [StudyJobOut.model_validate(j) for j in jobs],
            "tables": StudyTables.model_validate(tables)})


def list_studies(svc: Services, limit: int, offset: int) -> dict[str, Any]:
    """A page of studies with their job counts."""
    items, total = svc.store.list_studies(limit=limit, offset=offset)
    counts = svc.store.study_status_counts([s.id for s in items])
    out = []
    for s in items:
        c = counts.get(s.id, {})
        n = sum(c.values())
        done = sum(v for k, v in c.items() if k in FINAL_STATUSES)
        out.append(study_out(s, c, done / n if n else 0.0))
    return {"items": out, "total": total, "limit": limit, "offset": offset}


def cancel_study(svc: Services, study_id: str) -> StudyDetail:
    """Cancel every queued or running job of a study."""
    get_study(svc, study_id)
    for job in svc.store.study_jobs(study_id):
        if job.status in ("queued", "running"):
            svc.store.request_cancel(job.id)
            svc.runner.cancel(job.id)
    return study_detail(svc, study_id)


def delete_study(svc: Services, study_id: str) -> None:
    """Delete a study, its jobs and their result files."""
    from flexride.api.services.jobs import delete_records_and_files, forget_cached

    files = [j.result_file for j in svc.store.list_jobs(study_id=study_id, limit=100_000,
                                                        offset=0)[0]]
    study, jobs = delete_records_and_files(svc, files, lambda: svc.store.delete_study(study_id))
    if study is None:
        raise NotFound(f"no study {study_id!r}")
    for job in jobs:
        if job.status in ("queued", "running"):
            svc.runner.cancel(job.id)
    forget_cached(svc, [j.id for j in jobs])


def study_presets() -> list[dict[str, Any]]:
    """The built-in studies with the requests they stand for and their sizes."""
    out = []
    for name, req in STUDY_PRESETS.items():
        n = 1
        for key in ("conditions", "speeds_kmh", "body_models"):
            n *= len(req.get(key) or [None])
        out.append({"name": name, "description": req.get("description", ""),
                    "request": req, "n_jobs": n})
    return out


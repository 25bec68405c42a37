"""Study operations: expand and submit, read with aggregated tables, list, cancel, delete;
the report of a paper report study (its state, its build once every run has finished, its
files).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any, Literal

from flexride.api.deps import Services
from flexride.api.errors import Conflict, NotFound
from flexride.api.schemas import (
    StudyCreate,
    StudyDetail,
    StudyJobOut,
    StudyOut,
    StudyReportOut,
    StudyTables,
)
from flexride.settings import API_PREFIX
from flexride.store import FINAL_STATUSES, Job, Study
from flexride.study.aggregate import study_tables
from flexride.study.expand import expand_study
from flexride.study.presets import STUDY_PRESETS
from flexride.study.report import (
    REPORT_FILES,
    REPORT_KIND,
    REPORT_PRESET,
    report_dir,
    report_key,
)


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
                            "status": j.status, "summary": j.summary,
                            "run_meta": j.run_meta or {}} for j in jobs])
    return StudyDetail.model_validate(study).with_jobs_state(
        study_status(counts), _progress(jobs), counts).model_copy(update={
            "jobs": [StudyJobOut.model_validate(j) for j in jobs],
            "tables": StudyTables.model_validate(tables),
            "report": report_state(svc, study, jobs)})


def _report_links(study_id: str) -> dict[str, str]:
    base = f"{API_PREFIX}/studies/{study_id}/report"
    return {"html": base, "summary": f"{base}/summary"}


def _report_ready(svc: Services, study_id: str) -> Path | None:
    d = report_dir(svc.files.root, study_id)
    return d if all((d / f).is_file() for f in REPORT_FILES) else None


def report_state(svc: Services, study: Study, jobs: list[Any]) -> StudyReportOut | None:
    """The report of a paper report study (None for other studies). Once every run has
    finished (none cancelled, one at least succeeded) and no report exists or is being built,
    its build is queued: one ``paper_report`` job per study at a time; a failed build is not
    retried.
    """
    if study.preset != REPORT_PRESET:
        return None
    ready = _report_ready(svc, study.id)
    last = svc.store.latest_job(REPORT_KIND, report_key(study.id))
    if ready is not None:
        counts = (last.run_meta or {}).get("counts", {}) if last is not None else {}
        return StudyReportOut(state="ready", message="the report is ready", progress=1.0,
                              job_id=last.id if last else None, counts=counts,
                              links=_report_links(study.id))
    if last is not None and last.status in ("queued", "running", "failed", "cancelled"):
        return _report_of_job(last)
    done = sum(1 for j in jobs if j.status in FINAL_STATUSES)
    if done < len(jobs):
        return StudyReportOut(state="waiting", message=f"{done} of {len(jobs)} runs finished; "
                              "the report is built when all have")
    if any(j.status == "cancelled" for j in jobs):
        return StudyReportOut(state="failed", error="runs of the study were cancelled",
                              message="no report: the study was cancelled")
    if not any(j.status == "succeeded" for j in jobs):
        return StudyReportOut(state="failed", error="no run of the study succeeded",
                              message="no report: every run failed or was cancelled")
    job, _ = svc.submitter.submit_report(study)
    return _report_of_job(job)


#: Studies (the most recent) the reaper's pass looks at for a report to queue; an older
#: report study has its report queued when it is read.
RECENT_STUDIES = 50


def queue_due_reports(svc: Services) -> list[str]:
    """Queue the report build of every recent paper report study whose runs have all finished
    (a pass of the reaper, so that a report is built without anyone reading the study).

    Returns
    -------
    list of str
        Ids of the studies whose report is queued, being built or ready after the pass.
    """
    studies, _ = svc.store.list_studies(limit=RECENT_STUDIES)
    due = []
    for study in studies:
        if study.preset != REPORT_PRESET or _report_ready(svc, study.id) is not None:
            continue
        rep = report_state(svc, study, svc.store.study_jobs(study.id))
        if rep is not None and rep.state in ("queued", "running", "ready"):
            due.append(study.id)
    return due


def _report_of_job(job: Job) -> StudyReportOut:
    if job.status in ("queued", "running"):
        state: Literal["queued", "running"] = "queued" if job.status == "queued" else "running"
        return StudyReportOut(state=state, message=job.message or "building the report",
                              progress=job.progress, job_id=job.id)
    return StudyReportOut(state="failed", job_id=job.id, message=f"the report's build {job.status}",
                          error=job.error or job.status)


def report_file(svc: Services, study_id: str, name: str) -> Path:
    """A file of a study's report (``index.html`` or ``summary.json``).

    Raises
    ------
    NotFound
        No such study, or not a paper report study.
    Conflict
        The report is not ready (the message says what it waits for).
    """
    study = get_study(svc, study_id)
    if study.preset != REPORT_PRESET:
        raise NotFound(f"study {study_id} is not a paper report study (preset "
                       f"{REPORT_PRESET!r}): it has no report")
    ready = _report_ready(svc, study.id)
    if ready is None:
        st = report_state(svc, study, svc.store.study_jobs(study.id))
        why = st.error or st.message if st is not None else ""
        raise Conflict(f"the report of study {study_id} is not ready ({st.state if st else ''}"
                       f": {why})")
    return ready / name


def report_summary(svc: Services, study_id: str) -> Any:
    """The claims of a study's report (``summary.json``)."""
    return json.loads(report_file(svc, study_id, "summary.json").read_text(encoding="utf-8"))


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
    """Cancel every queued or running job of a study (and the build of its report)."""
    study = get_study(svc, study_id)
    jobs = svc.store.study_jobs(study_id)
    if study.preset == REPORT_PRESET:
        report = svc.store.latest_job(REPORT_KIND, report_key(study_id))
        jobs += [report] if report is not None else []
    for job in jobs:
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
    if study.preset == REPORT_PRESET:
        _delete_report(svc, study.id)
    for job in jobs:
        if job.status in ("queued", "running"):
            svc.runner.cancel(job.id)
    forget_cached(svc, [j.id for j in jobs])


def _delete_report(svc: Services, study_id: str) -> None:
    """Remove a report study's report files and its report jobs (cancelled if active)."""
    for _ in range(1000):  # one job per build; a failed build is rebuilt only on request
        job = svc.store.latest_job(REPORT_KIND, report_key(study_id))
        if job is None:
            break
        if job.status in ("queued", "running"):
            svc.store.request_cancel(job.id)
            svc.runner.cancel(job.id)
        svc.store.delete_job(job.id)
    shutil.rmtree(report_dir(svc.files.root, study_id), ignore_errors=True)


def study_presets() -> list[dict[str, Any]]:
    """The built-in studies with the requests they stand for and their sizes."""
    from flexride.study.report import expand_report_size

    out = []
    for name, req in STUDY_PRESETS.items():
        n = 1
        for key in ("conditions", "speeds_kmh", "body_models"):
            n *= len(req.get(key) or [None])
        if name == REPORT_PRESET:
            n = expand_report_size(req)
        out.append({"name": name, "description": req.get("description", ""),
                    "request": req, "n_jobs": n})
    return out


"""Run a study's jobs in this process, one after the other: the command line's way to a study
(``flexride fe convergence … --response``), with the same plan
(:func:`flexride.study.expand.expand_study`), the same per-job summary
(:func:`flexride.study.sections.job_summary`) and the same tables
(:func:`flexride.study.aggregate.study_tables`) as the service's studies.

No results file is written: what the tables need (the summary and the run's metadata) is kept
in memory, one job at a time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from flexride.analysis._common import jsonable
from flexride.solver import simulate
from flexride.study.expand import StudyPlan
from flexride.study.sections import job_summary

__all__ = ["JobProgress", "run_plan"]

JobProgress = Callable[[int, int, float, str], None]
"""``progress(job_index, n_jobs, fraction_of_job, message)``."""


def run_plan(plan: StudyPlan, progress: JobProgress | None = None) -> list[dict[str, Any]]:
    """Simulate every job of ``plan`` and analyse it as a study job would be.

    Parameters
    ----------
    plan : StudyPlan
        The expanded study.
    progress : callable, optional
        Told each job's progress (:data:`JobProgress`).

    Returns
    -------
    list of dict
        One per job, as :func:`~flexride.study.aggregate.study_tables` reads them: ``id``
        (``job-<index>``), ``name``, ``axes``, ``speed_kmh``, ``status`` (``succeeded``),
        ``summary`` and ``run_meta`` (the run's metadata with its ``section``).

    Raises
    ------
    FlexrideError
        A job's scenario cannot be simulated (the error of that job, unchanged).
    """
    done = []
    n = len(plan.jobs)
    for job in plan.jobs:
        def report(fraction: float, message: str, _i: int = job.index) -> None:
            if progress is not None:
                progress(_i, n, fraction, message)

        results = simulate(job.scenario, progress=report)
        meta = jsonable(results.meta)
        if job.section:
            meta["section"] = job.section
        done.append({"id": f"job-{job.index}", "name": job.name, "axes": job.axes,
                     "speed_kmh": job.scenario.speed_kmh, "status": "succeeded",
                     "summary": job_summary(results, job.section), "run_meta": meta})
        report(1.0, "done")
    return done

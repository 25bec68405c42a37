"""The one Celery task: run a job of the job store by its id."""

from __future__ import annotations

from flexride.jobs.celery_app import app, job_context
from flexride.jobs.celery_config import TASK_NAME


@app.task(name=TASK_NAME, acks_late=True, reject_on_worker_lost=True, ignore_result=True)
def run_job(job_id: str) -> str:
    """Claim job ``job_id`` and run it (:func:`flexride.study.run_job.claim_and_run`).

    Returns the final status, or why the job was not run (already done, cancelled, running on
    another live worker).
    """
    from flexride.study.run_job import claim_and_run

    return claim_and_run(job_id, job_context())

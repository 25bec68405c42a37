"""Celery application of flexride's workers (``flexride worker``).

:mod:`worker.app` configures Celery from the service settings (:mod:`flexride.settings`,
:mod:`flexride.jobs.celery_config`); :mod:`worker.tasks` holds the one task, a thin call of
:func:`flexride.study.run_job.claim_and_run`.
"""

"""Celery configuration for long CPU-bound jobs, and the worker app built from it."""

from __future__ import annotations

from flexride.jobs.celery_config import TASK_NAME, celery_config
from service.svc_testkit import REPO, make_settings


def test_settings_fit_long_cpu_bound_jobs(tmp_path):
    s = make_settings(tmp_path, broker_url="redis://127.0.0.1:6379/0", job_time_limit_s=7200,
                      workers=3, worker_max_memory_mb=1000, celery_queue="q")
    c = celery_config(s)
    assert c["task_serializer"] == c["result_serializer"] == "json"
    assert c["accept_content"] == ["json"] and c["result_backend"] is None
    assert c["task_acks_late"] and c["task_reject_on_worker_lost"]
    assert c["worker_prefetch_multiplier"] == 1 and c["worker_concurrency"] == 3
    assert c["broker_transport_options"]["visibility_timeout"] > c["task_time_limit"] == 7200
    assert c["task_soft_time_limit"] < c["task_time_limit"]
    assert c["worker_max_memory_per_child"] == 1000 * 1024  # KiB
    assert c["task_default_queue"] == "q"


def test_worker_app_registers_the_one_task(monkeypatch):
    monkeypatch.setenv("FLEXRIDE_BROKER_URL", "redis://127.0.0.1:6379/9")
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                "NUMBA_NUM_THREADS"):  # restored after the test (the app sets them)
        monkeypatch.setenv(var, "1")
    monkeypatch.syspath_prepend(str(REPO))  # worker/ is a top-level package of the repo
    from flexride.settings import get_settings

    get_settings.cache_clear()
    try:
        from flexride.jobs.celery_app import app
        from flexride.jobs.celery_tasks import run_job

        assert run_job.name == TASK_NAME and TASK_NAME in app.tasks
        assert run_job.acks_late and run_job.reject_on_worker_lost
        assert app.conf.accept_content == ["json"]
    finally:
        get_settings.cache_clear()

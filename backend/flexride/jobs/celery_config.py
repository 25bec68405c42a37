"""Celery configuration for long CPU-bound simulation jobs, shared by the API (client) and
the workers (``worker/app.py``).

* JSON only (serializer and accepted content): no pickle on the wire;
* ``acks_late`` with ``reject_on_worker_lost``: a message is acknowledged after the job, and
  a worker child that dies puts it back in the queue (the job store bounds the retries);
* prefetch 1: a worker holds no job it is not running;
* broker visibility timeout longer than the longest job (the hard time limit plus an hour), so
  Redis does not hand a running job to a second worker;
* hard and soft time limits; a memory limit per child;
* no result backend: the job store is where states and results live.
"""

from __future__ import annotations

from typing import Any

from flexride.settings import Settings

TASK_NAME = "flexride.run_job"
"""Name of the one task: ``run_job(job_id)``."""


def celery_config(settings: Settings) -> dict[str, Any]:
    """Celery settings (``app.conf.update(...)``) for ``settings``."""
    hard = float(settings.job_time_limit_s)
    visibility = int(hard + 3600)
    return {
        "broker_url": settings.broker_url,
        "broker_connection_retry_on_startup": True,
        "broker_connection_timeout": 4.0,
        "broker_transport_options": {"visibility_timeout": visibility},
        "broker_heartbeat": 0,
        "result_backend": None,
        "task_ignore_result": True,
        "task_serializer": "json",
        "result_serializer": "json",
        "event_serializer": "json",
        "accept_content": ["json"],
        "result_accept_content": ["json"],
        "task_acks_late": True,
        "task_reject_on_worker_lost": True,
        "task_acks_on_failure_or_timeout": True,
        "worker_prefetch_multiplier": 1,
        "worker_concurrency": settings.workers,
        "worker_max_memory_per_child": int(settings.worker_max_memory_mb) * 1024,  # KiB
        "worker_cancel_long_running_tasks_on_connection_loss": False,
        "worker_disable_rate_limits": True,
        "worker_send_task_events": False,
        "task_time_limit": hard,
        "task_soft_time_limit": hard * 0.95,
        "task_default_queue": settings.celery_queue,
        "task_create_missing_queues": True,
        "task_publish_retry": True,
        "task_publish_retry_policy": {"max_retries": 2, "interval_start": 0.0,
                                      "interval_step": 0.5, "interval_max": 1.0},
        "timezone": "UTC",
        "enable_utc": True,
    }

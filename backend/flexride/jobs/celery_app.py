"""The Celery app: configuration from ``FLEXRIDE_*`` settings, numba warm-up before the pool
forks, one job context per worker child.

Start it with ``flexride worker`` (or ``celery -A flexride.jobs.celery_app worker``); its one
task is in :mod:`flexride.jobs.celery_tasks`.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

from celery import Celery, signals

from flexride.jobs.celery_config import celery_config
from flexride.jobs.warmup import single_threaded_env
from flexride.settings import get_settings

if TYPE_CHECKING:
    from flexride.study.run_job import JobContext

single_threaded_env()

log = logging.getLogger("flexride.worker")

app = Celery("flexride", include=["flexride.jobs.celery_tasks"])
app.conf.update(celery_config(get_settings()))

_state: dict[str, JobContext] = {}


@signals.worker_init.connect
def _warm_before_fork(**_kwargs) -> None:
    """Compile or load the numba kernels in the parent, so every forked child has them."""
    from flexride.jobs.warmup import limit_blas_threads, warm_numba

    limit_blas_threads(1)
    warm_numba()


@signals.worker_process_init.connect
def _child_started(**_kwargs) -> None:
    """Create this child's job context (its own database engine) and report it as seen."""
    from flexride.jobs.presence import Presence, worker_name
    from flexride.study.run_job import JobContext

    settings = get_settings()
    ctx = JobContext.from_settings(settings, worker_name("celery"))
    ctx.presence = Presence(ctx.store, ctx.worker, "celery",
                            settings.heartbeat_interval_s).start()
    _state["ctx"] = ctx


@signals.worker_process_shutdown.connect
def _child_stopping(**_kwargs) -> None:
    ctx = _state.pop("ctx", None)
    if ctx is not None and ctx.presence is not None:
        ctx.presence.stop()


def job_context() -> JobContext:
    """The :class:`~flexride.study.run_job.JobContext` of this child (made on first use)."""
    ctx = _state.get("ctx")
    if ctx is None:  # e.g. the solo pool, where worker_process_init is not sent
        _child_started()
        ctx = _state["ctx"]
    return ctx

"""Choose the runner from the settings: embedded pool, Celery client, or none."""

from __future__ import annotations

from flexride.jobs.base import JobRunner, NullRunner
from flexride.settings import Settings
from flexride.store import JobStore


def make_runner(settings: Settings, store: JobStore) -> JobRunner:
    """The runner named by ``settings.effective_runner`` (not started)."""
    kind = settings.effective_runner
    if kind == "embedded":
        from flexride.jobs.embedded import EmbeddedRunner

        return EmbeddedRunner(settings, store)
    if kind == "celery":
        from flexride.jobs.celery_runner import CeleryRunner

        return CeleryRunner(settings, store)
    return NullRunner()

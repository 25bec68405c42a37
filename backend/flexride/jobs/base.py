"""The job runner interface: how the API hands jobs to workers.

A runner never runs a simulation in the API process. Jobs are records in the job store; a
runner only makes sure that some worker process picks each queued job up, and offers a
best-effort way to stop one (the store's cancel flag is what the solver obeys). Two
implementations: :class:`~flexride.jobs.embedded.EmbeddedRunner` (a pool of worker processes
on this machine) and :class:`~flexride.jobs.celery_runner.CeleryRunner` (Celery workers via a
broker). :class:`NullRunner` only records jobs.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Sequence
from typing import Any


class JobRunner(ABC):
    """Dispatches queued jobs to workers."""

    kind: str = "base"

    @abstractmethod
    def start(self) -> None:
        """Start the runner (worker processes, broker connection); called once."""

    @abstractmethod
    def stop(self) -> None:
        """Stop the runner; jobs interrupted by the stop are queued again."""

    @abstractmethod
    def submit(self, job_ids: Sequence[str]) -> None:
        """Make sure workers will run these queued jobs (never raises for a broker outage:
        the jobs stay queued and are dispatched again later).
        """

    def cancel(self, job_id: str) -> None:  # noqa: B027 - optional hook
        """Help stopping a job beyond the store's cancel flag (e.g. revoke its message)."""

    def redispatch(self) -> int:
        """Dispatch again the jobs that may have been lost by the transport; return how many."""
        return 0

    @abstractmethod
    def status(self) -> dict[str, Any]:
        """Health of the runner: ``{"kind", "ok", "detail", ...}``."""


class NullRunner(JobRunner):
    """Records jobs and runs none of them (``FLEXRIDE_RUNNER=none``: another process, e.g. a
    separately started worker, takes them, or tests that only exercise the API).
    """

    kind = "none"

    def start(self) -> None:
        """Load the solver's kernels for the submission check (compiled here if needed,
        :data:`flexride.jobs.warmup.SOLVER`); nothing else to start.
        """
        from flexride.jobs.warmup import SOLVER

        SOLVER.start(compile_here=True)

    def stop(self) -> None:
        """End a compilation started by :meth:`start`."""
        from flexride.jobs.warmup import SOLVER

        SOLVER.stop()

    def submit(self, job_ids: Sequence[str]) -> None:
        """Leave the jobs queued."""

    def status(self) -> dict[str, Any]:
        """Always healthy: there is nothing to check."""
        return {"kind": self.kind, "ok": True, "detail": "jobs are recorded, not run"}

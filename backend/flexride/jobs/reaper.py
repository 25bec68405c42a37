"""Recovery of jobs whose worker was lost, run periodically in the API process.

A running job whose heartbeat is older than ``heartbeat_timeout_s`` lost its worker (killed,
machine gone, network cut): it is queued again and re-dispatched while attempts remain, and
marked failed with the reason otherwise. The runner is also asked to re-dispatch jobs a
transport may have lost (a broker restarted without persistence). Then the ``hooks`` run:
periodic work of the service registered by the API (e.g. queueing the report of a finished
paper report study).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any

from flexride.jobs.base import JobRunner
from flexride.jobs.fault_log import FaultLog
from flexride.settings import Settings
from flexride.store import JobStore, now

log = logging.getLogger(__name__)

_FORGET_WORKERS_AFTER_S = 24 * 3600.0


class Reaper:
    """Periodic recovery of lost jobs (daemon thread).

    Parameters
    ----------
    store : JobStore
        The job store.
    runner : JobRunner
        Where requeued jobs are dispatched.
    settings : Settings
        ``heartbeat_timeout_s`` and ``reaper_interval_s``.
    """

    def __init__(self, store: JobStore, runner: JobRunner, settings: Settings):
        self.store, self.runner, self.settings = store, runner, settings
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self.last: dict[str, Any] = {}
        #: Called after every pass, each on its own (a failing hook is logged).
        self.hooks: list[Callable[[], object]] = []
        self.faults = FaultLog(log, "reaper pass")
        self._hook_faults: dict[int, FaultLog] = {}

    def run_once(self) -> dict[str, Any]:
        """One pass: requeue or fail stale jobs, re-dispatch; return what was done."""
        timeout = self.settings.heartbeat_timeout_s
        requeued, failed = [], []
        for job in self.store.stale_running(now() - timeout):
            reason = f"no heartbeat from its worker for more than {timeout:g} s"
            status = self.store.worker_lost(job.id, job.worker or "", reason)
            if status == "queued":
                requeued.append(job.id)
            elif status is not None:
                failed.append(job.id)
            if status is not None:
                log.warning("job %s: %s (worker %s) -> %s", job.id, reason, job.worker, status)
        if requeued:
            self.runner.submit(requeued)
        redispatched = self.runner.redispatch()
        self.store.forget_workers(now() - _FORGET_WORKERS_AFTER_S)
        self.last = {"requeued": requeued, "failed": failed, "redispatched": redispatched,
                     "at": now()}
        for hook in self.hooks:
            faults = self._hook_faults.setdefault(
                id(hook), FaultLog(log, f"reaper hook {getattr(hook, '__name__', hook)}"))
            try:
                hook()
            except Exception as exc:
                faults.failed(exc)
            else:
                faults.succeeded()
        return self.last

    def run_logged(self) -> None:
        """One pass whose failure is logged once per change of its reason (a database that
        refuses writes fails every pass: one line, not a traceback every few seconds).
        """
        try:
            self.run_once()
        except Exception as exc:
            self.faults.failed(exc)
        else:
            self.faults.succeeded()

    def start(self) -> Reaper:
        """Start the periodic thread."""
        self._thread = threading.Thread(target=self._loop, name="flexride-reaper", daemon=True)
        self._thread.start()
        return self

    def _loop(self) -> None:
        while not self._stop.wait(self.settings.reaper_interval_s):
            self.run_logged()

    def stop(self) -> None:
        """Stop the thread."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(2.0)

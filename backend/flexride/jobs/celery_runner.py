"""The Celery runner (client side): queued jobs become messages on the broker, taken by
``flexride worker`` processes on any machine that shares the database and the results.

The message carries only the job id; the worker reads the scenario from the job store. Sending
never fails a request: if the broker is down the job stays queued and is sent again by the
reaper when the broker is back. A broker restart without persistence loses messages, not jobs:
the runner notices the restart (Redis ``run_id``) and sends every queued job again; duplicate
messages are harmless because a worker runs a job only after claiming its record.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Sequence
from typing import Any

from celery import Celery

from flexride.jobs.base import JobRunner
from flexride.jobs.celery_config import TASK_NAME, celery_config
from flexride.settings import Settings, url_location
from flexride.store import JobStore

log = logging.getLogger(__name__)

KIND = "celery"


def make_client(settings: Settings) -> Celery:
    """A Celery app configured for ``settings`` that only sends tasks."""
    app = Celery("flexride-client", set_as_current=False)
    app.conf.update(celery_config(settings))
    return app


class CeleryRunner(JobRunner):
    """Dispatch jobs to Celery workers through the broker of ``settings.broker_url``."""

    kind = KIND

    def __init__(self, settings: Settings, store: JobStore):
        if not settings.broker_url:
            raise ValueError("the Celery runner needs FLEXRIDE_BROKER_URL")
        self.broker_url: str = settings.broker_url
        self.settings = settings
        self.store = store
        self.app = make_client(settings)
        self._pending: set[str] = set()
        self._lock = threading.Lock()
        self._run_id: str | None = None

    def start(self) -> None:
        """Load (compiling in a child process if needed) the solver's kernels for the
        submission check, and send the jobs queued while the API was down (duplicates are
        harmless).
        """
        from flexride.jobs.warmup import SOLVER

        SOLVER.start(compile_here=True)
        self._run_id = self._broker_run_id()
        queued = self.store.queued_ids(KIND)
        if queued:
            log.info("celery runner: re-sending %d queued job(s)", len(queued))
            self.submit(queued)

    def stop(self) -> None:
        """End a compilation started by :meth:`start`; close the broker connections."""
        from flexride.jobs.warmup import SOLVER

        SOLVER.stop()
        try:
            self.app.close()
        except Exception:  # pragma: no cover - best effort
            pass

    def submit(self, job_ids: Sequence[str]) -> None:
        """Send one message per job; jobs that could not be sent are retried later."""
        failed = []
        for job_id in job_ids:
            try:
                self.app.send_task(TASK_NAME, args=[job_id], task_id=job_id,
                                   queue=self.settings.celery_queue)
            except Exception as exc:
                log.warning("celery runner: cannot send job %s (%s); will retry", job_id, exc)
                failed.append(job_id)
        with self._lock:
            self._pending.difference_update(set(job_ids) - set(failed))
            self._pending.update(failed)

    def cancel(self, job_id: str) -> None:
        """Revoke the job's message (a worker that already runs it stops through the store).

        Sent from a background thread: a broker outage must not hold up the request (the
        store's cancel flag is what counts; the revocation only saves a worker the claim).
        """

        def revoke() -> None:
            try:
                self.app.control.revoke(job_id)
            except Exception as exc:
                log.warning("celery runner: cannot revoke %s: %s", job_id, exc)

        threading.Thread(target=revoke, name=f"revoke-{job_id[:8]}", daemon=True).start()

    def redispatch(self) -> int:
        """Send again the jobs that failed to send, and all queued jobs after a broker restart."""
        run_id = self._broker_run_id()
        restarted = run_id is not None and self._run_id is not None and run_id != self._run_id
        if run_id is not None:
            self._run_id = run_id
        queued = set(self.store.queued_ids(KIND))
        with self._lock:
            todo = queued if restarted else (self._pending & queued)
            self._pending &= queued
        if restarted:
            log.warning("celery runner: the broker restarted; re-sending %d queued job(s)",
                        len(todo))
        if todo and run_id is not None:
            self.submit(sorted(todo))
            return len(todo)
        return 0

    def _redis(self):
        import redis

        return redis.Redis.from_url(self.broker_url, socket_timeout=2.0,
                                    socket_connect_timeout=2.0)

    def _broker_run_id(self) -> str | None:
        """Redis's ``run_id`` (changes when the server restarts); None if unknown/unreachable."""
        if not self.broker_url.startswith(("redis://", "rediss://")):
            return None
        try:
            client = self._redis()
            try:
                return str(client.info("server").get("run_id"))
            finally:
                client.close()
        except Exception:
            return None

    def status(self) -> dict[str, Any]:
        """Broker reachability and the number of messages waiting in the queue."""
        url = url_location(self.broker_url)
        info: dict[str, Any] = {"kind": self.kind, "broker": url}
        try:
            if self.broker_url.startswith(("redis://", "rediss://")):
                client = self._redis()
                try:
                    client.ping()
                    info["queue_length"] = int(client.llen(self.settings.celery_queue))
                finally:
                    client.close()
            else:
                with self.app.connection_for_write() as conn:
                    conn.ensure_connection(max_retries=1, timeout=2)
            info.update(ok=True, detail="broker reachable")
        except Exception as exc:
            info.update(ok=False, detail=f"broker unreachable: {type(exc).__name__}: {exc}")
        with self._lock:
            info["pending_dispatch"] = len(self._pending)
        return info

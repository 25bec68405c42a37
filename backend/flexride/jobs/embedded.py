"""The embedded runner: a pool of worker processes on this machine, fed by the job store.

``flexride serve`` without a broker starts this. Each worker process (``spawn``: a clean
interpreter, no threads or connections inherited from the API) compiles the numba kernels once,
then claims the oldest queued job from the store, runs it (:mod:`flexride.study.run_job`) and
repeats. Queued jobs survive an API restart because the queue *is* the store. A supervisor
thread in the API process replaces a worker process that dies and requeues (or fails, after
``max_attempts``) the job it was running; on a clean shutdown the interrupted jobs are queued
again without counting an attempt.
"""

from __future__ import annotations

import logging
import multiprocessing as mp
import os
import signal
import threading
import time
from collections.abc import Sequence
from typing import Any

from flexride.jobs.base import JobRunner
from flexride.jobs.presence import hostname, worker_is_dead, worker_name
from flexride.settings import Settings
from flexride.store import JobStore, now

log = logging.getLogger(__name__)

KIND = "embedded"
_IDLE_POLL_S = 1.0
_QUICK_DEATH_S = 30.0
_MAX_BACKOFF_S = 60.0
_GROUP_STOP_GRACE_S = 2.0
_STOP_SIGNALS = {signal.SIGINT, signal.SIGTERM}


class _Termination:
    """How a worker ends on SIGTERM.

    Busy (claiming or running a job), the handler raises ``SystemExit``, so ``finally``
    blocks and finalizers run (presence record, multiprocessing semaphores) and a job being
    run stays ``running`` for the API (or the next start) to queue again. Idle (waiting on the
    runner's events), it only notes the request: an exception raised inside a
    multiprocessing ``Event.wait`` unwinds its condition's lock half-acquired ("semaphore or
    lock released too many times", exit code 1); the wait returns within its poll interval
    and the loop then ends.
    """

    def __init__(self) -> None:
        self.idle = False
        self.requested = False

    def handle(self, _signum: int, _frame: Any) -> None:
        """The SIGTERM handler."""
        signal.signal(signal.SIGTERM, signal.SIG_IGN)  # a second one must not cut the clean-up
        self.requested = True
        if not self.idle:
            raise SystemExit(0)

    def wait(self, event: Any, timeout: float) -> bool:
        """``event.wait(timeout)`` during which a SIGTERM only notes the request."""
        self.idle = True
        try:
            return bool(event.wait(timeout))
        finally:
            self.idle = False


def _exit_cleanly_on_signals() -> _Termination:
    """In a worker: Ctrl-C (SIGINT to the terminal's process group) is left to the API
    process, which stops its workers; SIGTERM ends the worker (:class:`_Termination`).
    """
    termination = _Termination()
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, termination.handle)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, _STOP_SIGNALS)  # blocked by _spawn until now
    return termination


def worker_main(settings_data: dict[str, Any], wake: Any, stop: Any, parent_pid: int) -> None:
    """Body of one embedded worker process: claim queued jobs and run them until stopped.

    Parameters
    ----------
    settings_data : dict
        The service settings (``Settings.model_dump()``), so the worker sees exactly the
        API's configuration.
    wake, stop : multiprocessing.Event
        Set by the API on new jobs / to stop.
    parent_pid : int
        The API process; the worker exits after its current job if that process is gone.
    """
    from flexride.jobs.fault_log import FaultLog
    from flexride.jobs.presence import Presence
    from flexride.jobs.warmup import limit_blas_threads, warm_numba
    from flexride.study.run_job import JobContext, claimed_job, run_claimed

    termination = _exit_cleanly_on_signals()
    logging.basicConfig(level=str(settings_data.get("log_level", "info")).upper(),
                        format="%(asctime)s %(levelname)s [%(processName)s] %(message)s")
    limit_blas_threads(1)  # NumPy was imported while this module loaded
    settings = Settings.model_validate(settings_data)
    name = worker_name(KIND)
    ctx = JobContext.from_settings(settings, name)
    ctx.presence = Presence(ctx.store, name, KIND, settings.heartbeat_interval_s).start()
    warm_numba()
    claims = FaultLog(log, f"{name}: claiming a job")
    try:
        while (not stop.is_set() and not termination.requested
               and os.getppid() == parent_pid):
            try:
                claim = ctx.store.claim_next(
                    KIND, name, stale_before=now() - settings.heartbeat_timeout_s,
                    dead=worker_is_dead)
            except Exception as exc:  # database briefly unavailable
                claims.failed(exc)
                termination.wait(stop, _IDLE_POLL_S)
                continue
            claims.succeeded()
            if claim is None:
                if termination.wait(wake, _IDLE_POLL_S):
                    wake.clear()
                continue
            if claim.claimed:
                run_claimed(claimed_job(claim), ctx)
    finally:
        ctx.presence.stop()


class EmbeddedRunner(JobRunner):
    """A supervised pool of ``settings.workers`` worker processes on this machine.

    Parameters
    ----------
    settings : Settings
        Pool size, database, results directory, heartbeat settings.
    store : JobStore
        The API process's store (for recovery of jobs whose worker died).
    """

    kind = KIND

    def __init__(self, settings: Settings, store: JobStore):
        self.settings = settings
        self.store = store
        self._ctx = mp.get_context("spawn")
        self._wake = self._ctx.Event()
        self._stop = self._ctx.Event()
        self._procs: list[Any] = []
        self._lock = threading.Lock()
        self._stopping = threading.Event()
        self._supervisor: threading.Thread | None = None
        self._started: list[float] = []
        self._failures: list[int] = []
        self._restart_at: list[float] = []
        self.restarts = 0

    # -- lifecycle ----------------------------------------------------------------------------

    def start(self) -> None:
        """Recover jobs of dead local workers, start the processes and their supervisor.

        The worker processes inherit one-thread BLAS/numba settings (set here, before they
        start, because they import NumPy before their own code runs).
        """
        from flexride.jobs.warmup import SOLVER, single_threaded_env

        single_threaded_env()
        SOLVER.start(compile_here=False)  # the workers compile; the API loads what they made
        self._recover_dead()
        with self._lock:
            self._procs = [self._spawn(i) for i in range(self.settings.workers)]
            self._failures = [0] * len(self._procs)
            self._restart_at = [0.0] * len(self._procs)
        self._supervisor = threading.Thread(target=self._supervise, name="flexride-supervisor",
                                            daemon=True)
        self._supervisor.start()
        log.info("embedded runner: %d worker process(es)", self.settings.workers)

    def _spawn(self, slot: int):
        while len(self._started) <= slot:
            self._started.append(0.0)
        self._started[slot] = time.monotonic()
        p = self._ctx.Process(
            target=worker_main,
            args=(self.settings.model_dump(mode="json"), self._wake, self._stop, os.getpid()),
            name=f"flexride-worker-{slot}",
            daemon=False,
        )
        # the new process starts with SIGINT and SIGTERM blocked (the mask is inherited), so a
        # stop signal that arrives while it still imports waits for worker_main's handlers
        mask = signal.pthread_sigmask(signal.SIG_BLOCK, _STOP_SIGNALS)
        try:
            p.start()
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        return p

    def _recover_dead(self) -> None:
        """Requeue or fail jobs left running by embedded workers of this host that are gone."""
        for job in self.store.running_jobs(KIND):
            if job.worker and worker_is_dead(job.worker):
                self._lost(job.id, job.worker, "its worker process is gone")

    def _lost(self, job_id: str, worker: str, reason: str) -> None:
        status = self.store.worker_lost(job_id, worker, reason)
        log.warning("job %s: %s (worker %s) -> %s", job_id, reason, worker, status)
        if status == "queued":
            self._wake.set()

    def _supervise(self) -> None:
        while not self._stopping.wait(0.5):
            with self._lock:
                for i, p in enumerate(self._procs):
                    if p.is_alive() or self._stopping.is_set() or self._group_stop(p):
                        continue
                    if self._restart_at[i] == 0.0:
                        self._handle_death(i, p)
                    if time.monotonic() >= self._restart_at[i]:
                        self._procs[i] = self._spawn(i)
                        self._restart_at[i] = 0.0
                        self.restarts += 1

    def _group_stop(self, p: Any) -> bool:
        """Whether a worker ended by a signal (or cleanly) while the service itself is being
        stopped: SIGTERM or Ctrl-C to the whole process group reaches the workers a moment
        before the API sets ``_stopping``; wait up to ``_GROUP_STOP_GRACE_S`` for it rather
        than report a death and start a new worker.
        """
        if p.exitcode not in (0, -signal.SIGTERM, -signal.SIGINT):
            return False
        return self._stopping.wait(_GROUP_STOP_GRACE_S)

    def _handle_death(self, i: int, p) -> None:
        """Recover the dead process's job and schedule its restart (backing off when a
        process keeps dying right after it starts).
        """
        name = worker_name(KIND, p.pid)
        reason = f"its worker process died (exit code {p.exitcode})"
        log.error("embedded runner: worker process %s died (exit code %s)", p.pid, p.exitcode)
        try:
            for job in self.store.running_on([name]):
                self._lost(job.id, name, reason)
            self.store.worker_gone(name)
        except Exception:
            log.exception("embedded runner: recovery after %s failed", reason)
        lived = time.monotonic() - self._started[i]
        self._failures[i] = self._failures[i] + 1 if lived < _QUICK_DEATH_S else 0
        delay = min(_MAX_BACKOFF_S, 2.0 ** self._failures[i]) if self._failures[i] else 0.0
        self._restart_at[i] = time.monotonic() + delay

    def stop(self) -> None:
        """Stop the processes (a running job is interrupted and queued again)."""
        from flexride.jobs.warmup import SOLVER

        SOLVER.stop()
        self._stopping.set()
        self._stop.set()
        self._wake.set()
        with self._lock:
            procs = list(self._procs)
        for p in procs:
            if p.is_alive():
                p.terminate()
        for p in procs:
            p.join(5.0)
            if p.is_alive():
                p.kill()
                p.join(2.0)
        for p in procs:
            name = worker_name(KIND, p.pid)
            try:
                if self.store.requeue_interrupted(name, "interrupted by a service stop"):
                    log.info("embedded runner: requeued the job of %s", name)
                self.store.worker_gone(name)
            except Exception:
                log.exception("embedded runner: cannot requeue the jobs of %s", name)
        if self._supervisor is not None:
            self._supervisor.join(2.0)

    # -- dispatch -----------------------------------------------------------------------------

    def submit(self, job_ids: Sequence[str]) -> None:
        """Wake the worker processes (they take queued jobs from the store)."""
        self._wake.set()

    def redispatch(self) -> int:
        """Wake the workers if jobs are waiting (nothing can be lost in transit here)."""
        n = len(self.store.queued_ids(KIND))
        if n:
            self._wake.set()
        return n

    def status(self) -> dict[str, Any]:
        """Processes alive out of the pool size, and restarts so far."""
        with self._lock:
            alive = [p.pid for p in self._procs if p.is_alive()]
        n = self.settings.workers
        return {"kind": self.kind, "ok": len(alive) == n and not self._stopping.is_set(),
                "detail": f"{len(alive)} of {n} worker process(es) alive on {hostname()}",
                "processes": alive, "restarts": self.restarts}

"""A service stop ends idle embedded workers cleanly: exit code 0, no traceback.

SIGTERM used to raise ``SystemExit`` wherever it landed; in an idle worker that is inside a
multiprocessing ``Event.wait``, whose condition's lock the exception left half-acquired
("semaphore or lock released too many times", exit code 1). Idle workers now only note the
request and leave their loop. (The race depends on where the signal lands: before the change
this test failed in one run of six on the 2-core machine; it cannot pass by accident after.)
"""

from __future__ import annotations

import os
from pathlib import Path

from flexride.jobs.embedded import EmbeddedRunner
from flexride.store import JobStore
from service.svc_testkit import make_settings, wait_for


def _cpu_ticks(pid: int) -> int:
    """User + system CPU time of process ``pid`` (clock ticks)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return int(fields[11]) + int(fields[12])


class _Idle:
    """True once process ``pid`` used no CPU between two calls (its worker waits for jobs:
    it has loaded its kernels and found the queue empty)."""

    def __init__(self, pid: int):
        self.pid, self.last = pid, -1

    def __call__(self) -> bool:
        ticks = _cpu_ticks(self.pid)
        idle, self.last = ticks == self.last, ticks
        return idle


def test_idle_workers_stop_with_exit_code_zero(tmp_path):
    settings = make_settings(tmp_path, runner="embedded", workers=2, heartbeat_interval_s=5.0)
    store = JobStore.from_url(settings.effective_database_url, create=True)
    runner = EmbeddedRunner(settings, store)
    runner.start()
    try:
        procs = list(runner._procs)
        for p in procs:
            wait_for(_Idle(p.pid), 300.0, 0.5, f"worker {p.pid} to wait for jobs")
    finally:
        runner.stop()
    assert [p.exitcode for p in procs] == [0, 0]
    assert all(not os.path.exists(f"/proc/{p.pid}") for p in procs)

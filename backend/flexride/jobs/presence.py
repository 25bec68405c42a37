"""Worker identity and liveness: names ``<kind>-<pid>@<host>``, a check whether a named worker
on this host is dead, and a background thread that reports a worker as seen.
"""

from __future__ import annotations

import logging
import os
import socket
import threading
from pathlib import Path

from flexride.jobs.fault_log import FaultLog

log = logging.getLogger(__name__)


def hostname() -> str:
    """The host name of this machine."""
    return socket.gethostname()


def worker_name(kind: str, pid: int | None = None) -> str:
    """Name of a worker process: ``<kind>-<pid>@<host>``."""
    return f"{kind}-{os.getpid() if pid is None else pid}@{hostname()}"


def parse_worker_name(name: str) -> tuple[str, int, str] | None:
    """``(kind, pid, host)`` of a worker name, or None if it is not one."""
    try:
        left, host = name.rsplit("@", 1)
        kind, pid = left.rsplit("-", 1)
        return kind, int(pid), host
    except (ValueError, AttributeError):
        return None


def pid_alive(pid: int) -> bool:
    """Whether process ``pid`` exists on this machine and is not a zombie."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    stat = Path(f"/proc/{pid}/stat")
    try:
        state = stat.read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return True
    return state not in ("Z", "X")


def worker_is_dead(name: str) -> bool:
    """True if ``name`` is a worker on this host whose process no longer exists.

    Workers on other hosts are never declared dead here (their heartbeats tell).
    """
    parsed = parse_worker_name(name)
    if parsed is None:
        return False
    _, pid, host = parsed
    return host == hostname() and not pid_alive(pid)


class Presence:
    """Reports a worker process to the job store every ``interval`` seconds (daemon thread).

    Parameters
    ----------
    store : JobStore
        Where workers are recorded.
    name, kind : str
        Worker name and kind (``embedded`` or ``celery``).
    interval : float
        Seconds between reports.
    """

    def __init__(self, store, name: str, kind: str, interval: float):
        self.store, self.name, self.kind, self.interval = store, name, kind, interval
        self.current_job: str | None = None
        self.faults = FaultLog(log, f"worker {name}: presence report")
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def report(self) -> None:
        """Record the worker as seen now (errors are logged once per change, not raised)."""
        try:
            self.store.worker_seen(self.name, self.kind, hostname(), os.getpid(),
                                   self.current_job)
        except Exception as exc:  # the database may be briefly unreachable
            self.faults.failed(exc)
        else:
            self.faults.succeeded()

    def start(self) -> Presence:
        """Report now and then periodically."""
        self.report()
        self._thread = threading.Thread(target=self._loop, name="flexride-presence",
                                        daemon=True)
        self._thread.start()
        return self

    def _loop(self) -> None:
        while not self._stop.wait(self.interval):
            self.report()

    def stop(self, forget: bool = True) -> None:
        """Stop reporting; remove the worker's row when ``forget``."""
        self._stop.set()
        if forget:
            try:
                self.store.worker_gone(self.name)
            except Exception as exc:
                log.warning("worker %s: cannot remove its record: %s", self.name, exc)

#!/opt/flexride/bin/python
"""Health check of the flexride image (``flexride-healthcheck api|worker``).

* ``api``: ``GET /api/v1/health`` on ``127.0.0.1:$FLEXRIDE_PORT`` (default 8000) answers 200
  (the database is reachable and the storage takes writes).
* ``worker``: the Celery worker of this container (named by the ``-n`` option of its
  command line, ``flexride-<pid>@<host>``) answers a ping through the broker
  (``FLEXRIDE_BROKER_URL``) within 4 s; a worker busy with a job answers too (the pool's
  parent process replies). The ping goes to that worker only and returns at its answer.

Exit code 0 when healthy, 1 with one line saying why otherwise.
"""

from __future__ import annotations

import os
import socket
import sys
import urllib.request
from pathlib import Path


def api_problem() -> str | None:
    """Why the API of this container is not healthy, or None."""
    port = os.environ.get("FLEXRIDE_PORT") or "8000"
    try:
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/v1/health", timeout=4) as r:
            return None if r.status == 200 else f"health answered {r.status}"
    except OSError as exc:
        return f"health: {exc}"


def worker_names(proc: Path = Path("/proc")) -> list[str]:
    """Names of the Celery workers running in this container: the ``-n`` argument of their
    command lines (``flexride-<pid>@%h``), with ``%h`` the host name.
    """
    host, names = socket.gethostname(), set()
    for cmdline in proc.glob("[0-9]*/cmdline"):
        try:
            argv = cmdline.read_bytes().decode(errors="replace").split("\0")
        except OSError:  # the process ended meanwhile
            continue
        if "celery" in " ".join(argv[:3]) and "worker" in argv and "-n" in argv[:-1]:
            names.add(argv[argv.index("-n") + 1].replace("%h", host))
    return sorted(names)


def worker_problem() -> str | None:
    """Why the Celery worker of this container does not answer a ping, or None."""
    broker = os.environ.get("FLEXRIDE_BROKER_URL")
    if not broker:
        return "FLEXRIDE_BROKER_URL is not set"
    names = worker_names()
    if not names:
        return "no Celery worker process in this container"
    from celery import Celery

    app = Celery("flexride-healthcheck", broker=broker)
    try:  # returns at the first answer of this container's worker
        replies = app.control.ping(destination=names, timeout=4.0, limit=len(names))
    except Exception as exc:  # any broker error means unhealthy
        return f"broker: {exc}"
    answered = {name for reply in replies for name in reply}
    missing = [n for n in names if n not in answered]
    return f"{', '.join(missing)} did not answer a ping within 4 s" if missing else None


def main(argv: list[str]) -> int:
    """Run the check named by ``argv[0]``; return the exit code."""
    checks = {"api": api_problem, "worker": worker_problem}
    if len(argv) != 1 or argv[0] not in checks:
        print("usage: flexride-healthcheck api|worker", file=sys.stderr)
        return 2
    problem = checks[argv[0]]()
    if problem is not None:
        print(problem)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

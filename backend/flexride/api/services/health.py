"""Health and version: API, database, storage, broker, workers seen, job counts.

Two views of one report. An *operator* (a request with the API token, or any request when the
service has no token) sees every component's detail: where the database and the broker are
(host, port and database name; never a password or a server path), the workers seen with
their host names, process ids and the jobs the job table says they run, the job counts. Anyone
else sees only whether each component is ok (:func:`public_view`) and the solver's compile
state, which the dashboard shows while the first job waits.
"""

from __future__ import annotations

import platform
import time
from importlib import metadata
from typing import Any

from flexride import __version__
from flexride.api.deps import Kept, Services
from flexride.api.services.jobs import iso
from flexride.settings import url_location
from flexride.store import now
from flexride.store.probe import db_fault, db_problem, dir_problem

ALIVE_INTERVALS = 3.0
"""A worker is alive when it reported within this many heartbeat intervals."""
WORKERS_SHOWN_S = 3600.0
"""Workers seen within this many seconds are listed (alive or gone)."""
DOWN_WHEN_NOT_OK = frozenset({"database", "broker"})
"""Components that are ``down`` (not ``degraded``) when not ok."""
REPORT_TTL_S = 1.0
"""Seconds a health report is reused (health may be polled by many clients at once: under
50 clients it was a third of the API's CPU); a write that failed since makes a new one."""
STORAGE_PROBE_TTL_S = 2.0
"""Seconds a storage probe is reused (each writes and syncs a file in two directories)."""


def health(svc: Services, recent_fault: str | None = None, *, operator: bool = True
           ) -> tuple[int, dict[str, Any]]:
    """HTTP status (200, or 503 when the database is down) and the health report (the
    operator's, or the public view of it).
    """
    kept = svc.health_report
    if kept is None or kept.key != recent_fault or time.monotonic() - kept.at >= REPORT_TTL_S:
        kept = svc.health_report = Kept(time.monotonic(), recent_fault,
                                        _report(svc, recent_fault))
    report = kept.value
    code = 503 if report["status"] == "down" else 200
    return code, report if operator else public_view(report)


def public_view(report: dict[str, Any]) -> dict[str, Any]:
    """What anyone may see of a report: the status, the state of each component, the
    solver's compile state.
    """
    return {"status": report["status"], "view": "public", "components": report["components"],
            "solver": report["solver"]}


def _report(svc: Services, recent_fault: str | None) -> dict[str, Any]:
    s = svc.settings
    db: dict[str, Any] = {"ok": False, "detail": "", "data": _location(s.effective_database_url)}
    jobs: dict[str, int] = {}
    workers: list[dict[str, Any]] = []
    try:
        t = now()
        store = svc.store.overview(workers_seen_after=t - WORKERS_SHOWN_S)
        db["data"]["latency_ms"] = round(store.latency_s * 1000.0, 2)
        db["ok"], db["detail"] = True, "reachable"
        jobs = store.counts
        alive_after = t - ALIVE_INTERVALS * s.heartbeat_interval_s
        workers = [_worker(w, alive_after) for w in store.workers]
    except Exception as exc:
        db["detail"] = f"unreachable: {_why(exc)}"
    storage = storage_health(svc, db["ok"], recent_fault)
    runner = svc.runner.status()
    runner_ok = bool(runner.get("ok", True))
    broker = None
    if svc.runner.kind == "celery":  # the runner's health is the broker's
        broker = {"ok": runner_ok, "detail": str(runner.get("detail", "")),
                  "data": {k: v for k, v in runner.items() if k not in ("ok", "detail")}}
    api = {"ok": True, "detail": f"runner {svc.runner.kind}: {runner.get('detail', '')}",
           "data": {"runner": runner, "reaper": svc.reaper.last}}
    serving = (svc.runner.kind == "none" or jobs.get("queued", 0) == 0
               or any(w["alive"] for w in workers))
    parts = {"api": True, "database": db["ok"], "storage": storage["ok"],
             "workers": serving and (runner_ok or broker is not None)}
    if broker is not None:
        parts["broker"] = broker["ok"]
    components = {name: "ok" if ok else "down" if name in DOWN_WHEN_NOT_OK else "degraded"
                  for name, ok in parts.items()}
    status = ("down" if not db["ok"] else "ok" if all(parts.values()) else "degraded")
    from flexride.jobs.warmup import SOLVER

    return {"status": status, "view": "operator", "components": components,
            "version": __version__, "runner": svc.runner.kind, "api": api, "database": db,
            "storage": storage, "broker": broker, "workers": workers, "jobs": jobs,
            "solver": SOLVER.status()}


def _location(url: str) -> dict[str, Any]:
    """Backend and location of the database (no password, no server path)."""
    return {"backend": url.split(":", 1)[0].split("+", 1)[0], "location": url_location(url)}


def _why(exc: BaseException) -> str:
    """Why the database cannot be read: the fault, or the error's class and first line."""
    orig = getattr(exc, "orig", None) or exc
    first = (str(orig).strip().splitlines() or [""])[0][:200]
    return db_fault(exc) or f"{type(orig).__name__}: {first}"


def _worker(w: Any, alive_after: float) -> dict[str, Any]:
    """A worker seen (a row of :meth:`flexride.store.JobStore.overview`): alive or gone, and
    the job the job records say it runs.
    """
    alive = w.last_seen >= alive_after
    return {"name": w.name, "kind": w.kind, "hostname": w.hostname, "pid": w.pid,
            "started_at": iso(w.started_at), "last_seen": iso(w.last_seen), "alive": alive,
            "state": "alive" if alive else "gone", "current_job": w.job_id}


def storage_health(svc: Services, db_reachable: bool, recent_fault: str | None = None
                   ) -> dict[str, Any]:
    """Whether the results and upload directories and the database take writes: probes of
    :mod:`flexride.store.probe` (reused for ``STORAGE_PROBE_TTL_S``), and ``recent_fault``, a
    write of a request that failed lately (a full SQLite file still takes the probe's small
    rolled-back write in its log, but not a new job).
    """
    kept = svc.storage_probe
    if kept is None or kept.key != db_reachable or (
            time.monotonic() - kept.at >= STORAGE_PROBE_TTL_S):
        kept = svc.storage_probe = Kept(time.monotonic(), db_reachable, {
            "results": dir_problem(svc.files.root), "uploads": dir_problem(svc.uploads.root),
            "database": db_problem(svc.store.engine) if db_reachable else None})
    problems = dict(kept.value)
    if recent_fault and not any(problems.values()):
        part = "database" if "database" in recent_fault else "results"
        problems[part] = recent_fault
    bad = {k: v for k, v in problems.items() if v}
    out = {"ok": not bad,
           "detail": "writable" if not bad else "not writable: " + "; ".join(
               f"{k}: {v}" for k, v in bad.items()),
           "data": {k: v is None for k, v in problems.items()}}
    return out


def _version(dist: str) -> str:
    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return "not installed"


def version(svc: Services) -> dict[str, Any]:
    """Versions of flexride and its main libraries."""
    libs = {d: _version(d) for d in ("numpy", "scipy", "numba", "h5py", "fastapi", "pydantic",
                                      "sqlalchemy", "celery")}
    return {"flexride": __version__, "api": "v1", "python": platform.python_version(),
            "libraries": libs, "runner": svc.runner.kind}

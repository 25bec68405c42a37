"""Health and version: API, database, broker, workers seen, job counts."""

from __future__ import annotations

import platform
import time
from importlib import metadata
from typing import Any

from flexride import __version__
from flexride.api.deps import Services
from flexride.api.services.jobs import iso
from flexride.settings import redact_url
from flexride.store import now
from flexride.store.probe import db_problem, dir_problem


def health(svc: Services, recent_fault: str | None = None) -> tuple[int, dict[str, Any]]:
    """HTTP status (200, or 503 when the database is down) and the health report."""
    s = svc.settings
    db: dict[str, Any] = {"ok": False, "detail": "", "data": {
        "url": redact_url(s.effective_database_url)}}
    jobs: dict[str, int] = {}
    workers: list[dict[str, Any]] = []
    try:
        db["data"]["latency_ms"] = round(svc.store.ping() * 1000.0, 2)
        db["ok"], db["detail"] = True, "reachable"
        jobs = svc.store.counts()
        alive_after = now() - 3.0 * s.heartbeat_interval_s
        for w in svc.store.workers(seen_after=now() - 3600.0):
            workers.append({"name": w.name, "kind": w.kind, "hostname": w.hostname,
                            "pid": w.pid, "started_at": iso(w.started_at),
                            "last_seen": iso(w.last_seen), "alive": w.last_seen >= alive_after,
                            "current_job": w.current_job})
    except Exception as exc:
        db["detail"] = f"unreachable: {type(exc).__name__}: {exc}"
    storage = storage_health(svc, db["ok"], recent_fault)
    runner = svc.runner.status()
    broker = None
    if svc.runner.kind == "celery":
        broker = {"ok": bool(runner.get("ok")), "detail": str(runner.get("detail", "")),
                  "data": {k: v for k, v in runner.items() if k not in ("ok", "detail")}}
    alive = [w for w in workers if w["alive"]]
    api = {"ok": True, "detail": f"runner {svc.runner.kind}: {runner.get('detail', '')}",
           "data": {"runner": runner, "reaper": svc.reaper.last}}
    if not db["ok"]:
        status = "down"
    elif not storage["ok"] or not runner.get("ok", True) or (
            svc.runner.kind != "none" and not alive and jobs.get("queued", 0) > 0):
        status = "degraded"
    else:
        status = "ok"
    from flexride.jobs.warmup import SOLVER

    body = {"status": status, "version": __version__, "runner": svc.runner.kind, "api": api,
            "database": db, "storage": storage, "broker": broker, "workers": workers,
            "jobs": jobs, "solver": SOLVER.status()}
    return (503 if status == "down" else 200), body


STORAGE_PROBE_TTL_S = 2.0
"""Seconds a storage probe is reused (health may be polled often)."""
_probe_cache: dict[int, tuple[float, dict[str, str | None]]] = {}


def storage_health(svc: Services, db_reachable: bool, recent_fault: str | None = None
                   ) -> dict[str, Any]:
    """Whether the results and upload directories and the database take writes: probes of
    :mod:`flexride.store.probe` (reused for ``STORAGE_PROBE_TTL_S``), and ``recent_fault``, a
    write of a request that failed lately (a full SQLite file still takes the probe's small
    rolled-back write in its log, but not a new job).
    """
    key = id(svc)
    hit = _probe_cache.get(key)
    if hit is None or time.monotonic() - hit[0] >= STORAGE_PROBE_TTL_S:
        problems = {"results": dir_problem(svc.files.root),
                    "uploads": dir_problem(svc.uploads.root),
                    "database": db_problem(svc.store.engine) if db_reachable else None}
        hit = (time.monotonic(), problems)
        _probe_cache[key] = hit
    problems = dict(hit[1])
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

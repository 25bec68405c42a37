"""Health and version: API, database, broker, workers seen, job counts."""

from __future__ import annotations

import platform
from importlib import metadata
from typing import Any

from flexride import __version__
from flexride.api.deps import Services
from flexride.api.services.jobs import iso
from flexride.settings import redact_url
from flexride.store import now


def health(svc: Services) -> tuple[int, dict[str, Any]]:
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
    elif not runner.get("ok", True) or (svc.runner.kind != "none" and not alive
                                        and jobs.get("queued", 0) > 0):
        status = "degraded"
    else:
        status = "ok"
    body = {"status": status, "version": __version__, "runner": svc.runner.kind, "api": api,
            "database": db, "broker": broker, "workers": workers, "jobs": jobs}
    return (503 if status == "down" else 200), body


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

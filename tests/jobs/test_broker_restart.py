"""A broker that is down or restarts without persistence loses messages, not jobs: submission
still succeeds (the job stays queued) and the runner sends the queued jobs again once the
broker is back; with the records in SQLite and in PostgreSQL. Uses a private redis-server on a
free port (the shared one is not touched)."""

from __future__ import annotations

import contextlib
import shutil
import subprocess
import time
import warnings

import pytest
import redis

from service.svc_testkit import free_port, make_settings, pg_schema, wait_for

API = "/api/v1"
pytestmark = pytest.mark.filterwarnings("ignore:Using `httpx`")


def _redis_server(port: int, tmp) -> subprocess.Popen:
    exe = shutil.which("redis-server")
    assert exe, "redis-server is not installed (tools/ensure_services.sh installs it)"
    proc = subprocess.Popen([exe, "--port", str(port), "--bind", "127.0.0.1", "--save", "",
                             "--appendonly", "no", "--dir", str(tmp)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    client = redis.Redis(port=port)
    wait_for(lambda: _ping(client), 10.0, 0.1, "the private redis-server")
    return proc


def _ping(client) -> bool:
    try:
        return bool(client.ping())
    except redis.ConnectionError:
        return False


def _stop(proc: subprocess.Popen) -> None:
    proc.terminate()
    proc.wait(10)


@pytest.mark.parametrize("db", ["sqlite", "postgresql"])
def test_jobs_survive_a_broker_outage_and_restart(tmp_path, db):
    from fastapi.testclient import TestClient

    from flexride.api import create_app

    port = free_port()
    server = _redis_server(port, tmp_path)
    queue = "flexride-restart-test"
    records = contextlib.ExitStack()
    url = records.enter_context(pg_schema()) if db == "postgresql" else None
    settings = make_settings(tmp_path / "data", runner="auto", database_url=url,
                             broker_url=f"redis://127.0.0.1:{port}/0", celery_queue=queue,
                             reaper_interval_s=3600.0)  # passes are run by hand below
    r = redis.Redis(port=port)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            client = TestClient(create_app(settings), raise_server_exceptions=False)
        with client:
            svc = client.app.state.services
            body = {"preset": "paper-metro", "overrides": {"duration_s": 1.0}, "reuse": False}
            first = client.post(f"{API}/jobs", json=body).json()["id"]
            assert r.llen(queue) == 1
            # the broker restarts without persistence: the message is gone, the job is not
            _stop(server)
            server = _redis_server(port, tmp_path)
            assert r.llen(queue) == 0
            assert svc.reaper.run_once()["redispatched"] == 1
            assert r.llen(queue) == 1
            # the broker is down: submitting still works, the job waits
            _stop(server)
            t0 = time.monotonic()
            resp = client.post(f"{API}/jobs", json={**body, "name": "during-outage"})
            assert resp.status_code == 201 and time.monotonic() - t0 < 20.0
            second = resp.json()["id"]
            health = client.get(f"{API}/health").json()
            assert health["status"] == "degraded" and not health["broker"]["ok"]
            server = _redis_server(port, tmp_path)
            svc.reaper.run_once()
            assert r.llen(queue) >= 1
            queued = [b for b in r.lrange(queue, 0, -1) if second.encode() in b]
            assert queued, "the job submitted during the outage was not sent"
            assert client.get(f"{API}/jobs/{first}").json()["status"] == "queued"
    finally:
        _stop(server)
        records.close()

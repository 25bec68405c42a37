"""The API killed mid-job (SIGKILL to ``flexride serve`` and its embedded workers: no clean-up
at all) with the records in PostgreSQL: nothing is lost. The next start finds the job running
on a worker of this host that is gone, queues it again and runs it to the end, once.
"""

from __future__ import annotations

import signal

import httpx

from service.svc_testkit import (
    free_port,
    pg_schema,
    service_command,
    service_env,
    start_process,
    stop_process,
    wait_for,
)


def _serve(tmp_path, db_url: str, n: int):
    port = free_port()
    proc = start_process([*service_command(), "serve", "--host", "127.0.0.1", "--port",
                          str(port)],
                         service_env(FLEXRIDE_DATA_DIR=str(tmp_path / "data"),
                                     FLEXRIDE_DATABASE_URL=db_url, FLEXRIDE_WORKERS="1",
                                     FLEXRIDE_HEARTBEAT_INTERVAL_S="1"),
                         tmp_path / f"serve{n}.log")
    return proc, f"http://127.0.0.1:{port}/api/v1"


def _get(url: str):
    try:
        r = httpx.get(url, timeout=5)
        return r.json() if r.status_code == 200 else None
    except httpx.HTTPError:
        return None


def test_a_killed_api_loses_no_job_on_postgresql(tmp_path):
    with pg_schema() as db_url:
        proc, api = _serve(tmp_path, db_url, 1)
        try:
            wait_for(lambda: (h := _get(f"{api}/health")) and any(
                w["alive"] for w in h["workers"]), 120.0, 0.3, "the embedded worker")
            r = httpx.post(f"{api}/jobs", timeout=60, json={
                "preset": "paper-random-straight-80", "reuse": False,
                "overrides": {"duration_s": 8.0, "distance_m": None}})
            assert r.status_code == 201, r.text
            job = r.json()["id"]
            wait_for(lambda: (j := _get(f"{api}/jobs/{job}")) and j["status"] == "running"
                     and j["progress"] > 0.0, 120.0, 0.1, "the job to run")
        finally:
            stop_process(proc, signal.SIGKILL)  # the API and its worker, at once
        proc, api = _serve(tmp_path, db_url, 2)
        try:
            done = wait_for(lambda: (j := _get(f"{api}/jobs/{job}")) and j["status"] not in (
                "queued", "running") and j, 180.0, 0.3, "the job to finish after the restart")
            assert done["status"] == "succeeded" and done["attempts"] == 2, done
            summary = _get(f"{api}/jobs/{job}/summary")
            assert summary is not None and summary["summary"]["run"]["speed_kmh"] == 80.0
        finally:
            stop_process(proc)

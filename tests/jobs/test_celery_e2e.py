"""End to end through Celery: a real Redis broker (127.0.0.1:6379), real `flexride worker`
processes, PostgreSQL as the shared job store (127.0.0.1:5432, database test).

The same short job as through the embedded runner, an FE export built by a worker (a job of
kind fe_export), a study of three jobs, cancellation of a running job, a worker child killed
with SIGKILL mid-job (the message is requeued and the job retried) and a whole worker killed
with SIGKILL (the reaper requeues the job after the heartbeat timeout and a new worker
finishes it). These tests fail, never skip, when Redis or
PostgreSQL is down.
"""

from __future__ import annotations

import os
import signal
import uuid
import warnings
from collections.abc import Iterator
from contextlib import contextmanager

import pytest
import redis

from flexride.jobs.presence import parse_worker_name
from service.svc_testkit import (
    make_settings,
    pg_schema,
    redis_url,
    service_command,
    service_env,
    start_process,
    stop_process,
    wait_for,
)

API = "/api/v1"
HEARTBEAT_TIMEOUT_S = 6.0
pytestmark = pytest.mark.filterwarnings("ignore:Using `httpx`")


class Cluster:
    """A Celery deployment on this machine: settings, worker processes, an API client."""

    def __init__(self, tmp, db_url):
        self.tmp = tmp
        self.queue = f"flexride-test-{uuid.uuid4().hex[:8]}"
        self.values = {"FLEXRIDE_BROKER_URL": redis_url(9), "FLEXRIDE_DATABASE_URL": db_url,
                       "FLEXRIDE_DATA_DIR": str(tmp / "data"),
                       # shared with the API (make_settings: <data>/cache): FE exports
                       "FLEXRIDE_CACHE_DIR": str(tmp / "data" / "cache"),
                       "FLEXRIDE_CELERY_QUEUE": self.queue,
                       "FLEXRIDE_HEARTBEAT_INTERVAL_S": "1",
                       "FLEXRIDE_HEARTBEAT_TIMEOUT_S": str(HEARTBEAT_TIMEOUT_S),
                       "FLEXRIDE_MAX_ATTEMPTS": "2", "FLEXRIDE_LOG_LEVEL": "info"}
        self.workers = []
        self.client = None

    def start_worker(self, concurrency=2):
        n = len(self.workers)
        proc = start_process([*service_command(), "worker", "--concurrency", str(concurrency)],
                             service_env(**self.values), self.tmp / f"worker{n}.log")
        self.workers.append(proc)
        return proc

    def worker_log(self):
        return "\n".join((self.tmp / f"worker{i}.log").read_text(errors="replace")[-3000:]
                         for i in range(len(self.workers)))

    def start_api(self):
        from fastapi.testclient import TestClient

        from flexride.api import create_app

        settings = make_settings(
            self.tmp / "data", runner="auto", broker_url=self.values["FLEXRIDE_BROKER_URL"],
            database_url=self.values["FLEXRIDE_DATABASE_URL"], celery_queue=self.queue,
            heartbeat_interval_s=1.0, heartbeat_timeout_s=HEARTBEAT_TIMEOUT_S,
            reaper_interval_s=1.0, max_attempts=2)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            self.client = TestClient(create_app(settings), raise_server_exceptions=False)
        self.client.__enter__()

    def stop(self):
        if self.client is not None:
            self.client.__exit__(None, None, None)
        for w in self.workers:
            stop_process(w)
        r = redis.Redis.from_url(self.values["FLEXRIDE_BROKER_URL"])
        r.delete(self.queue)
        r.close()

    # -- helpers --
    def submit(self, duration, **overrides):
        r = self.client.post(f"{API}/jobs", json={
            "preset": "paper-random-straight-80", "reuse": False,
            "overrides": {"duration_s": duration, "distance_m": None, **overrides}})
        assert r.status_code == 201, r.text
        return r.json()["id"]

    def job(self, job_id):
        return self.client.get(f"{API}/jobs/{job_id}").json()

    def final(self, job_id, timeout=150.0):
        try:
            return wait_for(lambda: (j := self.job(job_id))["status"]
                            not in ("queued", "running") and j, timeout, 0.25,
                            f"job {job_id} to finish")
        except AssertionError as exc:
            raise AssertionError(f"{exc}\n--- worker log ---\n{self.worker_log()}") from None

    def running(self, job_id, progress=0.05, timeout=150.0):
        return wait_for(lambda: (j := self.job(job_id))["status"] == "running"
                        and j["progress"] >= progress and j, timeout, 0.1,
                        f"job {job_id} to run")


@contextmanager
def running_cluster(tmp_path_factory, name: str) -> Iterator[Cluster]:
    """A started cluster (two Celery worker processes and the API) on a fresh PostgreSQL
    schema; fails loudly when Redis or PostgreSQL is down."""
    redis.Redis.from_url(redis_url(9), socket_connect_timeout=3).ping()
    with pg_schema() as db_url:
        c = Cluster(tmp_path_factory.mktemp(name), db_url)
        try:
            c.start_worker(concurrency=2)
            c.start_api()
            yield c
        finally:
            c.stop()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    with running_cluster(tmp_path_factory, "celery") as c:
        yield c


def test_celery_job_end_to_end(cluster):
    job_id = cluster.submit(2.0)
    job = cluster.final(job_id)
    assert job["status"] == "succeeded", (job, cluster.worker_log())
    assert job["runner"] == "celery" and job["worker"].startswith("celery-")
    assert job["attempts"] == 1 and job["progress"] == 1.0
    c = cluster.client
    summary = c.get(f"{API}/jobs/{job_id}/summary").json()["summary"]
    assert summary["points"]["PR"]["directions"]["z"]["peaks"]["max_abs"] > 0
    series = c.get(f"{API}/jobs/{job_id}/series",
                   params={"channels": ["carbody.PC.acc.z"], "max_points": 200}).json()
    assert len(series["channels"][0]["values"]) <= 200
    spec = c.get(f"{API}/jobs/{job_id}/spectrum", params={"channels": ["carbody.PC.acc.z"]})
    assert spec.status_code == 200 and spec.json()["channels"][0]["values"]
    health = c.get(f"{API}/health").json()
    assert health["broker"]["ok"] and health["runner"] == "celery"
    assert any(w["kind"] == "celery" and w["alive"] for w in health["workers"])


def test_celery_fe_export_job(cluster):
    """``GET /fe/carbody``: the export is built by a Celery worker as a job of kind fe_export
    (a real coarse car body), written to the shared cache directory and served by the API."""
    c = cluster.client
    params = {"element_size_m": 0.5, "cutoff_hz": 25, "max_modes": 4}
    r = c.get(f"{API}/fe/carbody", params=params)
    if r.status_code == 202:
        job = cluster.final(r.json()["job_id"])
        assert job["status"] == "succeeded", (job, cluster.worker_log())
        r = c.get(f"{API}/fe/carbody", params=params)
    assert r.status_code == 200, r.text
    model = r.json()["model"]
    assert (model["element_size_m"], model["cutoff_hz"], len(r.json()["modes"])) == (0.5, 25.0, 4)
    (job,) = c.get(f"{API}/jobs", params={"kind": "fe_export"}).json()["items"]
    assert job["runner"] == "celery" and job["worker"].startswith("celery-")
    assert job["status"] == "succeeded" and job["scenario_hash"] == model["key"]
    cache = cluster.tmp / "data" / "cache"
    assert list(cache.glob(f"fe-export-*/{model['key']}.json"))
    assert not model["from_cache"] and list(cache.glob("fem-*/*.npz"))  # the worker's FE cache
    assert all(j["kind"] == "simulation" for j in c.get(f"{API}/jobs").json()["items"])


def test_celery_study_of_three_jobs(cluster):
    c = cluster.client
    r = c.post(f"{API}/studies", json={
        "name": "celery-study", "base": {"preset": "paper-random-straight-80"},
        "speeds_kmh": [60, 70, 80], "overrides": {"duration_s": 2.0, "distance_m": None},
        "reuse": False})
    assert r.status_code == 201, r.text
    study_id = r.json()["id"]
    detail = wait_for(lambda: (d := c.get(f"{API}/studies/{study_id}").json())["status"]
                      not in ("queued", "running") and d, 150.0, 0.5, "the study")
    assert detail["status"] == "succeeded", detail["counts"]
    rows = [t for t in detail["tables"]["peak_vs_speed"]
            if t["point"] == "PR" and t["direction"] == "z"]
    assert rows and rows[0]["speed_kmh"] == [60.0, 70.0, 80.0]
    assert rows[0]["fit"]["n"] == 3 and 0.0 <= rows[0]["fit"]["r_squared"] <= 1.0


def test_cancel_a_running_celery_job(cluster):
    job_id = cluster.submit(60.0)
    cluster.running(job_id, progress=0.02)
    r = cluster.client.post(f"{API}/jobs/{job_id}/cancel")
    assert r.status_code == 200 and r.json()["cancel_requested"]
    job = cluster.final(job_id, timeout=30.0)
    assert job["status"] == "cancelled" and "cancelled at t" in job["message"]
    assert not job["has_results"]


def test_worker_child_killed_mid_job_is_retried(cluster):
    job_id = cluster.submit(25.0)
    job = cluster.running(job_id)
    _, pid, _ = parse_worker_name(job["worker"])
    os.kill(pid, signal.SIGKILL)
    job = cluster.final(job_id)
    assert job["status"] == "succeeded", (job, cluster.worker_log())
    assert job["attempts"] == 2 and str(pid) not in job["worker"]


def test_whole_worker_killed_mid_job_is_requeued_then_finished(cluster):
    job_id = cluster.submit(25.0)
    cluster.running(job_id)
    old = cluster.workers[-1]
    stop_process(old, sig=signal.SIGKILL)  # the worker and its children, no clean-up
    job = wait_for(lambda: (j := cluster.job(job_id))["status"] != "running" and j,
                   HEARTBEAT_TIMEOUT_S + 20.0, 0.25, "the reaper to notice the lost worker")
    assert job["status"] == "queued" and "no heartbeat" in job["message"], job
    cluster.start_worker(concurrency=1)
    job = cluster.final(job_id)
    assert job["status"] == "succeeded", (job, cluster.worker_log())
    assert job["attempts"] == 2

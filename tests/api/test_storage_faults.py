"""Storage faults: read-only and full disks (real tmpfs mounts, so the test runs as root, as CI
does) and a database that refuses writes (SQLite on a read-only mount, PostgreSQL with
read-only transactions). Every fault is a 503 ``storage unavailable: …`` (never 500), health
says the storage is not writable, deletions leave no orphan, and a job that could not write its
results fails before it simulates."""

from __future__ import annotations

import os
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from sqlalchemy import text

from service.svc_testkit import pg_schema, tmpfs

API = "/api/v1"
CSV = b"distance_m,vertical\n0,0\n1,0.001\n2,0\n"
JOB = {"preset": "paper-metro", "overrides": {"duration_s": 0.5, "distance_m": None}}


@pytest.fixture(params=["sqlite", "postgresql"])
def db_kind(request):
    return request.param


@contextmanager
def database(kind: str, tmp_path: Path) -> Iterator[str]:
    if kind == "sqlite":
        yield f"sqlite:///{tmp_path / 'jobs.db'}"
    else:
        with pg_schema() as url:
            yield url


def _finished_job_with_file(client, data_dir: Path) -> tuple[str, Path]:
    """A job record marked succeeded with a (stand-in) result file."""
    job_id = client.post(API + "/jobs", json=JOB).json()["id"]
    svc = client.app.state.services
    name = f"{job_id}.h5"
    path = data_dir / "results" / name
    path.write_bytes(b"stand-in results")
    with svc.store.engine.begin() as conn:
        conn.execute(text("UPDATE flexride_jobs SET status='succeeded', result_file=:f "
                          "WHERE id=:i"), {"f": name, "i": job_id})
    return job_id, path


def _unavailable(r, needle: str) -> None:
    assert r.status_code == 503, r.text
    assert r.json()["detail"].startswith("storage unavailable:") and needle in r.text, r.text
    assert "/tmp" not in r.text and "pytest" not in r.text  # no server path


def test_read_only_results_directory(make_client, tmp_path, db_kind):
    with database(db_kind, tmp_path) as url, tmpfs(tmp_path / "data") as fs:
        client = make_client(database_url=url)
        data = fs.path
        # make_client puts data under tmp_path/"data": that is the mount
        job_id, result = _finished_job_with_file(client, data)
        fs.read_only()
        _unavailable(client.post(API + "/jobs", json=JOB), "read-only file system")
        _unavailable(client.post(API + "/irregularities", content=CSV), "read-only")
        _unavailable(client.delete(f"{API}/jobs/{job_id}"), "read-only")
        assert client.get(f"{API}/jobs/{job_id}").status_code == 200 and result.is_file()
        health = client.get(API + "/health").json()
        assert health["status"] == "degraded" and not health["storage"]["ok"]
        assert health["storage"]["data"] == {"results": False, "uploads": False,
                                             "database": True}
        fs.writable()
        assert client.delete(f"{API}/jobs/{job_id}").status_code == 204
        assert not result.exists() and not list((data / "results").glob(".deleting-*"))
        assert client.get(f"{API}/jobs/{job_id}").status_code == 404


def test_full_disk(make_client, tmp_path):
    with tmpfs(tmp_path / "data", size_kb=2048) as fs:
        client = make_client()  # SQLite database on the same (full) file system
        job_id = client.post(API + "/jobs", json=JOB).json()["id"]
        fs.fill()
        big = b"distance_m,vertical\n" + b"".join(f"{i},0\n".encode() for i in range(50_000))
        _unavailable(client.post(API + "/irregularities", content=big),
                     "no space left on device")
        _unavailable(client.post(API + "/jobs", json=JOB), "no space left on device")
        health = client.get(API + "/health")
        assert health.status_code == 200 and health.json()["status"] == "degraded"
        assert client.get(f"{API}/jobs/{job_id}").status_code == 200  # reads still work


@pytest.mark.parametrize("fault", ["sqlite-full", "postgresql-read-only"])
def test_database_refusing_writes(make_client, tmp_path, fault):
    """SQLite on a full file system ("database or disk is full"); PostgreSQL with read-only
    transactions (an open SQLite file cannot be remounted read-only, and a WAL database on a
    read-only mount cannot be opened at all, so the service would not start)."""
    kind, needle = ("sqlite", "database full") if fault == "sqlite-full" else (
        "postgresql", "database read-only")
    with database(kind, tmp_path) as url, tmpfs(tmp_path / "db", size_kb=1024) as dbfs:
        if kind == "sqlite":
            url = f"sqlite:///{dbfs.path / 'jobs.db'}"
        writer = make_client(database_url=url)
        job_id, result = _finished_job_with_file(writer, tmp_path / "data")
        if kind == "sqlite":
            client = writer
            dbfs.fill()
        else:
            client = make_client(database_url=url + "%20-cdefault_transaction_read_only%3Don")
        jobs = [client.post(API + "/jobs", json=JOB) for _ in range(20 if kind == "sqlite" else 1)]
        _unavailable(jobs[-1], needle)
        _unavailable(client.delete(f"{API}/jobs/{job_id}"), needle)
        assert result.is_file() and not list(result.parent.glob(".deleting-*"))
        assert client.get(f"{API}/jobs/{job_id}").status_code == 200
        health = client.get(API + "/health")
        assert health.status_code == 200
        body = health.json()
        assert body["status"] == "degraded" and body["storage"]["data"]["database"] is False


def test_job_fails_before_simulating_when_results_cannot_be_written(tmp_path, monkeypatch):
    import flexride.solver
    from flexride.store import JobStore, ResultFiles
    from flexride.study.run_job import JobContext, claim_and_run
    from flexride.study.submit import Submitter
    from service.svc_testkit import make_settings

    def never(*_a, **_k):
        raise AssertionError("simulate must not run")

    monkeypatch.setattr(flexride.solver, "simulate", never)
    with tmpfs(tmp_path / "data") as fs:
        settings = make_settings(fs.path, database_url=f"sqlite:///{tmp_path / 'jobs.db'}")
        store = JobStore.from_url(settings.effective_database_url, create=True)
        files = ResultFiles(settings.results_dir)

        class _NoRunner:
            kind = "none"

            def submit(self, _ids):
                pass

        sub = Submitter(store, files, _NoRunner(), settings)  # type: ignore[arg-type]
        from flexride.scenario.loading import resolve_scenario

        job = sub.submit_job(resolve_scenario(**{"preset": "paper-metro",
                                                 "overrides": JOB["overrides"]})).job
        fs.read_only()
        ctx = JobContext(store=store, files=files, settings=settings,
                         worker=f"test-{uuid.uuid4().hex[:6]}@{os.uname().nodename}")
        assert claim_and_run(job.id, ctx) == "failed"
        rec = store.get_job(job.id)
        assert "results directory not writable: read-only file system" in rec.error


def test_deleting_a_study_on_read_only_storage_changes_nothing(make_client, tmp_path):
    with tmpfs(tmp_path / "data") as fs:
        client = make_client(database_url=f"sqlite:///{tmp_path / 'jobs.db'}")
        study = client.post(API + "/studies", json={
            "name": "s", "base": {"preset": "paper-metro", "overrides": JOB["overrides"]},
            "speeds_kmh": [60, 80]}).json()
        svc = client.app.state.services
        files = []
        for job in svc.store.list_jobs(study_id=study["id"])[0]:
            name = f"{job.id}.h5"
            (fs.path / "results" / name).write_bytes(b"stand-in")
            with svc.store.engine.begin() as conn:
                conn.execute(text("UPDATE flexride_jobs SET status='succeeded', result_file=:f "
                                  "WHERE id=:i"), {"f": name, "i": job.id})
            files.append(fs.path / "results" / name)
        fs.read_only()
        _unavailable(client.delete(f"{API}/studies/{study['id']}"), "read-only")
        assert client.get(f"{API}/studies/{study['id']}").status_code == 200
        assert all(f.is_file() for f in files)
        fs.writable()
        assert client.delete(f"{API}/studies/{study['id']}").status_code == 204
        assert not any(f.exists() for f in files)
        assert not list((fs.path / "results").glob(".deleting-*"))

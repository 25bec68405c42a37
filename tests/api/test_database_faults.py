"""PostgreSQL refusing writes, for every reason the service answers 503 ``storage unavailable:
<reason>`` with ``Retry-After`` (never 500), made by the real server: a role with SELECT only
(insufficient privilege), a full disk (the tables on a tablespace on a small tmpfs that is
filled), a serialization failure (retried, then refused), a connection the server ends in the
middle of a write. Health says degraded; reads keep working; the reaper logs one line per
change of state, not a traceback per pass.
"""

from __future__ import annotations

import logging
import os
import pwd
import tempfile
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest
from sqlalchemy import text
from sqlalchemy.engine import make_url

from service.svc_testkit import pg_admin, pg_role, pg_schema, schema_of, tmpfs

API = "/api/v1"
JOB = {"preset": "paper-metro", "overrides": {"duration_s": 0.5, "distance_m": None}}
STUDY = {"name": "s", "base": {"preset": "paper-metro", "overrides": JOB["overrides"]},
         "speeds_kmh": [60, 80]}
TABLES = ("flexride_jobs", "flexride_studies", "flexride_workers")


def _unavailable(r, reason: str) -> None:
    assert r.status_code == 503, r.text
    assert r.json()["detail"] == f"storage unavailable: database {reason}", r.text
    assert int(r.headers["retry-after"]) > 0
    assert "/tmp" not in r.text and "flexride_t_" not in r.text  # no path, no schema


def _finished_job_with_file(client) -> tuple[str, Path]:
    """A job marked succeeded with a (stand-in) result file."""
    r = client.post(API + "/jobs", json=JOB)
    assert r.status_code == 201, r.text
    job_id = r.json()["id"]
    svc = client.app.state.services
    path = svc.files.root / f"{job_id}.h5"
    path.write_bytes(b"stand-in results")
    with svc.store.engine.begin() as conn:
        conn.execute(text("UPDATE flexride_jobs SET status='succeeded', result_file=:f "
                          "WHERE id=:i"), {"f": path.name, "i": job_id})
    return job_id, path


def _degraded(client) -> None:
    health = client.get(API + "/health")
    assert health.status_code == 200, health.text
    body = health.json()
    assert body["status"] == "degraded" and body["components"]["storage"] == "degraded", body
    assert body["storage"]["data"]["database"] is False, body


def test_a_select_only_role_is_503_and_the_reaper_says_so_once(make_client, caplog):
    with pg_schema() as url:
        owner = make_client(database_url=url)
        job_id, result = _finished_job_with_file(owner)
        with pg_role(url, "SELECT") as select_only:
            client = make_client(database_url=select_only, reaper_interval_s=3600.0)
            why = "refuses writes (insufficient privilege)"
            _unavailable(client.post(API + "/jobs", json=JOB), why)
            _unavailable(client.post(API + "/studies", json=STUDY), why)
            _unavailable(client.delete(f"{API}/jobs/{job_id}"), why)
            _unavailable(client.post(f"{API}/jobs/{job_id}/cancel"), why)
            assert result.is_file() and not list(result.parent.glob(".deleting-*"))
            assert client.get(f"{API}/jobs/{job_id}").json()["status"] == "succeeded"
            assert client.get(f"{API}/jobs").json()["total"] == 1
            _degraded(client)

            reaper = client.app.state.services.reaper
            caplog.set_level(logging.INFO, logger="flexride.jobs.reaper")
            for _ in range(3):
                reaper.run_logged()
            role = make_url(select_only).username
            with pg_admin() as conn:
                conn.execute(f'GRANT INSERT, UPDATE, DELETE ON ALL TABLES IN SCHEMA '
                             f'"{schema_of(url)}" TO "{role}"')
            for _ in range(2):
                reaper.run_logged()
            lines = [r for r in caplog.records if r.name == "flexride.jobs.reaper"]
            assert [r.levelname for r in lines] == ["WARNING", "INFO"], [
                r.getMessage() for r in lines]
            assert why in lines[0].getMessage() and lines[0].exc_info is None
            assert "works again" in lines[1].getMessage()
            assert client.post(API + "/jobs", json=JOB).status_code == 201  # granted now


@contextmanager
def pg_tablespace_on_tmpfs(size_kb: int = 1024) -> Iterator[tuple[str, object]]:
    """A tablespace of the PostgreSQL server on a small tmpfs owned by the server's user
    (the server runs on this machine, as tools/ensure_services.sh sets it up)."""
    try:
        server = pwd.getpwnam("postgres")
    except KeyError:
        pytest.fail("the disk-full test puts a tablespace of the local PostgreSQL server on a "
                    "tmpfs and needs its system user 'postgres'")
    base = Path(tempfile.mkdtemp(prefix="flexride-pgspace-"))
    os.chmod(base, 0o755)  # the server's user passes through
    name = f"flexride_t_{uuid.uuid4().hex[:10]}"
    try:
        with tmpfs(base, size_kb, f"uid={server.pw_uid},gid={server.pw_gid},mode=0700") as fs:
            with pg_admin() as conn:
                conn.execute(f"CREATE TABLESPACE {name} LOCATION '{base}'")
            try:
                yield name, fs
            finally:
                (base / "filler").unlink(missing_ok=True)
                with pg_admin() as conn:
                    conn.execute(f"DROP TABLESPACE IF EXISTS {name}")
    finally:
        base.rmdir()


def test_a_full_disk_under_postgresql_is_503(make_client):
    with pg_tablespace_on_tmpfs() as (space, fs), pg_schema() as url:
        client = make_client(database_url=url)
        with pg_admin() as conn:
            for table in TABLES:  # empty: the next row needs a new page
                conn.execute(f'ALTER TABLE "{schema_of(url)}".{table} SET TABLESPACE {space}')
        fs.fill()  # type: ignore[attr-defined]
        _unavailable(client.post(API + "/jobs", json=JOB), "full")
        _unavailable(client.post(API + "/studies", json=STUDY), "full")
        assert client.get(f"{API}/jobs").json()["total"] == 0  # reads work
        _degraded(client)


def _trigger(url: str, table: str, body: str) -> None:
    """A BEFORE INSERT trigger on ``table`` of the schema of ``url`` running ``body``
    (PL/pgSQL)."""
    schema = schema_of(url)
    with pg_admin() as conn:
        conn.execute(f'CREATE FUNCTION "{schema}".fault() RETURNS trigger LANGUAGE plpgsql AS '
                     f"$$ BEGIN {body} RETURN NEW; END $$")
        conn.execute(f'CREATE TRIGGER fault BEFORE INSERT ON "{schema}".{table} FOR EACH ROW '
                     f'EXECUTE FUNCTION "{schema}".fault()')


def test_serialization_failures_are_retried_then_503(make_client):
    with pg_schema() as url:
        client = make_client(database_url=url)
        schema = schema_of(url)
        with pg_admin() as conn:
            conn.execute(f'CREATE SEQUENCE "{schema}".tries')
        # the first two attempts of every insert into the jobs table fail as PostgreSQL fails
        # a serializable transaction that conflicts (SQLSTATE 40001), then the third passes
        _trigger(url, "flexride_jobs",
                 f"IF nextval('\"{schema}\".tries') % 3 <> 0 THEN RAISE EXCEPTION "
                 "'could not serialize access' USING ERRCODE = '40001'; END IF;")
        r = client.post(API + "/jobs", json=JOB)
        assert r.status_code == 201, r.text
        tries = f'SELECT last_value FROM "{schema}".tries'
        with pg_admin() as conn:
            assert conn.execute(tries).fetchone() == (3,)
            # from now on every attempt fails (4, 7, 10, …): three attempts, then 503
            conn.execute(f'ALTER SEQUENCE "{schema}".tries INCREMENT BY 3 RESTART WITH 4')
        _unavailable(client.post(API + "/jobs", json=JOB), "busy (serialization failure)")
        with pg_admin() as conn:
            assert conn.execute(tries).fetchone() == (10,)


def test_a_connection_ended_by_the_server_mid_write_is_503(make_client):
    with pg_schema() as url:
        client = make_client(database_url=url)
        _trigger(url, "flexride_studies", "PERFORM pg_terminate_backend(pg_backend_pid());")
        _unavailable(client.post(API + "/studies", json=STUDY),
                     "connection lost (ended by the server)")
        assert client.get(f"{API}/studies").json()["total"] == 0  # a new connection reads

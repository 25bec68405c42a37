"""Read caching of job records (not timed): the job list and a job's detail are answered from
memory only while nothing in the database changed (any process's commit is seen at once),
only for finished jobs, never on PostgreSQL, and equal the answers read from the records."""

from __future__ import annotations

import pytest
from sqlalchemy import event, update

from flexride.api.services.jobs import job_out
from flexride.api.services.record_cache import settled
from flexride.store import Job
from flexride.store.db import create_store_engine
from service.svc_testkit import insert_finished_job, services, synthetic_results

API = "/api/v1"


def _count_queries(engine):
    seen: list[str] = []

    def record(_conn, _cursor, statement, *_args):
        if "flexride_jobs" in statement:
            seen.append(statement)

    event.listen(engine, "before_cursor_execute", record)
    return seen, lambda: event.remove(engine, "before_cursor_execute", record)


def _reads(client, svc, path):
    """(answer, number of job queries it made)."""
    seen, stop = _count_queries(svc.store.engine)
    try:
        r = client.get(path)
    finally:
        stop()
    assert r.status_code == 200, r.text
    return r.json(), len(seen)


@pytest.fixture
def two_jobs(client):
    svc = services(client)
    ids = [insert_finished_job(svc.store, svc.files, synthetic_results(duration=2.0))
           for _ in range(2)]
    return client, svc, ids


def test_unchanged_records_are_answered_from_memory_on_sqlite(two_jobs, db_url):
    client, svc, ids = two_jobs
    for path in (f"{API}/jobs", f"{API}/jobs/{ids[0]}"):
        first, queries = _reads(client, svc, path)
        again, queries_again = _reads(client, svc, path)
        assert queries > 0 and again == first
        # SQLite has a change counter; PostgreSQL reads the records every time
        assert queries_again == (0 if db_url.startswith("sqlite") else queries)


def test_a_commit_by_another_connection_is_seen_at_once(two_jobs, db_url):
    client, svc, ids = two_jobs
    _reads(client, svc, f"{API}/jobs")
    _reads(client, svc, f"{API}/jobs/{ids[0]}")
    other = create_store_engine(db_url)  # as a worker process would write
    try:
        with other.begin() as conn:
            conn.execute(update(Job).where(Job.id == ids[0]).values(name="renamed elsewhere"))
    finally:
        other.dispose()
    page, _ = _reads(client, svc, f"{API}/jobs")
    assert {j["id"]: j["name"] for j in page["items"]}[ids[0]] == "renamed elsewhere"
    detail, _ = _reads(client, svc, f"{API}/jobs/{ids[0]}")
    assert detail["name"] == "renamed elsewhere"


def test_a_deleted_job_is_gone_from_list_and_detail(two_jobs):
    client, svc, ids = two_jobs
    assert _reads(client, svc, f"{API}/jobs")[0]["total"] == 2
    _reads(client, svc, f"{API}/jobs/{ids[1]}")
    assert client.delete(f"{API}/jobs/{ids[1]}").status_code == 204
    assert client.get(f"{API}/jobs/{ids[1]}").status_code == 404
    page, _ = _reads(client, svc, f"{API}/jobs")
    assert page["total"] == 1 and [j["id"] for j in page["items"]] == [ids[0]]


def test_answers_with_unfinished_jobs_are_not_kept(sqlite_client):
    svc = services(sqlite_client)
    job_id = insert_finished_job(svc.store, svc.files, synthetic_results(duration=2.0),
                                 status="queued", started_at=None, finished_at=None)
    first, _ = _reads(sqlite_client, svc, f"{API}/jobs/{job_id}")
    again, queries = _reads(sqlite_client, svc, f"{API}/jobs/{job_id}")
    assert queries > 0  # read again: its queue time moves with the clock
    assert again["queue_time_s"] >= first["queue_time_s"]
    assert not settled(job_out(svc.store.get_job(job_id)))


def test_kept_answers_equal_answers_read_from_the_records(two_jobs, monkeypatch):
    client, svc, ids = two_jobs
    paths = (f"{API}/jobs?limit=1&offset=1", f"{API}/jobs/{ids[1]}", f"{API}/jobs?kind=all")
    with monkeypatch.context() as m:  # no counter: FastAPI serialises the records' models
        m.setattr(svc.store, "data_version", lambda: None)
        fresh = [client.get(p).json() for p in paths]
    for path, expected in zip(paths, fresh, strict=True):
        for encoding in ("identity", "gzip"):  # made, then from memory, in both encodings
            r = client.get(path, headers={"Accept-Encoding": encoding})
            assert r.json() == expected
    assert client.get(f"{API}/jobs?limit=1").json()["limit"] == 1


def test_start_up_objects_are_kept_out_of_full_collections(make_client):
    """With ``gc_freeze`` (the service's default) the app's start-up freezes the objects made
    so far, so the collector's full passes stop scanning them (their pauses were the tail of
    the read latency, docs/service.md)."""
    import gc

    gc.unfreeze()
    try:
        make_client(gc_freeze=True)
        assert gc.get_freeze_count() > 0
    finally:
        gc.unfreeze()

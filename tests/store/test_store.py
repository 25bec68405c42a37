"""The job store on SQLite and PostgreSQL: records, claims, progress, cancellation, lost
workers, studies, workers seen, schema creation and migration."""

from __future__ import annotations

import pytest
from sqlalchemy import inspect, text

from flexride.store import Job, JobStore, Study, create_store_engine, init_db, now
from service.svc_testkit import pg_schema


@pytest.fixture(params=["sqlite", "postgresql"])
def store(request, tmp_path):
    if request.param == "sqlite":
        yield JobStore.from_url(f"sqlite:///{tmp_path / 's.db'}")
    else:
        with pg_schema() as url:
            yield JobStore.from_url(url)


def _job(i=0, **kw):
    t = now() + i * 1e-3
    values = dict(id=f"{i:032x}", name=f"job{i}", status="queued", created_at=t, updated_at=t,
                  runner="embedded", max_attempts=2, attempts=0, cancel_requested=False,
                  scenario_hash=f"h{i}", scenario={"speed_kmh": 80}, axes={}, run_meta={},
                  progress=0.0, message="queued")
    values.update(kw)
    return Job(**values)


def test_add_get_list_filter_page(store):
    store.add([_job(i) for i in range(5)])
    job = store.get_job(f"{3:032x}", scenario=True)
    assert job.name == "job3" and job.scenario == {"speed_kmh": 80}
    items, total = store.list_jobs(limit=2)
    assert total == 5 and [j.name for j in items] == ["job4", "job3"]
    items, total = store.list_jobs(limit=2, offset=4)
    assert [j.name for j in items] == ["job0"]
    assert store.list_jobs(status="running")[1] == 0
    assert store.get_job("nope") is None
    assert store.counts() == {"queued": 5}
    assert store.ping() >= 0


def test_claim_runs_a_job_once_and_takes_over_only_from_lost_workers(store):
    store.add([_job(1)])
    jid = f"{1:032x}"
    c = store.claim(jid, "w-1@h", stale_before=now() - 60)
    assert c.claimed and c.job.attempts == 1 and c.job.scenario == {"speed_kmh": 80}
    again = store.claim(jid, "w-2@h", stale_before=now() - 60)
    assert not again.claimed and again.reason == "running elsewhere"
    # the first worker is known dead: immediate takeover, attempt 2
    c2 = store.claim(jid, "w-2@h", stale_before=now() - 60, dead=lambda n: n == "w-1@h")
    assert c2.claimed and c2.job.attempts == 2 and "previous attempt lost" in c2.job.message
    assert not store.report_progress(jid, "w-1@h", 0.5, "late")  # the old owner is ignored
    assert store.report_progress(jid, "w-2@h", 0.5, "half")
    # attempts used up: a stale job is failed, not run a third time
    c3 = store.claim(jid, "w-3@h", stale_before=now() + 1)
    assert not c3.claimed and c3.reason == "failed"
    job = store.get_job(jid)
    assert job.status == "failed" and "lost 2 time(s)" in job.error


def test_claim_next_takes_the_oldest_queued_job_of_its_runner(store):
    store.add([_job(1), _job(2), _job(3, runner="celery")])
    c = store.claim_next("embedded", "w@h", stale_before=now() - 60)
    assert c.claimed and c.job.name == "job1"
    assert store.claim_next("embedded", "w@h", stale_before=now() - 60).job.name == "job2"
    assert store.claim_next("embedded", "w@h", stale_before=now() - 60) is None


def test_progress_cancel_finish(store):
    store.add([_job(1), _job(2)])
    a, b = f"{1:032x}", f"{2:032x}"
    store.claim(a, "w@h", stale_before=0)
    assert store.report_progress(a, "w@h", 0.25, "quarter")
    assert store.get_job(a).progress == 0.25 and not store.should_stop(a, "w@h")
    assert store.request_cancel(a).cancel_requested
    assert store.should_stop(a, "w@h")
    assert store.finish(a, "w@h", "cancelled", message="stopped")
    assert not store.finish(a, "w@h", "succeeded")  # no longer running: ignored
    assert store.get_job(a).status == "cancelled"
    queued = store.request_cancel(b)
    assert queued.status == "cancelled"
    assert not store.claim(b, "w@h", stale_before=0).claimed
    assert store.should_stop("missing", "w@h")
    with pytest.raises(ValueError):
        store.finish(a, "w@h", "running")


def test_lost_worker_requeues_then_fails(store):
    store.add([_job(1)])
    jid = f"{1:032x}"
    store.claim(jid, "w@h", stale_before=0)
    assert store.worker_lost(jid, "other@h", "x") is None  # not its job
    assert store.worker_lost(jid, "w@h", "worker died") == "queued"
    assert "requeued after attempt 1: worker died" in store.get_job(jid).message
    store.claim(jid, "w2@h", stale_before=0)
    assert store.stale_running(now() + 1)[0].id == jid
    assert store.worker_lost(jid, "w2@h", "no heartbeat") == "failed"
    job = store.get_job(jid)
    assert job.status == "failed" and "gave up after 2 attempt(s)" in job.error


def test_interrupted_job_is_requeued_without_counting_the_attempt(store):
    store.add([_job(1)])
    jid = f"{1:032x}"
    store.claim(jid, "w@h", stale_before=0)
    assert [j.id for j in store.running_on(["w@h"])] == [jid]
    assert [j.id for j in store.running_jobs("embedded")] == [jid]
    assert store.requeue_interrupted("w@h", "service stop")
    job = store.get_job(jid)
    assert job.status == "queued" and job.attempts == 0
    assert store.queued_ids("embedded") == [jid]


def test_reusable_results_studies_and_delete(store):
    t = now()
    study = Study(id="s" * 32, name="st", description="", created_at=t, n_jobs=2, axes=[],
                  spec={"a": 1})
    store.add([_job(1, study_id=study.id, study_index=0, scenario_hash="same"),
               _job(2, study_id=study.id, study_index=1, status="succeeded",
                    scenario_hash="same", result_file="f.h5", finished_at=t,
                    summary={"ok": True})], study)
    assert store.find_reusable("same").id == f"{2:032x}"
    assert store.find_reusable("other") is None
    assert [j.study_index for j in store.study_jobs(study.id)] == [0, 1]
    assert store.get_study(study.id, spec=True).spec == {"a": 1}
    assert store.list_studies()[1] == 1
    assert store.study_status_counts([study.id]) == {study.id: {"queued": 1, "succeeded": 1}}
    gone, jobs = store.delete_study(study.id)
    assert gone.id == study.id and len(jobs) == 2
    assert store.get_job(f"{1:032x}") is None
    assert store.delete_study(study.id) == (None, [])
    store.add([_job(3)])
    assert store.delete_job(f"{3:032x}").name == "job3" and store.delete_job("x") is None


def test_workers_seen(store):
    store.worker_seen("embedded-1@h", "embedded", "h", 1, None)
    store.worker_seen("embedded-1@h", "embedded", "h", 1, "j")
    (w,) = store.workers()
    assert w.current_job == "j" and w.last_seen >= w.started_at
    assert store.workers(seen_after=now() + 10) == []
    assert store.forget_workers(now() + 10) == 1
    store.worker_seen("x@h", "celery", "h", 2)
    store.worker_gone("x@h")
    assert store.workers() == []


def test_schema_is_created_once_and_migrated(tmp_path):
    url = f"sqlite:///{tmp_path / 'old.db'}"
    engine = create_store_engine(url)
    with engine.begin() as conn:  # an "old" store whose jobs table lacks a newer column
        conn.execute(text("CREATE TABLE flexride_jobs (id VARCHAR(32) PRIMARY KEY, "
                          "name VARCHAR(120), status VARCHAR(16))"))
    init_db(engine)
    init_db(engine)  # idempotent
    cols = {c["name"] for c in inspect(engine).get_columns("flexride_jobs")}
    assert {"scenario_hash", "summary", "heartbeat_at", "axes"} <= cols
    from flexride.store.db import current_revision, head_revision

    assert current_revision(engine) == head_revision()
    engine.dispose()


def test_reuse_lookup_reads_the_newest_entry_of_its_index(tmp_path):
    """The newest succeeded job with a hash comes from the end of ix_flexride_jobs_reuse (no
    sort of every job with that hash: a scenario submitted 1,600 times made each submission
    cost 84 ms before the index), and it is the newest of many."""
    store = JobStore.from_url(f"sqlite:///{tmp_path / 's.db'}")
    t = now()
    store.add([_job(i, status="succeeded", scenario_hash="same", result_file=f"{i}.h5",
                    finished_at=t + i) for i in range(200)])
    assert store.find_reusable("same").id == f"{199:032x}"
    query = ("SELECT id FROM flexride_jobs WHERE kind = 'simulation' AND scenario_hash = 'same' "
             "AND status = 'succeeded' AND result_file IS NOT NULL "
             "ORDER BY finished_at DESC LIMIT 1")
    with store.engine.connect() as conn:
        plan = " | ".join(row[-1] for row in conn.execute(text("EXPLAIN QUERY PLAN " + query)))
    assert "ix_flexride_jobs_reuse" in plan and "TEMP B-TREE" not in plan, plan

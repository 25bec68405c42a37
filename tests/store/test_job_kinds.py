"""Job kinds in the store (SQLite and PostgreSQL): simulations and FE export builds share the
table and the runner, never reuse each other's results, are listed apart, and an FE build is
added once per content key while one is queued or running, however many callers ask at once."""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor

import pytest

from flexride.store import Job, JobStore, now
from flexride.store.db import create_store_engine
from flexride.study.submit import new_id
from service.svc_testkit import pg_schema


@pytest.fixture(params=["sqlite", "postgresql"])
def url(request, tmp_path):
    if request.param == "sqlite":
        yield f"sqlite:///{tmp_path / 's.db'}"
    else:
        with pg_schema() as u:
            yield u


def _job(kind="simulation", key="k", status="queued", **kw):
    t = now()
    values = dict(id=new_id(), kind=kind, name=f"{kind} {key}", status=status, created_at=t,
                  updated_at=t, runner="none", max_attempts=2, attempts=0,
                  cancel_requested=False, scenario_hash=key, scenario={}, axes={},
                  run_meta={}, progress=0.0, message=status)
    values.update(kw)
    return Job(**values)


def test_a_job_is_a_simulation_unless_told(url):
    store = JobStore.from_url(url)
    t = now()
    store.add([Job(id="a" * 32, name="old-style", status="queued", created_at=t, updated_at=t,
                   runner="none", max_attempts=2, attempts=0, cancel_requested=False,
                   scenario_hash="h", scenario={}, axes={}, run_meta={}, progress=0.0,
                   message="queued")])
    assert store.get_job("a" * 32).kind == "simulation"


def test_reuse_and_lists_keep_the_kinds_apart(url):
    store = JobStore.from_url(url)
    fe = _job("fe_export", "same", "succeeded", result_file="x.h5", finished_at=now())
    store.add([fe])
    assert store.find_reusable("same") is None  # an FE job is never a simulation's result
    assert store.find_reusable("same", kind="fe_export").id == fe.id
    sim = _job("simulation", "same", "succeeded", result_file="y.h5", finished_at=now() + 1)
    store.add([sim])
    assert store.find_reusable("same").id == sim.id
    assert [j.id for j in store.list_jobs()[0]] == [sim.id]
    assert [j.id for j in store.list_jobs(kind="fe_export")[0]] == [fe.id]
    items, total = store.list_jobs(kind=None)
    assert total == 2 and {j.id for j in items} == {sim.id, fe.id}
    assert store.latest_job("fe_export", "same").id == fe.id
    assert store.latest_job("fe_export", "other") is None


def test_one_active_fe_job_per_key_under_concurrent_callers(url):
    """16 callers at once, over two engines (two API processes): one job is added, every
    caller gets it; once it is finished, the next caller adds a new one."""
    stores = [JobStore.from_url(url), JobStore(create_store_engine(url))]
    barrier = threading.Barrier(16)

    def add(i):
        barrier.wait(10)
        return stores[i % 2].add_unless_active(_job("fe_export", "key1"))

    with ThreadPoolExecutor(16) as pool:
        results = list(pool.map(add, range(16)))
    assert sum(created for _, created in results) == 1
    assert len({job.id for job, _ in results}) == 1
    store = stores[0]
    assert store.count_active("fe_export") == 1
    (only,) = store.list_jobs(kind="fe_export")[0]
    # a simulation with the same hash, or another key, is another job
    assert store.add_unless_active(_job("simulation", "key1"))[1]
    assert store.add_unless_active(_job("fe_export", "key2"))[1]
    assert store.count_active("fe_export") == 2
    # running still counts as active; a finished one does not
    assert store.claim(only.id, "w-1@h", stale_before=now() - 60).claimed
    assert not store.add_unless_active(_job("fe_export", "key1"))[1]
    assert store.finish(only.id, "w-1@h", "failed", error="boom")
    job, created = store.add_unless_active(_job("fe_export", "key1"))
    assert created and job.id != only.id
    assert store.latest_job("fe_export", "key1").id == job.id
    stores[1].engine.dispose()

"""Running one job end to end in this process (the code both runners and the Celery task use):
success with file and summary, cancellation, failures recorded with their text, claims."""

from __future__ import annotations

import pytest

from flexride.errors import ResultsFileError
from flexride.results import Results
from flexride.scenario.loading import resolve_scenario
from flexride.store import Job, JobStore, ResultFiles, now
from flexride.study.run_job import JobContext, claim_and_run
from flexride.study.scenarios import scenario_hash
from service.svc_testkit import make_settings


@pytest.fixture
def ctx(tmp_path):
    settings = make_settings(tmp_path, heartbeat_interval_s=0.2)
    return JobContext(store=JobStore.from_url(settings.effective_database_url),
                      files=ResultFiles(settings.results_dir), settings=settings,
                      worker="test-1@here")


def _add(ctx, overrides, **kw):
    scenario = resolve_scenario(preset="paper-random-straight-80", overrides=overrides)
    t = now()
    job = Job(id=kw.pop("id", "a" * 32), name="t", status="queued", created_at=t, updated_at=t,
              runner="embedded", max_attempts=2, attempts=0, cancel_requested=False,
              scenario_hash=scenario_hash(scenario), scenario=scenario.model_dump(mode="json"),
              axes={}, run_meta={}, progress=0.0, message="queued", **kw)
    ctx.store.add([job])
    return job.id


def test_a_job_runs_to_results_and_summary(ctx):
    job_id = _add(ctx, {"duration_s": 1.5, "distance_m": None})
    assert claim_and_run(job_id, ctx) == "succeeded"
    job = ctx.store.get_job(job_id, summary=True)
    assert job.status == "succeeded" and job.progress == 1.0 and job.attempts == 1
    assert job.result_file == f"{job_id}.h5" and job.wall_time_s > 0
    assert job.run_meta["speed_kmh"] == 80.0 and job.heartbeat_at >= job.started_at
    assert "PR" in job.summary["points"]
    res = Results.read_hdf5(ctx.files.path(job.result_file))
    assert res.time[-1] == pytest.approx(1.5, abs=0.01)
    assert claim_and_run(job_id, ctx) == "succeeded"  # a duplicate message runs nothing
    assert ctx.store.get_job(job_id).attempts == 1
    assert claim_and_run("b" * 32, ctx) == "missing"


def test_cancel_requested_while_running_stops_the_solver(ctx, monkeypatch):
    import flexride.study.run_job as rj

    monkeypatch.setattr(rj, "PROGRESS_INTERVAL_S", 0.0)
    job_id = _add(ctx, {"duration_s": 20.0, "distance_m": None,
                        "solver.progress_every_steps": 500})
    original = ctx.store.report_progress
    calls = []

    def report(jid, worker, frac, msg):  # ask for cancellation from "another process"
        calls.append(frac)
        if frac > 0.01:
            ctx.store.request_cancel(jid)
        return original(jid, worker, frac, msg)

    monkeypatch.setattr(ctx.store, "report_progress", report)
    assert claim_and_run(job_id, ctx) == "cancelled"
    job = ctx.store.get_job(job_id)
    assert job.status == "cancelled" and "cancelled at t" in job.message
    assert max(calls) < 0.2 and not ctx.files.exists(f"{job_id}.h5")


def test_failures_are_recorded_with_their_text(ctx, monkeypatch):
    job_id = _add(ctx, {"duration_s": 1.0, "distance_m": None, "solver.dt": 1e-3})
    assert claim_and_run(job_id, ctx) == "failed"
    job = ctx.store.get_job(job_id)
    assert "use solver.dt" in job.error and job.message == "failed: StabilityError"

    import flexride.solver as solver

    def boom(*a, **k):
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(solver, "simulate", boom)
    other = _add(ctx, {"duration_s": 1.0, "distance_m": None}, id="c" * 32)
    assert claim_and_run(other, ctx) == "failed"
    assert ctx.store.get_job(other).error == "internal error: RuntimeError: disk on fire"


def test_a_job_deleted_while_running_leaves_no_file(ctx, monkeypatch):
    job_id = _add(ctx, {"duration_s": 1.0, "distance_m": None})
    real_write = Results.write_hdf5

    def write_then_delete(self, path):
        out = real_write(self, path)
        ctx.store.delete_job(job_id)  # the user deletes the job meanwhile
        return out

    monkeypatch.setattr(Results, "write_hdf5", write_then_delete)
    assert claim_and_run(job_id, ctx) == "deleted"
    with pytest.raises(ResultsFileError):
        ctx.files.path("not a name")
    assert not ctx.files.exists(f"{job_id}.h5")

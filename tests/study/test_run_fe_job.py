"""An FE export job run by the workers' code path (:func:`flexride.study.run_job.claim_and_run`,
as the embedded runner and the Celery task do), with a stand-in build given through the job
context: the export written atomically where the API serves it, progress messages, the
heartbeat during the build, failures recorded with their origin, cancellation."""

from __future__ import annotations

import json
import time
from dataclasses import asdict

import pytest

from flexride import __version__
from flexride.errors import FEModelError
from flexride.fem.export import ExportSpec, export_path
from flexride.scenario.bodies import BodyModel
from flexride.scenario.presets import load_preset
from flexride.store import Job, JobStore, ResultFiles, now
from flexride.study.run_job import JobContext, claim_and_run
from service.svc_testkit import fake_fe_export, make_settings

SPEC = ExportSpec.create("carbody", load_preset("paper-metro").vehicle,
                         BodyModel(element_size_m=0.5, cutoff_hz=30.0), 6)


@pytest.fixture
def settings(tmp_path):
    return make_settings(tmp_path, heartbeat_interval_s=0.1)


def _ctx(settings, build=fake_fe_export):
    return JobContext(store=JobStore.from_url(settings.effective_database_url),
                      files=ResultFiles(settings.results_dir), settings=settings,
                      worker="test-1@here", fe_build=build)


def _add(ctx, spec=SPEC, key=None, **kw):
    t = now()
    job = Job(id=kw.pop("id", "e" * 32), kind=kw.pop("kind", "fe_export"), name="fe",
              status="queued", created_at=t, updated_at=t, runner="none", max_attempts=2,
              attempts=0, cancel_requested=False, scenario_hash=key or spec.key,
              scenario=asdict(spec), axes={}, run_meta={}, progress=0.0, message="queued", **kw)
    ctx.store.add([job])
    return job.id


def test_the_export_is_written_where_the_api_serves_it(settings):
    seen = []

    def build(spec, progress):
        seen.append(ctx.store.get_job(job_id).message)  # what the API shows meanwhile
        progress(0.4, "building the FE model of the car body (eigenmodes)")
        seen.append(ctx.store.get_job(job_id).message)
        time.sleep(0.5)  # a build without progress: the heartbeat keeps the record fresh
        job = ctx.store.get_job(job_id)
        seen.append(job.heartbeat_at - job.started_at)
        return fake_fe_export(spec)

    ctx = _ctx(settings, build)
    job_id = _add(ctx)
    assert claim_and_run(job_id, ctx) == "succeeded"
    assert seen[:2] == ["building the FE model of the car body",
                        "building the FE model of the car body (eigenmodes)"]
    assert seen[2] >= 0.3
    dest = export_path(settings.cache_dir, SPEC.key)
    assert dest == settings.cache_dir / f"fe-export-{__version__}" / f"{SPEC.key}.json"
    assert json.loads(dest.read_text()) == fake_fe_export(SPEC)
    assert [p.name for p in dest.parent.iterdir()] == [dest.name]  # no temporary file left
    job = ctx.store.get_job(job_id)
    assert (job.status, job.progress, job.message, job.error) == ("succeeded", 1.0, "done", None)
    assert job.result_file is None and job.run_meta["export"] == dest.name
    assert claim_and_run(job_id, ctx) == "succeeded"  # a duplicate message runs nothing


@pytest.mark.parametrize(("error", "origin", "words"), [
    (FEModelError("car body: no elastic mode below the cut-off"), "input", "no elastic mode"),
    (MemoryError("cannot allocate"), "internal", "internal error: MemoryError"),
])
def test_failures_are_recorded_with_their_origin(settings, error, origin, words):
    def build(spec, progress):
        raise error

    ctx = _ctx(settings, build)
    job_id = _add(ctx)
    assert claim_and_run(job_id, ctx) == "failed"
    job = ctx.store.get_job(job_id)
    assert words in job.error and job.run_meta == {"error_type": type(error).__name__,
                                                   "error_origin": origin}
    assert not export_path(settings.cache_dir, SPEC.key).exists()


def test_an_unwritable_export_directory_is_a_storage_failure(settings):
    blocker = export_path(settings.cache_dir, SPEC.key).parent
    blocker.parent.mkdir(parents=True)
    blocker.write_text("not a directory")
    ctx = _ctx(settings)
    job_id = _add(ctx)
    assert claim_and_run(job_id, ctx) == "failed"
    job = ctx.store.get_job(job_id)
    assert job.error.startswith("storage unavailable") and job.run_meta["error_origin"] == "storage"


def test_a_spec_of_another_flexride_version_is_not_built(settings):
    ctx = _ctx(settings)
    job_id = _add(ctx, key="0" * 32)
    assert claim_and_run(job_id, ctx) == "failed"
    job = ctx.store.get_job(job_id)
    assert "content key" in job.error and job.run_meta["error_origin"] == "internal"


def test_an_unknown_kind_fails_with_the_reason(settings):
    ctx = _ctx(settings)
    job_id = _add(ctx, kind="mesh")
    assert claim_and_run(job_id, ctx) == "failed"
    assert "unknown job kind 'mesh'" in ctx.store.get_job(job_id).error


def test_a_cancel_during_the_build_leaves_no_export(settings):
    def build(spec, progress):
        ctx.store.request_cancel(job_id)  # from "another process" while the build runs
        return fake_fe_export(spec)

    ctx = _ctx(settings, build)
    job_id = _add(ctx)
    assert claim_and_run(job_id, ctx) == "cancelled"
    assert "no export written" in ctx.store.get_job(job_id).message
    assert not export_path(settings.cache_dir, SPEC.key).exists()
    # a queued job cancelled before a worker claims it never runs
    other = _add(ctx, id="f" * 32)
    ctx.store.request_cancel(other)
    assert claim_and_run(other, ctx) == "cancelled"

"""Evaluated sections of study jobs: the paper report's rules (flexride.paper.plan.section_of)
applied to a job's scenario, the worker's analysis of the section, the tables' use of it."""

from __future__ import annotations

import pytest

from flexride.analysis import analyze
from flexride.paper.plan import full_window
from flexride.paper.record import window_results
from flexride.results import Results
from flexride.scenario.loading import resolve_scenario
from flexride.store import Job, JobStore, ResultFiles, now
from flexride.study.aggregate import study_tables
from flexride.study.expand import expand_study
from flexride.study.run_job import JobContext, claim_and_run
from flexride.study.scenarios import scenario_hash
from flexride.study.sections import job_section
from flexride.study.summary_values import summary_value
from service.svc_testkit import make_settings

HALF = 12.6 / 2 + 2.2 / 2  # paper vehicle: bogie spacing and wheelbase (m)


def test_sections_follow_the_reports_rules():
    curve = resolve_scenario(preset="paper-random-curve-50")
    arc = job_section(curve)
    # the curve starts at 40 m, 55 m transitions, 200 m arc: by hand
    assert arc["rule"] == "arc"
    assert (arc["start_m"], arc["end_m"]) == pytest.approx((95 + HALF, 295 - HALF))
    assert (arc["start_m"], arc["end_m"]) == pytest.approx(full_window("random-curve")[:2])
    whole = job_section(curve, "curve")
    assert (whole["start_m"], whole["end_m"]) == pytest.approx((40 + HALF, 350 - HALF))
    assert "102.4–287.6 m" in arc["label"] and "circular arc" in arc["label"]
    straight = job_section(resolve_scenario(preset="paper-corrugation-80"))
    assert straight["rule"] == "after-fade-in" and straight["start_m"] == 30.0
    assert straight["end_m"] == pytest.approx(full_window("corrugation")[1])
    assert job_section(resolve_scenario(preset="paper-settlement-80")) is None  # whole run
    assert job_section(curve, "run") is None
    short = resolve_scenario(preset="paper-random-straight-80",
                             overrides={"duration_s": 5.5, "distance_m": None})
    assert job_section(short) is None  # 30–122 m is 4.1 s < 6 s: the whole run


def test_study_jobs_carry_their_sections():
    plan = expand_study({"preset": "paper-table3", "speeds_kmh": [80.0]}, max_jobs=100)
    rules = {j.axes["condition"]: (j.section or {}).get("rule") for j in plan.jobs}
    assert rules == {"random-straight": "after-fade-in", "random-curve": "arc",
                     "corrugation": "after-fade-in", "settlement": None}
    plan = expand_study({"preset": "paper-table3", "speeds_kmh": [80.0], "section": "run"},
                        max_jobs=100)
    assert all(j.section is None for j in plan.jobs)


def test_the_worker_analyses_the_section(tmp_path):
    settings = make_settings(tmp_path)
    ctx = JobContext(store=JobStore.from_url(settings.effective_database_url),
                     files=ResultFiles(settings.results_dir), settings=settings,
                     worker="test-1@here")
    scenario = resolve_scenario(preset="paper-random-straight-80",
                                overrides={"duration_s": 8.0, "distance_m": None})
    section = {"rule": "after-fade-in", "start_m": 30.0, "end_m": 170.0, "label": "x"}
    t = now()
    ctx.store.add([Job(id="c" * 32, name="t", status="queued", created_at=t, updated_at=t,
                       runner="embedded", max_attempts=1, attempts=0, cancel_requested=False,
                       scenario_hash=scenario_hash(scenario),
                       scenario=scenario.model_dump(mode="json"), axes={},
                       run_meta={"section": section}, progress=0.0, message="queued")])
    assert claim_and_run("c" * 32, ctx) == "succeeded"
    job = ctx.store.get_job("c" * 32, summary=True)
    assert job.run_meta["section"] == section
    sec = job.summary["section"]
    # oracle: the stored results cut and analysed here
    res = Results.read_hdf5(ctx.files.path(job.result_file))
    ref = analyze(window_results(res, (30.0, 170.0))).to_dict()
    for q in ("peak", "rms"):
        assert summary_value(sec["summary"], "PC", "z", q) == pytest.approx(
            summary_value(ref, "PC", "z", q))
    assert sec["summary"]["run"]["duration_s"] == pytest.approx(140.0 / (80 / 3.6), abs=2e-3)
    assert summary_value(sec["summary"], "PC", "z", "rms") != summary_value(
        job.summary, "PC", "z", "rms")  # the whole run's differs
    row = study_tables([{"id": "c", "axes": {"speed_kmh": 80.0}, "speed_kmh": 80.0,
                         "status": "succeeded", "summary": job.summary}])["peak_vs_speed"]
    pc = next(r for r in row if r["point"] == "PC" and r["direction"] == "z")
    assert pc["value"] == [summary_value(ref, "PC", "z", "peak")] and pc["sections"] == ["x"]

"""The paper report as a kind of study: ``POST /studies`` with the ``paper-report`` preset.

Its jobs are the runs of ``flexride.paper.plan.build_plan`` (the CLI's plan, checked against it
here), its other fields are refused, its report is served once built. The end-to-end test runs
on the embedded runner with the plan replaced by the tiny study of tests/paper (random
irregularity and settlement at 50 km/h, rigid and flexible, ≈ 6 s each, a 0.5 m car body
mesh): 4 runs instead of the quick report's 16 (whose 0.2 m car body alone takes minutes).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from flexride.paper.plan import ReportOptions, build_plan
from service.svc_testkit import make_settings, services, wait_for

API = "/api/v1"
TINY = ReportOptions(conditions=("random-straight", "settlement"), speeds=(50.0,), seeds=1,
                     distance_scale=0.01, jobs=1, mesh_sizes=(),
                     overrides=(("bodies.carbody.element_size_m", 0.5),
                                ("bodies.carbody.cutoff_hz", 30.0),
                                ("bodies.frames.cutoff_hz", 30.0)))


def test_quick_report_study_has_the_plans_runs(client):
    r = client.post(f"{API}/studies", json={"preset": "paper-report", "quick": True,
                                             "seeds": 2})
    assert r.status_code == 201, r.text
    st = r.json()
    plan = build_plan(ReportOptions(quick=True, seeds=2).checked())
    # 2 speeds × (2 random × 2 seeds + 2) × 2 bodies, and Fig. 4's 2 tracks × 3 sizes
    assert st["n_jobs"] == len(plan) == 24 + 6
    assert st["preset"] == "paper-report"
    assert [a["name"] for a in st["axes"]] == ["condition", "speed_kmh", "body_model", "seed",
                                               "bodies.carbody.element_size_m"]
    for job, spec in zip(st["jobs"], plan, strict=True):
        mesh = {} if spec.element_size_m is None else {
            "bodies.carbody.element_size_m": spec.element_size_m}
        assert job["axes"] == {"condition": spec.condition, "speed_kmh": spec.speed_kmh,
                               "body_model": spec.body, "seed": spec.seed or 1, **mesh}
        record = services(client).store.get_job(job["id"])
        section = record.run_meta.get("section")
        if spec.window_m[0] > 0:  # the report's section, analysed by the worker too
            assert [section["start_m"], section["end_m"]] == list(spec.window_m)
        else:
            assert section is None
        scen = client.get(f"{API}/jobs/{job['id']}/scenario").json()
        assert scen == spec.scenario().model_dump(mode="json") | {"name": scen["name"]}
    assert st["report"]["state"] == "waiting" and "0 of 30" in st["report"]["message"]
    r = client.get(f"{API}/studies/{st['id']}/report")
    assert r.status_code == 409 and "not ready" in r.json()["message"]
    assert client.get(f"{API}/studies/{st['id']}/report/summary").status_code == 409


@pytest.mark.parametrize(("extra", "loc"), [
    ({"speeds_kmh": [60]}, ["speeds_kmh"]), ({"overrides": {"duration_s": 1}}, ["overrides"]),
    ({"base": {"preset": "paper-metro"}}, ["base"]), ({"seeds": 21}, ["body", "seeds"])])
def test_report_study_refuses_what_its_plan_fixes(sqlite_client, extra, loc):
    r = sqlite_client.post(f"{API}/studies", json={"preset": "paper-report", **extra})
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"] == loc


def test_quick_only_with_the_report_and_no_report_for_other_studies(sqlite_client):
    c = sqlite_client
    r = c.post(f"{API}/studies", json={"preset": "paper-table2", "quick": True})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["quick"]
    st = c.post(f"{API}/studies", json={"preset": "paper-table2"}).json()
    assert st["report"] is None
    r = c.get(f"{API}/studies/{st['id']}/report")
    assert r.status_code == 404 and "not a paper report study" in r.json()["message"]
    presets = {p["name"]: p for p in c.get(f"{API}/study-presets").json()}
    assert presets["paper-report"]["n_jobs"] == len(build_plan(ReportOptions().checked()))


def _client(data_dir: Path):
    from fastapi.testclient import TestClient

    from flexride.api import create_app

    settings = make_settings(data_dir, runner="embedded", workers=2, heartbeat_interval_s=1.0,
                             heartbeat_timeout_s=60.0, reaper_interval_s=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return TestClient(create_app(settings), raise_server_exceptions=False)


def test_report_study_end_to_end_on_the_embedded_runner(tmp_path, monkeypatch):
    import flexride.study.report as report

    monkeypatch.setattr(report, "report_options", lambda request: TINY.checked())
    data = tmp_path / "data"
    with _client(data) as c:
        st = c.post(f"{API}/studies", json={"preset": "paper-report", "quick": True})
        assert st.status_code == 201, st.text
        sid = st.json()["id"]
        assert st.json()["n_jobs"] == 4
        final = wait_for(lambda: (s := c.get(f"{API}/studies/{sid}").json())["report"]["state"]
                         in ("ready", "failed") and s, 900.0, 1.0, "the report")
        assert final["report"]["state"] == "ready", final["report"]
        assert final["counts"] == {"succeeded": 4}
        sections = {sec for r in final["tables"]["peak_vs_speed"] for sec in r["sections"]}
        assert any(sec.startswith("report (the paper report's section) 30.0–")
                   for sec in sections), sections  # random-straight: the report's stretch
        assert "whole run" in sections  # settlement: the whole run, as in the report
        rep = final["report"]
        assert sum(rep["counts"].values()) > 50 and rep["links"]["html"].endswith("/report")
        page = c.get(rep["links"]["html"])
        assert page.status_code == 200 and page.headers["content-type"].startswith("text/html")
        assert "Dynamic evaluation on ride comfort" in page.text and "<script" in page.text
        assert "wall time of the runs (the service's jobs)" in page.text
        # its own inline scripts only: nothing loaded from or sent to anywhere
        csp = page.headers["content-security-policy"]
        assert "default-src 'none'" in csp and "connect-src 'none'" in csp
        claims = c.get(rep["links"]["summary"]).json()
        assert {"id", "source", "paper", "flexride", "verdict", "note"} <= set(claims[0])
        by_id = {x["id"]: x for x in claims}
        assert by_id["table1.mode1"]["verdict"] in ("reproduced", "not reproduced")
        # the same counts as the job recorded; the files published in one step
        assert sum(1 for x in claims if x["verdict"] == "reproduced") == (
            rep["counts"]["reproduced"])
        reports = data / "results" / "reports"
        assert sorted(p.name for p in reports.iterdir()) == [sid]
        assert {"index.html", "summary.json", "report.json"} <= {
            p.name for p in (reports / sid).iterdir()}
        job = c.get(f"{API}/jobs/{rep['job_id']}")
        assert job.status_code == 200 and job.json()["kind"] == "paper_report", job.text
        listed = c.get(f"{API}/jobs", params={"kind": "all", "limit": 20}).json()["items"]
        assert rep["job_id"] in [j["id"] for j in listed]
        # asking again builds nothing more
        again = c.get(f"{API}/studies/{sid}").json()["report"]
        assert again["job_id"] == rep["job_id"]
        assert c.delete(f"{API}/studies/{sid}").status_code == 204
        assert not (reports / sid).exists()


def test_a_cancelled_report_study_builds_no_report(sqlite_client):
    c = sqlite_client
    st = c.post(f"{API}/studies", json={"preset": "paper-report", "quick": True}).json()
    rep = c.post(f"{API}/studies/{st['id']}/cancel").json()["report"]
    assert rep["state"] == "failed" and "cancelled" in rep["error"]
    assert c.get(f"{API}/jobs", params={"kind": "all"}).json()["total"] == st["n_jobs"]
    r = c.get(f"{API}/studies/{st['id']}/report")
    assert r.status_code == 409 and "cancelled" in r.json()["message"]


def test_finished_runs_queue_one_report_build(client):
    from sqlalchemy import update

    from flexride.store import Job

    st = client.post(f"{API}/studies", json={"preset": "paper-report", "quick": True}).json()
    svc = services(client)
    with svc.store.writing() as s, s.begin():
        s.execute(update(Job).where(Job.study_id == st["id"]).values(
            status="succeeded", progress=1.0, summary={"points": {}}))
    first = client.get(f"{API}/studies/{st['id']}").json()["report"]
    assert first["state"] == "queued" and first["job_id"]
    for _ in range(3):  # asking again queues nothing more
        assert client.get(f"{API}/studies/{st['id']}").json()["report"]["job_id"] == (
            first["job_id"])
    r = client.get(f"{API}/studies/{st['id']}/report/summary")
    assert r.status_code == 409 and "queued" in r.json()["message"]
    jobs = client.get(f"{API}/jobs", params={"kind": "all", "limit": 100}).json()
    assert [j["kind"] for j in jobs["items"]].count("paper_report") == 1
    assert client.delete(f"{API}/studies/{st['id']}").status_code == 204
    assert client.get(f"{API}/jobs", params={"kind": "all"}).json()["total"] == 0


def test_the_reaper_queues_a_finished_studys_report_without_a_reader(client):
    """Nobody reads the study: the service's periodic pass queues its report build once."""
    from sqlalchemy import update

    from flexride.store import Job
    from flexride.study.report import REPORT_KIND, report_key

    st = client.post(f"{API}/studies", json={"preset": "paper-report", "quick": True}).json()
    svc = services(client)
    svc.reaper.run_once()  # runs unfinished: nothing to build
    assert svc.store.latest_job(REPORT_KIND, report_key(st["id"])) is None
    with svc.store.writing() as s, s.begin():
        s.execute(update(Job).where(Job.study_id == st["id"]).values(
            status="succeeded", progress=1.0, summary={"points": {}}))
    svc.reaper.run_once()
    built = svc.store.latest_job(REPORT_KIND, report_key(st["id"]))
    assert built is not None and built.status in ("queued", "running", "failed")
    svc.reaper.run_once()  # a second pass queues nothing more
    assert svc.store.latest_job(REPORT_KIND, report_key(st["id"])).id == built.id
    assert client.delete(f"{API}/studies/{st['id']}").status_code == 204

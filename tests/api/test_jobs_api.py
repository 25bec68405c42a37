"""Jobs API on SQLite and PostgreSQL: submit, validate, list, detail, cancel, delete, reuse."""

from __future__ import annotations

from service.svc_testkit import SHORT, insert_finished_job, services, synthetic_results

UNKNOWN = "5f0c1e9a-0000-4000-8000-00000000abcd"
"""A well-formed job id that no job has."""

API = "/api/v1"


def _submit(client, **body):
    body.setdefault("preset", "paper-random-straight-80")
    body.setdefault("overrides", dict(SHORT))
    return client.post(f"{API}/jobs", json=body)


def test_submit_preset_creates_a_queued_job_with_its_check(client):
    r = _submit(client)
    assert r.status_code == 201, r.text
    job = r.json()
    assert job["status"] == "queued" and job["progress"] == 0.0 and not job["reused"]
    assert job["preset"] == "paper-random-straight-80" and job["duration_s"] == 1.5
    assert job["preflight"]["stability"]["dt_suggested"] > 0
    assert job["links"]["summary"].endswith(f"/jobs/{job['id']}/summary")
    detail = client.get(f"{API}/jobs/{job['id']}").json()
    assert detail["id"] == job["id"] and detail["created_at"].endswith("Z")
    scenario = client.get(f"{API}/jobs/{job['id']}/scenario").json()
    assert scenario["speed_kmh"] == 80.0 and scenario["duration_s"] == 1.5


def test_submit_full_scenario_that_starts_from_a_preset(client):
    r = client.post(f"{API}/jobs", json={"scenario": {"preset": "paper-metro", "speed_kmh": 60,
                                                      "duration_s": 1.0}, "name": "my run"})
    assert r.status_code == 201, r.text
    assert r.json()["name"] == "my run" and r.json()["speed_kmh"] == 60.0


def test_invalid_scenarios_give_422_with_field_paths_and_ranges(client):
    r = _submit(client, overrides={"speed_kmh": 500})
    assert r.status_code == 422
    item = r.json()["detail"][0]
    assert item["loc"] == ["speed_kmh"] and "allowed: ≤ 200" in item["msg"]
    r = client.post(f"{API}/jobs", json={"scenario": {"preset": "paper-metro",
                                                      "vehicle": {"carbody": {"mass": -1}}}})
    assert r.status_code == 422
    assert ["vehicle", "carbody", "mass"] in [i["loc"] for i in r.json()["detail"]]
    for body in ({}, {"preset": "paper-metro", "scenario": {}}, {"preset": "nope"},
                 {"preset": "paper-metro", "overrides": {"a..b": 1}},
                 {"preset": "paper-metro", "overrides": {"excitation.7.seed": 1}},
                 {"preset": "paper-metro", "overrides": {"nonsense": 1}},
                 {"scenario": {"speed_kmh": 50}}, {"preset": "paper-metro", "extra": 1}):
        r = client.post(f"{API}/jobs", json=body)
        assert r.status_code == 422, (body, r.text)
        assert r.json()["detail"], body


def test_unstable_step_is_refused_with_a_step_that_works(client):
    r = _submit(client, overrides={**SHORT, "solver.dt": 1e-3})
    assert r.status_code == 422
    body = r.json()
    assert body["detail"][0]["loc"] == ["scenario", "solver", "dt"]
    assert 0 < body["dt_suggested"] < 1e-3
    ok = _submit(client, overrides={**SHORT, "solver.dt": body["dt_suggested"]})
    assert ok.status_code == 201, ok.text


def test_list_filter_page_cancel_delete(client):
    ids = [_submit(client, overrides={**SHORT, "speed_kmh": v}).json()["id"]
           for v in (50, 60, 70)]
    page = client.get(f"{API}/jobs", params={"limit": 2}).json()
    assert page["total"] == 3 and len(page["items"]) == 2
    assert page["items"][0]["id"] == ids[-1]  # newest first
    assert client.get(f"{API}/jobs", params={"offset": 2}).json()["items"][0]["id"] == ids[0]
    r = client.post(f"{API}/jobs/{ids[0]}/cancel")
    assert r.status_code == 200 and r.json()["status"] == "cancelled"
    assert client.get(f"{API}/jobs", params={"status": "cancelled"}).json()["total"] == 1
    assert client.get(f"{API}/jobs", params={"status": "queued"}).json()["total"] == 2
    assert client.get(f"{API}/jobs", params={"status": "bogus"}).status_code == 422
    assert client.delete(f"{API}/jobs/{ids[1]}").status_code == 204
    assert client.get(f"{API}/jobs/{ids[1]}").status_code == 404
    assert client.delete(f"{API}/jobs/{ids[1]}").status_code == 404
    assert client.post(f"{API}/jobs/{UNKNOWN}/cancel").status_code == 404
    assert client.post(f"{API}/jobs/unknown/cancel").status_code == 422  # not an id
    assert client.get(f"{API}/jobs/{ids[2]}/summary").status_code == 409


def test_identical_scenario_reuses_stored_results_unless_opted_out(client):
    from flexride.scenario.loading import resolve_scenario
    from flexride.study.scenarios import scenario_hash

    svc = services(client)
    digest = scenario_hash(resolve_scenario(preset="paper-random-straight-80", overrides=SHORT))
    src = insert_finished_job(svc.store, svc.files, synthetic_results(), scenario_hash=digest)
    r = _submit(client)
    assert r.status_code == 201
    job = r.json()
    assert job["reused"] and job["status"] == "succeeded" and job["reused_from"] == src
    assert job["has_results"] and job["id"] != src
    summary = client.get(f"{API}/jobs/{job['id']}/summary").json()["summary"]
    assert "PR" in summary["points"]
    # its own file: deleting the source keeps the copy readable
    assert client.delete(f"{API}/jobs/{src}").status_code == 204
    assert client.get(f"{API}/jobs/{job['id']}/download").status_code == 200
    r = _submit(client, reuse=False)
    assert r.json()["status"] == "queued" and not r.json()["reused"]


def test_validate_checks_without_creating_a_job(sqlite_client):
    ok = sqlite_client.post("/api/v1/jobs/validate", json={"preset": "paper-metro",
                                                            "overrides": SHORT})
    assert ok.status_code == 200 and ok.json()["valid"] is True
    assert ok.json()["preflight"]["stability"]["dt_suggested"] > 0
    bad = sqlite_client.post("/api/v1/jobs/validate", json={
        "preset": "paper-metro", "overrides": {**SHORT, "vehicle.carbody.mass": -1}})
    assert bad.status_code == 422 and "vehicle.carbody.mass" in bad.text
    unstable = sqlite_client.post("/api/v1/jobs/validate", json={
        "preset": "paper-metro", "overrides": {**SHORT, "solver.dt": 1e-3}})
    assert unstable.status_code == 422 and unstable.json()["dt_suggested"] > 0
    assert sqlite_client.get("/api/v1/jobs").json()["total"] == 0


def test_job_records_carry_the_timings_of_their_run(client):
    from flexride.results import TIMING_KEYS, run_timings

    svc = services(client)
    results = synthetic_results()
    meta = {**results.meta, "wall_time_setup_s": 0.12, "wall_time_solve_s": 1.5}
    timings = run_timings(meta, 0.05, 0.2)
    assert tuple(timings) == TIMING_KEYS
    done = insert_finished_job(svc.store, svc.files, results,
                               run_meta={**meta, "timings": timings})
    assert client.get(f"{API}/jobs/{done}").json()["timings"] == {
        "setup_s": 0.12, "solve_s": 1.5, "write_s": 0.05, "analyze_s": 0.2}
    queued = _submit(client).json()
    assert queued["timings"] is None

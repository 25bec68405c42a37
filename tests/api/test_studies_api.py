"""Studies API: job matrices from presets and axes, detail tables, cancel, delete."""

from __future__ import annotations

import copy

import pytest
from sqlalchemy import update

from flexride.store import Job
from service.svc_testkit import services

API = "/api/v1"
QUICK = {"duration_s": 1.0, "distance_m": None}


def _fake_summary(speed: float, flexible: bool) -> dict:
    """A summary dict whose values are known functions of speed."""
    k = 1.1 if flexible else 1.0
    dirs = {d: {"peaks": {"max_abs": k * (0.01 * speed + (0.1 if d == "z" else 0.0)),
                          "rms": k * 0.001 * speed},
                "sperling": {"value": k * (1.0 + 0.01 * speed)},
                "iso2631": {"Wb" if d == "z" else "Wd": {"a_w": k * 0.002 * speed}}}
            for d in ("z", "y")}
    return {"points": {"PC": {"directions": dirs}, "PR": {"directions": copy.deepcopy(dirs)}}}


def _finish_all(client, study_id):
    svc = services(client)
    jobs = svc.store.study_jobs(study_id)
    with svc.store.writing() as s, s.begin():
        for j in jobs:
            flexible = j.axes.get("body_model") == "flexible"
            s.execute(update(Job).where(Job.id == j.id).values(
                status="succeeded", progress=1.0,
                summary=_fake_summary(j.speed_kmh, flexible)))


def test_paper_table3_preset_makes_16_jobs(client):
    r = client.post(f"{API}/studies", json={"preset": "paper-table3", "overrides": QUICK})
    assert r.status_code == 201, r.text
    study = r.json()
    assert study["n_jobs"] == 16 and study["status"] == "queued" and len(study["jobs"]) == 16
    assert [a["name"] for a in study["axes"]] == ["condition", "speed_kmh", "body_model"]
    combos = {(j["axes"]["condition"], j["axes"]["speed_kmh"]) for j in study["jobs"]}
    assert len(combos) == 16 and ("settlement", 60.0) in combos
    jobs = client.get(f"{API}/jobs", params={"study_id": study["id"], "limit": 100}).json()
    assert jobs["total"] == 16 and all(j["duration_s"] == 1.0 for j in jobs["items"])
    curve = next(j for j in study["jobs"] if j["axes"]["condition"] == "random-curve")
    scen = client.get(f"{API}/jobs/{curve['id']}/scenario").json()
    assert scen["line"]["kind"] == "curve" and scen["line"]["radius_m"] == 800.0
    listed = client.get(f"{API}/studies").json()
    assert listed["total"] == 1 and listed["items"][0]["counts"] == {"queued": 16}


def test_tables_sperling_and_peak_vs_speed_with_fit(sqlite_client):
    c = sqlite_client
    study = c.post(f"{API}/studies", json={
        "name": "speeds", "base": {"preset": "paper-metro", "overrides": QUICK},
        "conditions": ["random-straight", "settlement"], "speeds_kmh": [50, 60, 80],
        "overrides": QUICK}).json()
    assert study["n_jobs"] == 6
    _finish_all(c, study["id"])
    detail = c.get(f"{API}/studies/{study['id']}").json()
    assert detail["status"] == "succeeded" and detail["progress"] == 1.0
    tables = detail["tables"]
    rows = [r for r in tables["peak_vs_speed"]
            if r["point"] == "PC" and r["direction"] == "z"
            and r["group"] == {"condition": "settlement"}]
    assert len(rows) == 1
    row = rows[0]
    assert row["speed_kmh"] == [50.0, 60.0, 80.0]
    assert row["fit"]["slope"] == pytest.approx(0.01) and row["fit"]["r_squared"] == (
        pytest.approx(1.0))
    assert row["fit"]["intercept"] == pytest.approx(0.1)
    sp = [r for r in tables["sperling_vs_speed"] if r["point"] == "PR" and r["direction"] == "y"]
    assert len(sp) == 2 and sp[0]["value"] == pytest.approx([1.5, 1.6, 1.8])
    assert tables["flexible_vs_rigid"] == []


def test_flexible_vs_rigid_differences(sqlite_client, monkeypatch):
    import flexride.study.scenarios as scen

    monkeypatch.setattr(scen, "flexible_available", lambda: True)  # FE side not needed here
    c = sqlite_client
    study = c.post(f"{API}/studies", json={"preset": "paper-table2", "overrides": QUICK})
    assert study.status_code == 201, study.text
    study = study.json()
    assert {j["axes"]["body_model"] for j in study["jobs"]} == {"rigid", "flexible"}
    flex = next(j for j in study["jobs"] if j["axes"]["body_model"] == "flexible")
    scen_f = c.get(f"{API}/jobs/{flex['id']}/scenario").json()
    assert scen_f["bodies"]["carbody"]["model"] == scen_f["bodies"]["frames"]["model"] == (
        "flexible")
    _finish_all(c, study["id"])
    rows = c.get(f"{API}/studies/{study['id']}").json()["tables"]["flexible_vs_rigid"]
    row = next(r for r in rows if r["point"] == "PC" and r["direction"] == "z"
               and r["quantity"] == "sperling")
    assert row["speed_kmh"] == 80.0
    assert row["relative"] == pytest.approx(0.1)
    assert row["flexible"] - row["rigid"] == pytest.approx(row["difference"])
    assert {r["quantity"] for r in rows} == {"sperling", "a_w", "rms", "peak"}


def test_custom_axes_parameters_and_errors(sqlite_client, make_client):
    c = sqlite_client
    body = {"base": {"preset": "paper-random-straight-80", "overrides": QUICK},
            "conditions": [{"name": "low", "set": {"excitation.0.spectrum": "german-low"}}],
            "parameters": [{"path": "excitation.0.seed", "values": [3, 4]}],
            "overrides": QUICK}
    study = c.post(f"{API}/studies", json=body).json()
    assert study["n_jobs"] == 2
    assert study["jobs"][1]["axes"] == {"condition": "low", "excitation.0.seed": 4}
    scen = c.get(f"{API}/jobs/{study['jobs'][1]['id']}/scenario").json()
    assert scen["excitation"][0]["seed"] == 4
    assert scen["excitation"][0]["spectrum"] == "german-low"
    bad = c.post(f"{API}/studies", json={**body, "parameters": [
        {"path": "vehicle.carbody.mass", "values": [30000, -1]}]})
    assert bad.status_code == 422 and "vehicle.carbody.mass=-1" in bad.json()["message"]
    assert c.post(f"{API}/studies", json={"conditions": ["random-straight"]}).status_code == 422
    r = c.post(f"{API}/studies", json={**body, "conditions": ["nowhere"]})
    assert r.status_code == 422 and "paper conditions" in r.json()["message"]
    assert c.post(f"{API}/studies", json={"preset": "nope"}).status_code == 422
    small = make_client(max_study_jobs=4)
    r = small.post(f"{API}/studies", json={"preset": "paper-table3", "overrides": QUICK})
    assert r.status_code == 422 and "16 jobs" in r.json()["message"]
    assert c.get(f"{API}/studies/{'0' * 32}").status_code == 404
    assert c.get(f"{API}/studies/unknown").status_code == 422  # not an id


def test_cancel_and_delete_a_study(sqlite_client):
    c = sqlite_client
    svc = services(c)
    study = c.post(f"{API}/studies", json={
        "base": {"preset": "paper-metro"}, "speeds_kmh": [50, 60], "overrides": QUICK}).json()
    r = c.post(f"{API}/studies/{study['id']}/cancel")
    assert r.status_code == 200 and r.json()["status"] == "cancelled"
    ids = [j["id"] for j in study["jobs"]]
    assert c.delete(f"{API}/studies/{study['id']}").status_code == 204
    assert c.get(f"{API}/studies/{study['id']}").status_code == 404
    assert all(svc.store.get_job(i) is None for i in ids)


def test_study_presets_endpoints(sqlite_client):
    presets = {p["name"]: p for p in sqlite_client.get(f"{API}/study-presets").json()}
    assert presets["paper-table3"]["n_jobs"] == 16 and presets["paper-table2"]["n_jobs"] == 2
    one = sqlite_client.get(f"{API}/study-presets/paper-table2").json()
    assert one["request"]["body_models"] == ["rigid", "flexible"]
    assert sqlite_client.get(f"{API}/study-presets/nope").status_code == 404


def test_seeds_make_n_jobs_per_condition_with_distinct_seeds(client):
    body = {"name": "seeds", "base": {"preset": "paper-metro", "overrides": QUICK},
            "conditions": ["random-straight", "random-curve"], "speeds_kmh": [60, 80],
            "overrides": QUICK}
    one = client.post(f"{API}/studies", json=body)
    three = client.post(f"{API}/studies", json={**body, "seeds": 3})
    assert one.status_code == three.status_code == 201, three.text
    one, three = one.json(), three.json()
    assert three["n_jobs"] == 3 * one["n_jobs"] == 12
    assert three["axes"][-1] == {"name": "seed", "values": [1, 2, 3]}
    seeds = {}
    for j in three["jobs"]:
        scen = client.get(f"{API}/jobs/{j['id']}/scenario").json()
        key = (j["axes"]["condition"], j["axes"]["speed_kmh"])
        seeds.setdefault(key, []).append(scen["excitation"][0]["seed"])
        assert scen["excitation"][0]["seed"] == j["axes"]["seed"]
    assert len(seeds) == 4 and all(sorted(v) == [1, 2, 3] for v in seeds.values())
    _finish_all(client, three["id"])
    rows = client.get(f"{API}/studies/{three['id']}").json()["tables"]["sperling_vs_speed"]
    assert rows and all(r["n"] == [3, 3] for r in rows)
    assert all(ci == pytest.approx(0.0) for r in rows for ci in r["ci95"])  # equal fakes


@pytest.mark.parametrize("seeds", [0, 21, "many"])
def test_seeds_out_of_range_is_422_with_field_and_range(sqlite_client, seeds):
    r = sqlite_client.post(f"{API}/studies", json={
        "base": {"preset": "paper-metro"}, "seeds": seeds, "overrides": QUICK})
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == ["body", "seeds"], r.text
    if seeds != "many":
        assert ("1" if seeds == 0 else "20") in item["msg"]


def test_mesh_convergence_preset_tables_and_the_fe_limit(sqlite_client, make_client):
    """The paper's Fig. 4 as a study: 2 conditions x 6 car-body sizes, the tables from the
    jobs' air-spring forces and frequencies, and sizes beyond the FE limit refused up front
    with the smallest admissible size."""
    c = sqlite_client
    r = c.post(f"{API}/studies", json={"preset": "mesh-convergence", "overrides": QUICK})
    assert r.status_code == 201, r.text
    study = r.json()
    axis = "bodies.carbody.element_size_m"
    assert study["n_jobs"] == 12
    assert sorted({j["axes"][axis] for j in study["jobs"]}) == [0.1, 0.15, 0.2, 0.3, 0.4, 0.5]
    svc = services(c)
    with svc.store.writing() as s, s.begin():
        for j in svc.store.study_jobs(study["id"]):
            h = j.axes[axis]
            summary = _fake_summary(80.0, True)
            summary["suspension"] = {"secondary.1L": {"z": {
                "mean": 9e4, "rms_dynamic": 100.0 + 2000.0 * h**2,
                "peak_dynamic": 300.0 + 6000.0 * h**2, "max_abs": 9.1e4}}}
            meta = {"flexible_bodies": {"carbody": {"element_size_m": h,
                                                    "elastic_frequencies_hz": [5.0 + h]}}}
            s.execute(update(Job).where(Job.id == j.id).values(
                status="succeeded", progress=1.0, summary=summary, run_meta=meta))
    tables = c.get(f"{API}/studies/{study['id']}").json()["tables"]["mesh_convergence"]
    assert [t["group"]["condition"] for t in tables] == ["smooth-straight", "random-straight"]
    rows = {row["key"]: row for row in tables[0]["rows"]}
    rms = rows["secondary.1L.z.rms_dynamic"]
    assert rms["estimate"]["extrapolated"] == pytest.approx(100.0)
    assert rms["at_reference"] == pytest.approx(0.8)  # 2000 * 0.2^2 / 100
    assert rows["frequency.1"]["estimate"]["order"] == pytest.approx(1.0)
    # the dynamic rms and peak grow; the largest value, the static 91 kN, does not
    assert tables[0]["claim"]["grows"] == [2, 3] and tables[0]["claim"]["grows_holds"] is False
    assert tables[0]["group"] == {"condition": "smooth-straight", "speed_kmh": 80.0,
                                  "body_model": "flexible"}
    small = make_client(max_fe_dofs=100_000)
    r = small.post(f"{API}/studies", json={"preset": "mesh-convergence", "overrides": QUICK})
    assert r.status_code == 422, r.text
    assert "at least 0.11 m" in r.text and "element_size_m" in r.text

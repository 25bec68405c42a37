"""The calibrated car body over the API: ``calibration_*`` query parameters of ``GET
/fe/{kind}`` and ``GET /fe/carbody/pairing`` (one dependency for both routes), the same
spelling as the scenario's ``bodies.carbody.calibration`` and ``flexride fe calibrate
--targets``, the build in the job worker (never in the API process), and ``POST /estimates``
with a calibrated body that is not built (409)."""

from __future__ import annotations

import json
from typing import Any

import pytest

from flexride.fem.export import ExportSpec
from flexride.scenario.presets import load_preset
from service.svc_testkit import fe_jobs, services, use_fe_builds

API = "/api/v1"
TARGETS = "6.5:rhombic,5.59:first vertical bending"
#: A calibrated 0.5 m car body cheap enough for a test (one variable, four evaluations).
QUERY = {"element_size_m": 0.5, "cutoff_hz": 30.0, "max_modes": 8,
         "calibration_targets": TARGETS, "calibration_variables": "floor_depth",
         "calibration_max_evaluations": 4}


def _scenario_spec(max_modes: int = 8) -> ExportSpec:
    """The export of the same calibrated body written as a scenario."""
    sc = load_preset("paper-metro", {
        "bodies.carbody.model": "flexible", "bodies.carbody.element_size_m": 0.5,
        "bodies.carbody.cutoff_hz": 30.0,
        "bodies.carbody.calibration": {"targets": TARGETS, "variables": ["floor_depth"],
                                       "max_evaluations": 4}})
    return ExportSpec.create("carbody", sc.vehicle, sc.bodies.carbody, max_modes)


@pytest.mark.parametrize(("path", "params", "loc", "words"), [
    ("/fe/frame", {"calibration_targets": "5:torsion"}, ["query", "calibration_targets"],
     "car body"),
    ("/fe/carbody", {"calibration_targets": "5:twisting"}, ["query", "calibration_targets"],
     "target 1: unknown mode type 'twisting'"),
    ("/fe/carbody", {"calibration_targets": "5:torsion", "calibration_max_evaluations": 5},
     ["query", "calibration_max_evaluations"], "allowed 18–60"),
    ("/fe/carbody", {"calibration_targets": "5", "calibration_max_evaluations": 99},
     ["query", "calibration_max_evaluations"], "60"),
    ("/fe/carbody", {"calibration_targets": "5", "calibration_variables": "floor"},
     ["query", "calibration_variables"], "'floor_depth'"),
    ("/fe/carbody", {"calibration_variables": "floor_depth"},
     ["query", "calibration_variables"], "give calibration_targets"),
    ("/fe/carbody/pairing", {"targets": "5", "calibration_targets": "5:twisting"},
     ["query", "calibration_targets"], "twisting"),
])
def test_a_bad_calibration_is_a_422_at_its_query_parameter(make_client, path, params, loc,
                                                          words):
    client = make_client()
    r = client.get(f"{API}{path}", params=params)
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == loc and words in item["msg"], item
    assert fe_jobs(client) == []


def test_both_routes_take_the_calibration_as_the_scenario_spells_it(make_client):
    """The query's calibration is the scenario's: the same content key, on both routes; the
    build is a job (202), the API computes nothing."""
    client = make_client(fe_wait_s=0.0)
    spec = _scenario_spec()
    r = client.get(f"{API}/fe/carbody", params=QUERY)
    assert r.status_code == 202, r.text
    assert r.json()["key"] == spec.key
    assert r.json()["parameters"]["calibration"]["targets"][0]["mode_type"] == "rhombic"
    r = client.get(f"{API}/fe/carbody/pairing", params={**QUERY, "targets": TARGETS})
    assert r.status_code == 202 and r.json()["key"] == spec.key
    (job,) = fe_jobs(client)
    stored = services(client).store.get_job(job.id, scenario=True)
    assert stored is not None and ExportSpec.from_dict(stored.scenario or {}) == spec
    plain = client.get(f"{API}/fe/carbody", params={k: v for k, v in QUERY.items()
                                                    if not k.startswith("calibration")})
    assert plain.json()["key"] != spec.key and len(fe_jobs(client)) == 2


def test_the_calibrated_build_reports_its_calibration_and_pairing(make_client, tmp_path,
                                                                 monkeypatch):
    """The job (in this process, the workers' code path) calibrates and builds the 0.5 m
    body: the export's model block says to what and how well, and the pairing route pairs
    the calibrated model's modes; a target type the starting model has no mode of fails the
    build after one evaluation, a 422 with the reason."""
    from flexride.fem.export import build_export

    monkeypatch.setenv("FLEXRIDE_CACHE_DIR", str(tmp_path / "fe-cache"))
    client = make_client()
    use_fe_builds(client, build_export, wait_s=120.0)
    r = client.get(f"{API}/fe/carbody", params=QUERY)
    assert r.status_code == 200, r.text
    model = r.json()["model"]
    cal = model["calibration"]
    assert cal["targets"] == TARGETS and set(cal["values"]) == {"floor_depth"}
    assert cal["n_evaluations"] <= 4 and cal["max_evaluations"] == 4
    assert [p["target_type"] for p in cal["pairs"]] == ["rhombic", "first vertical bending"]
    assert all(p["mode"] is not None and p["error"] is not None for p in cal["pairs"])
    assert model["discretisation"] is not None
    r = client.get(f"{API}/fe/carbody/pairing", params={**QUERY, "targets": TARGETS})
    assert r.status_code == 200, r.text
    pairs = r.json()["pairs"]
    assert pairs[0]["model_type"] == "rhombic"
    assert r.json()["model"]["calibration"]["key"] == cal["key"]
    job = fe_jobs(client)[0]
    assert job.status == "succeeded" and json.loads(json.dumps(job.run_meta))
    r = client.get(f"{API}/fe/carbody", params={**QUERY, "calibration_targets":
                                                 "5.03:torsion,6.5:rhombic"})
    assert r.status_code == 422, r.text
    assert "no mode of type 'torsion'" in r.json()["message"]


def test_an_estimate_of_a_calibrated_body_not_built_is_409_naming_the_build(sqlite_client,
                                                                          monkeypatch):
    """A calibrated body counts as built only when its calibration and body are in the FE
    cache (409 otherwise), nothing calibrates here."""
    import flexride.fem.calibration as fe_calibration

    def no_calibration(*_a: Any, **_k: Any) -> None:
        raise AssertionError("a calibration ran in the API process")

    monkeypatch.setattr(fe_calibration, "calibrate_carbody", no_calibration)
    r = sqlite_client.post(f"{API}/estimates", json={
        "preset": "paper-random-straight-80", "points": ["PC"],
        "overrides": {"bodies.carbody.model": "flexible",
                      "bodies.carbody.calibration": {"targets": TARGETS}}})
    assert r.status_code == 409, r.text
    msg = r.json()["message"]
    assert "calibrated car body" in msg and "build it first" in msg
    assert "calibration_targets=6.5%3Arhombic" in msg
    assert services(sqlite_client).store.list_jobs(kind="fe_export", limit=5)[0] == []

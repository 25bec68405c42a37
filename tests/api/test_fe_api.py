"""FE mesh and mode-shape endpoints: ``GET /fe/{kind}`` and ``GET /jobs/{id}/fe/{kind}``.

The build is replaced by a stand-in running in a thread where the test is about the protocol
(202 while building, one build per key, failures, a job's own parameters); one test goes
through the real build of the bogie frame in the service's build process and compares the
answer with ``flexride fe export``.
"""

from __future__ import annotations

import json
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import pytest
from typer.testing import CliRunner

from flexride.fem.export import ExportSpec
from flexride.model.bodies import BodyModel
from flexride.model.presets import load_preset
from service.svc_testkit import (
    fake_fe_export,
    insert_finished_job,
    services,
    synthetic_results,
    use_fe_builds,
)

API = "/api/v1"


def _poll(client, url, params=None, timeout=180.0):
    """GET until the answer is not 202; the answers seen (status codes) and the last one."""
    seen = []
    end = time.monotonic() + timeout
    while True:
        r = client.get(url, params=params)
        seen.append(r.status_code)
        if r.status_code != 202 or time.monotonic() > end:
            return seen, r
        assert int(r.headers["Retry-After"]) >= 1
        time.sleep(0.5)


# -- the real build --------------------------------------------------------------------------


def test_real_frame_build_answers_202_then_the_cli_export(make_client, tmp_path, monkeypatch):
    client = make_client()
    fe = services(client).fe
    fe.wait_s = 0.0  # answer at once, so the first request sees the build running
    params = {"max_modes": 3, "cutoff_hz": 40}
    seen, r = _poll(client, f"{API}/fe/frame", params)
    assert seen[0] == 202 and r.status_code == 200, (seen, r.text)
    assert r.headers["content-type"].startswith("application/json")
    got = r.json()
    model = got.pop("model")
    assert model["kind"] == "frame" and model["max_modes"] == 3 and not model["from_cache"]
    assert model["n_elastic_modes"] >= len(got["modes"]) >= 1
    # the same JSON as `flexride fe export` (its own process, the same FE cache)
    from flexride.fe_cli import fe_app

    monkeypatch.setenv("FLEXRIDE_CACHE_DIR", str(services(client).settings.cache_dir))
    out = tmp_path / "frame.json"
    res = CliRunner().invoke(fe_app, ["export", "frame", "--cutoff", "40", "--n-modes", "3",
                                      "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert got == json.loads(out.read_text())
    # once built, the export is a file: 200 at once, no new build
    started = fe.builds_started
    t0 = time.perf_counter()
    assert client.get(f"{API}/fe/frame", params=params).status_code == 200
    assert time.perf_counter() - t0 < 1.0 and fe.builds_started == started
    # other modes of the same body: it is in the FE cache, so one request (waiting for the
    # load, not a build) gives 200
    fe.wait_s = 60.0
    r = client.get(f"{API}/fe/frame", params={**params, "max_modes": 1})
    assert r.status_code == 200 and r.json()["model"]["from_cache"] is True
    assert len(r.json()["modes"]) == 1


# -- protocol, with a stand-in build ---------------------------------------------------------


def test_an_export_on_file_is_served_without_a_build(make_client):
    client = make_client()
    fe = use_fe_builds(client)
    spec = ExportSpec.create("carbody", load_preset("paper-metro").vehicle, BodyModel())
    fake_fe_export(spec, str(fe.path_for(spec.key)))
    r = client.get(f"{API}/fe/carbody")  # the defaults are the scenario's body defaults
    assert r.status_code == 200 and fe.builds_started == 0
    assert r.json()["model"]["key"] == spec.key


def test_one_build_per_key_however_often_it_is_asked_for(make_client):
    release = threading.Event()
    calls = []

    def slow_build(spec, dest):
        calls.append(spec.key)
        assert release.wait(30)
        return fake_fe_export(spec, dest)

    client = make_client()
    fe = use_fe_builds(client, build=slow_build)
    with ThreadPoolExecutor(4) as pool:
        answers = list(pool.map(lambda _: client.get(f"{API}/fe/carbody",
                                                     params={"element_size_m": 0.5}), range(4)))
    try:
        assert [a.status_code for a in answers] == [202] * 4
        body = answers[0].json()
        assert body["status"] in ("queued", "building") and "first time only" in body["message"]
        assert body["parameters"]["element_size_m"] == 0.5
        assert answers[0].headers["Retry-After"] == str(body["retry_after_s"])
        assert fe.builds_started == 1
    finally:
        release.set()
    _, r = _poll(client, f"{API}/fe/carbody", {"element_size_m": 0.5}, timeout=30)
    assert r.status_code == 200 and len(calls) == 1
    assert r.json()["model"]["element_size_m"] == 0.5


def test_failed_builds_are_clear_errors_not_500(make_client):
    client = make_client()

    def no_model(spec, dest):
        return {"ok": False, "type": "FEModelError",
                "error": "car body: no elastic mode below the cut-off frequency"}

    fe = use_fe_builds(client, build=no_model, wait_s=5.0)
    r = client.get(f"{API}/fe/carbody")
    assert r.status_code == 422, r.text
    assert "no elastic mode" in r.json()["message"] and r.json()["detail"][0]["type"]
    assert client.get(f"{API}/fe/carbody").status_code == 422  # remembered, not rebuilt
    assert fe.builds_started == 1

    def crash(spec, dest):
        raise MemoryError("cannot allocate the factorisation")

    use_fe_builds(client, build=crash, wait_s=5.0)
    r = client.get(f"{API}/fe/frame")
    assert r.status_code == 503, r.text
    assert "MemoryError" in r.json()["message"] and int(r.headers["Retry-After"]) > 0


def test_too_many_builds_at_once_are_refused_for_a_while(make_client):
    release = threading.Event()

    def slow_build(spec, dest):
        assert release.wait(30)
        return fake_fe_export(spec, dest)

    client = make_client()
    use_fe_builds(client, build=slow_build, max_pending=2)
    try:
        codes = [client.get(f"{API}/fe/carbody", params={"cutoff_hz": c}).status_code
                 for c in (30, 31, 32)]
        assert codes == [202, 202, 503]
    finally:
        release.set()


@pytest.mark.parametrize(("path", "params", "loc", "words"), [
    ("/fe/bogie", {}, ["path", "kind"], "'carbody' or 'frame'"),
    ("/fe/carbody", {"element_size_m": 0.01}, ["query", "element_size_m"], "allowed: ≥ 0.05"),
    ("/fe/carbody", {"element_size_m": 2}, ["query", "element_size_m"], "allowed: ≤ 1.0"),
    ("/fe/carbody", {"cutoff_hz": 1}, ["query", "cutoff_hz"], "allowed: > 1.0"),
    ("/fe/frame", {"cutoff_hz": 900}, ["query", "cutoff_hz"], "allowed: ≤ 500.0"),
    ("/fe/frame", {"cutoff_hz": "nan"}, ["query", "cutoff_hz"], ""),
    ("/fe/carbody", {"reduction": "lanczos"}, ["query", "reduction"], "'craig-bampton'"),
    ("/fe/carbody", {"max_modes": 101}, ["query", "max_modes"], "allowed: ≤ 100"),
    ("/fe/carbody", {"preset": "no-such"}, ["query", "preset"], "paper-metro"),
    ("/jobs/0123/fe/wheelset", {}, ["path", "kind"], "'carbody' or 'frame'"),
])
def test_bad_kind_or_parameter_is_a_422_naming_field_and_range(make_client, path, params, loc,
                                                               words):
    client = make_client()
    fe = use_fe_builds(client)
    r = client.get(f"{API}{path}", params=params)
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == loc and words in item["msg"]
    assert fe.builds_started == 0


def test_parameters_have_the_ranges_of_the_scenario_body_schema(sqlite_client):
    params = {p["name"]: p["schema"] for p in
              sqlite_client.get(f"{API}/openapi.json").json()
              ["paths"]["/api/v1/fe/{kind}"]["get"]["parameters"]}
    body = BodyModel.model_json_schema()["properties"]
    for name in ("element_size_m", "cutoff_hz", "reduction"):
        for key in ("minimum", "exclusiveMinimum", "maximum", "default", "enum"):
            assert params[name].get(key) == body[name].get(key), (name, key)


def test_a_jobs_own_flexible_body(make_client):
    client = make_client()
    fe = use_fe_builds(client, wait_s=10.0)  # the stand-in is quick: 200 in one request
    svc = services(client)
    sc = load_preset("paper-metro", {"vehicle.carbody.mass": 40000.0,
                                     "bodies.carbody.model": "flexible",
                                     "bodies.carbody.element_size_m": 0.8,
                                     "bodies.carbody.cutoff_hz": 25.0})
    res = synthetic_results(duration=2.0)
    res.scenario = sc.model_dump(mode="json")
    job = insert_finished_job(svc.store, svc.files, res)
    r = client.get(f"{API}/jobs/{job}/fe/carbody", params={"max_modes": 5})
    assert r.status_code == 200, r.text
    model = r.json()["model"]
    assert (model["element_size_m"], model["cutoff_hz"], model["max_modes"]) == (0.8, 25.0, 5)
    # the job's vehicle (40 t) makes it a different model than the preset's
    own = ExportSpec.create("carbody", sc.vehicle, sc.bodies.carbody, 5)
    assert model["key"] == own.key
    preset = client.get(f"{API}/fe/carbody", params={"element_size_m": 0.8, "cutoff_hz": 25,
                                                     "max_modes": 5}).json()["model"]
    assert preset["key"] != own.key and fe.builds_started == 2
    # its frames are rigid: nothing to draw, and the answer says why
    r = client.get(f"{API}/jobs/{job}/fe/frame")
    assert r.status_code == 409 and "rigid" in r.json()["message"]
    assert client.get(f"{API}/jobs/{'f' * 32}/fe/carbody").status_code == 404


def test_starting_a_build_needs_the_token_serving_a_built_model_does_not(make_client):
    """With an API token, a GET that would start an FE build (minutes of CPU) is refused
    without the token (401); with it the build starts (202); once built, reads stay open."""
    client = make_client(api_token="Qm7vR2xK9pLw4ZtB-e3Nc")
    fe = use_fe_builds(client, wait_s=5.0)
    params = {"element_size_m": 0.5}
    r = client.get(f"{API}/fe/carbody", params=params)
    assert r.status_code == 401 and "API token" in r.json()["message"]
    assert fe.builds_started == 0
    auth = {"Authorization": "Bearer Qm7vR2xK9pLw4ZtB-e3Nc"}
    r = client.get(f"{API}/fe/carbody", params=params, headers=auth)
    assert r.status_code in (200, 202) and fe.builds_started == 1
    _, r = _poll(client, f"{API}/fe/carbody", params, timeout=30)
    assert r.status_code == 200  # without the token: the model exists now
    r = client.get(f"{API}/fe/carbody", params=params,
                   headers={"Authorization": "Bearer wrong"})
    assert r.status_code == 200

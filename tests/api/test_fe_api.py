"""FE mesh and mode-shape endpoints: ``GET /fe/{kind}`` and ``GET /jobs/{id}/fe/{kind}``.

The API never builds an export: a missing one becomes a job of kind ``fe_export``. Here the
service has no runner; the FE jobs run in this process through the workers' code path
(:func:`flexride.study.run_job.claim_and_run`) with a stand-in build — either when the test
says so (``run_fe_jobs``) or in a thread as soon as they are submitted (``use_fe_builds``).
The real builds on the embedded runner and on Celery workers are in tests/jobs.
"""

from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict

import pytest

from flexride.errors import FEModelError
from flexride.fem.export import ExportSpec
from flexride.scenario.bodies import BodyModel
from flexride.scenario.presets import load_preset
from service.svc_testkit import (
    TEST_TOKEN,
    fake_fe_export,
    fe_jobs,
    insert_finished_job,
    run_fe_jobs,
    services,
    synthetic_results,
    use_fe_builds,
    wait_for,
    write_fake_export,
)

API = "/api/v1"
COARSE = {"element_size_m": 0.5}


def _spec(**body) -> ExportSpec:
    return ExportSpec.create("carbody", load_preset("paper-metro").vehicle, BodyModel(**body))


def _poll(client, url, params=None, timeout=30.0, headers=None):
    """GET until the answer is not 202; the answers seen (status codes) and the last one."""
    seen = []
    end = time.monotonic() + timeout
    while True:
        r = client.get(url, params=params, headers=headers)
        seen.append(r.status_code)
        if r.status_code != 202 or time.monotonic() > end:
            return seen, r
        assert int(r.headers["Retry-After"]) >= 1
        time.sleep(0.1)


# -- served from files; one job per key --------------------------------------------------------


def test_an_export_on_file_is_served_without_a_job(make_client):
    client = make_client()
    spec = _spec()
    write_fake_export(services(client).fe.path_for(spec.key), spec)
    r = client.get(f"{API}/fe/carbody")  # the defaults are the scenario's body defaults
    assert r.status_code == 200 and r.json()["model"]["key"] == spec.key
    assert r.headers["content-type"].startswith("application/json")
    assert fe_jobs(client) == []


def test_one_job_per_key_however_often_it_is_asked_for(client):
    """Concurrent requests for a model that is not built (SQLite and PostgreSQL) submit one
    job; once a worker has run it, the export is served and no job is added."""
    services(client).fe.wait_s = 0.0
    with ThreadPoolExecutor(8) as pool:
        answers = list(pool.map(lambda _: client.get(f"{API}/fe/carbody", params=COARSE),
                                range(16)))
    assert [a.status_code for a in answers] == [202] * 16, answers[0].text
    jobs = fe_jobs(client)
    assert len(jobs) == 1
    job = jobs[0]
    assert {a.json()["job_id"] for a in answers} == {job.id}
    body = answers[0].json()
    assert body["status"] == "queued" and body["progress"] == 0.0
    assert "waiting for a free worker" in body["message"] and "first time only" in body["message"]
    assert body["parameters"]["element_size_m"] == 0.5 and body["key"] == _spec(**COARSE).key
    assert answers[0].headers["Retry-After"] == str(body["retry_after_s"])
    assert body["elapsed_s"] >= 0
    # the record: an fe_export job whose scenario is the spec and whose hash its key
    detail = client.get(f"{API}/jobs/{job.id}").json()
    assert detail["kind"] == "fe_export" and detail["status"] == "queued"
    assert detail["scenario_hash"] == body["key"]
    assert client.get(f"{API}/jobs/{job.id}/scenario").json() == asdict(_spec(**COARSE))
    # a worker runs it (here: this process, the workers' code path, a stand-in build)
    assert run_fe_jobs(client) == {job.id: "succeeded"}
    r = client.get(f"{API}/fe/carbody", params=COARSE)
    assert r.status_code == 200 and r.json()["model"]["element_size_m"] == 0.5
    assert client.get(f"{API}/fe/carbody", params=COARSE).status_code == 200
    assert len(fe_jobs(client)) == 1
    done = client.get(f"{API}/jobs/{job.id}").json()
    assert (done["status"], done["progress"], done["message"]) == ("succeeded", 1.0, "done")
    assert not done["has_results"]


def test_a_request_waits_for_the_build_by_polling(make_client):
    """FLEXRIDE_FE_WAIT_S: a request waits for the job (file and record polled) and answers
    200 when the build ends in time; otherwise 202 with the job's progress and message."""
    release = threading.Event()

    def slow(spec, progress):
        progress(0.3, "building the FE model of the car body (mesh, eigenmodes)")
        assert release.wait(30)
        return fake_fe_export(spec)

    client = make_client()
    use_fe_builds(client, wait_s=5.0)
    t0 = time.perf_counter()
    r = client.get(f"{API}/fe/carbody", params=COARSE)
    assert r.status_code == 200 and time.perf_counter() - t0 < 5.0
    runner = use_fe_builds(client, build=slow, wait_s=1.0)
    try:
        r = client.get(f"{API}/fe/carbody", params={"element_size_m": 0.6})
        assert r.status_code == 202, r.text
        body = r.json()
        assert body["status"] == "building" and body["progress"] == pytest.approx(0.3)
        assert body["message"].startswith("building the FE model of the car body (mesh")
        assert body["elapsed_s"] >= 0.9 and body["job_id"] == runner.ran[0]
    finally:
        release.set()
    services(client).fe.wait_s = 10.0
    r = client.get(f"{API}/fe/carbody", params={"element_size_m": 0.6})
    assert r.status_code == 200 and r.json()["model"]["element_size_m"] == 0.6


# -- failures --------------------------------------------------------------------------------


def test_failed_builds_are_422_or_503_then_tried_again_after_the_ttl(make_client):
    client = make_client()
    fe = services(client).fe

    def no_model(spec, progress):
        raise FEModelError("car body: no elastic mode below the cut-off frequency")

    use_fe_builds(client, build=no_model, wait_s=5.0)
    r = client.get(f"{API}/fe/carbody")
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert "no elastic mode" in r.json()["message"] and item["type"] == "FEModelError"
    assert item["ctx"]["parameters"]["cutoff_hz"] == 40.0
    failed = fe_jobs(client)[0]
    assert failed.status == "failed" and "no elastic mode" in failed.error
    assert failed.message == "failed: FEModelError"
    r = client.get(f"{API}/fe/carbody")  # remembered, not built again
    assert r.status_code == 422 and len(fe_jobs(client)) == 1

    def crash(spec, progress):
        raise MemoryError("cannot allocate the factorisation")

    use_fe_builds(client, build=crash, wait_s=5.0)
    r = client.get(f"{API}/fe/frame")
    assert r.status_code == 503, r.text
    assert "MemoryError" in r.json()["message"] and "internal error" in r.json()["message"]
    assert 290 <= int(r.headers["Retry-After"]) <= 300  # the rest of the 5 minutes
    assert client.get(f"{API}/fe/frame").status_code == 503
    assert len(fe_jobs(client)) == 2
    # after the failure TTL a request submits the build again (now it works)
    use_fe_builds(client, wait_s=5.0, failure_ttl_s=1.0)
    time.sleep(1.1)
    assert fe.failure_ttl_s == 1.0
    r = client.get(f"{API}/fe/frame")
    assert r.status_code == 200, r.text
    r = client.get(f"{API}/fe/carbody")
    assert r.status_code == 200, r.text
    assert [j.status for j in fe_jobs(client)] == ["succeeded", "succeeded", "failed", "failed"]


def test_a_build_whose_file_is_not_here_is_a_503_then_built_again(make_client):
    """A job that succeeded while its export is not in the API's cache directory (workers with
    another FLEXRIDE_CACHE_DIR, or the file removed): 503 naming the setting, then after the
    failure TTL a new job."""
    client = make_client(fe_wait_s=0.0)
    fe = services(client).fe
    first = client.get(f"{API}/fe/carbody", params=COARSE).json()["job_id"]
    run_fe_jobs(client)
    fe.path_for(_spec(**COARSE).key).unlink()
    r = client.get(f"{API}/fe/carbody", params=COARSE)
    assert r.status_code == 503 and "FLEXRIDE_CACHE_DIR" in r.json()["message"]
    fe.failure_ttl_s = 0.0
    r = client.get(f"{API}/fe/carbody", params=COARSE)
    assert r.status_code == 202 and r.json()["job_id"] != first


def test_a_lost_worker_is_a_503(make_client):
    """A job that failed without a model error (here: its worker was lost) answers 503."""
    client = make_client(max_attempts=1, fe_wait_s=0.0)
    svc = services(client)
    client.get(f"{API}/fe/carbody", params=COARSE)
    (job,) = fe_jobs(client)
    from flexride.store import now

    claim = svc.store.claim(job.id, "embedded-999999@elsewhere", stale_before=now() - 60)
    assert claim.claimed
    svc.store.worker_lost(job.id, "embedded-999999@elsewhere", "no heartbeat for 60 s")
    r = client.get(f"{API}/fe/carbody", params=COARSE)
    assert r.status_code == 503 and "no heartbeat" in r.json()["message"]
    assert int(r.headers["Retry-After"]) > 0


def test_too_many_builds_at_once_are_refused_for_a_while(make_client):
    client = make_client(fe_wait_s=0.0)
    services(client).fe.max_pending = 2
    codes = [client.get(f"{API}/fe/carbody", params={"cutoff_hz": c}).status_code
             for c in (30, 31, 32)]
    assert codes == [202, 202, 503]
    assert client.get(f"{API}/fe/carbody", params={"cutoff_hz": 31}).status_code == 202
    run_fe_jobs(client)
    assert client.get(f"{API}/fe/carbody", params={"cutoff_hz": 32}).status_code == 202


# -- cancel ------------------------------------------------------------------------------------


def test_cancel_a_queued_or_running_fe_job(make_client):
    client = make_client(fe_wait_s=0.0)
    r = client.get(f"{API}/fe/carbody", params=COARSE)
    job_id = r.json()["job_id"]
    r = client.post(f"{API}/jobs/{job_id}/cancel")
    assert r.status_code == 200 and r.json()["status"] == "cancelled"
    assert run_fe_jobs(client) == {}  # nothing left to run
    # the next request starts a new build
    r = client.get(f"{API}/fe/carbody", params=COARSE)
    assert r.status_code == 202 and r.json()["job_id"] != job_id
    assert run_fe_jobs(client) == {r.json()["job_id"]: "succeeded"}
    assert client.get(f"{API}/fe/carbody", params=COARSE).status_code == 200
    # running: the build cannot be interrupted; the cancel is obeyed before the file is written
    release, started = threading.Event(), threading.Event()

    def slow(spec, progress):
        started.set()
        assert release.wait(30)
        return fake_fe_export(spec)

    runner = use_fe_builds(client, build=slow)
    client.get(f"{API}/fe/frame")
    assert started.wait(10)
    job_id = runner.ran[0]
    r = client.post(f"{API}/jobs/{job_id}/cancel")
    assert r.json()["status"] == "running" and r.json()["cancel_requested"]
    release.set()
    job = wait_for(lambda: (j := client.get(f"{API}/jobs/{job_id}").json())["status"]
                   != "running" and j, 10, what="the cancelled build")
    assert job["status"] == "cancelled" and "no export written" in job["message"]
    assert not services(client).fe.path_for(_spec().key).is_file()


# -- the job list --------------------------------------------------------------------------------


def test_the_job_list_shows_simulations_unless_asked_for_other_kinds(client):
    svc = services(client)
    svc.fe.wait_s = 0.0
    sim = insert_finished_job(svc.store, svc.files)
    client.get(f"{API}/fe/carbody", params=COARSE)
    (fe_job,) = fe_jobs(client)
    page = client.get(f"{API}/jobs").json()
    assert [j["id"] for j in page["items"]] == [sim] and page["total"] == 1
    assert page["items"][0]["kind"] == "simulation"
    page = client.get(f"{API}/jobs", params={"kind": "fe_export"}).json()
    assert [j["id"] for j in page["items"]] == [fe_job.id] and page["total"] == 1
    assert page["items"][0]["kind"] == "fe_export"
    page = client.get(f"{API}/jobs", params={"kind": "all"}).json()
    assert {j["id"] for j in page["items"]} == {sim, fe_job.id} and page["total"] == 2
    page = client.get(f"{API}/jobs", params={"kind": "fe_export", "status": "succeeded"}).json()
    assert page["total"] == 0
    r = client.get(f"{API}/jobs", params={"kind": "mesh"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["query", "kind"]


# -- parameters ----------------------------------------------------------------------------------


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
    ("/fe/carbody", {"element_size_m": 0.06}, ["query", "element_size_m"], "FLEXRIDE_MAX_FE"),
    ("/fe/carbody", {"cutoff_hz": 150}, ["query", "cutoff_hz"], "FLEXRIDE_MAX_FE"),
    (f"/jobs/{'0' * 32}/fe/wheelset", {}, ["path", "kind"], "'carbody' or 'frame'"),
    ("/jobs/0123/fe/carbody", {}, ["path", "job_id"], "32 hexadecimal digits"),
    ("/fe/frame/pairing", {"targets": "5"}, ["path", "kind"], "'carbody'"),
    ("/fe/carbody/pairing", {}, ["query", "targets"], "Field required"),
])
def test_bad_kind_or_parameter_is_a_422_naming_field_and_range(make_client, path, params, loc,
                                                               words):
    client = make_client()
    r = client.get(f"{API}{path}", params=params)
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == loc and words in item["msg"] + r.json()["message"]
    assert fe_jobs(client) == []


def test_parameters_have_the_ranges_of_the_scenario_body_schema(sqlite_client):
    params = {p["name"]: p["schema"] for p in
              sqlite_client.get(f"{API}/openapi.json").json()
              ["paths"]["/api/v1/fe/{kind}"]["get"]["parameters"]}
    body = BodyModel.model_json_schema()["properties"]
    for name in ("element_size_m", "cutoff_hz", "reduction"):
        for key in ("minimum", "exclusiveMinimum", "maximum", "default", "enum"):
            assert params[name].get(key) == body[name].get(key), (name, key)


# -- a job's own body; the token -------------------------------------------------------------------


def test_a_jobs_own_flexible_body(make_client):
    client = make_client()
    use_fe_builds(client, wait_s=10.0)  # the stand-in is quick: 200 in one request
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
    assert preset["key"] != own.key and len(fe_jobs(client)) == 2
    # its frames are rigid: nothing to draw, and the answer says why
    r = client.get(f"{API}/jobs/{job}/fe/frame")
    assert r.status_code == 409 and "rigid" in r.json()["message"]
    assert client.get(f"{API}/jobs/{'f' * 32}/fe/carbody").status_code == 404
    # an FE export job has no bodies of its own
    r = client.get(f"{API}/jobs/{fe_jobs(client)[0].id}/fe/carbody")
    assert r.status_code == 409 and "fe_export" in r.json()["message"]


def test_starting_a_build_needs_the_token_serving_a_built_model_does_not(make_client):
    """With an API token, a GET that would submit an FE build (minutes of CPU) is refused
    without the token (401); with it the build is submitted (202); once built, reads stay
    open."""
    client = make_client(api_token=TEST_TOKEN)
    use_fe_builds(client, wait_s=5.0)
    r = client.get(f"{API}/fe/carbody", params=COARSE)
    assert r.status_code == 401 and "API token" in r.json()["message"]
    assert r.headers["WWW-Authenticate"] == "Bearer" and fe_jobs(client) == []
    auth = {"Authorization": f"Bearer {TEST_TOKEN}"}
    r = client.get(f"{API}/fe/carbody", params=COARSE, headers=auth)
    assert r.status_code in (200, 202) and len(fe_jobs(client)) == 1
    _, r = _poll(client, f"{API}/fe/carbody", COARSE)
    assert r.status_code == 200  # without the token: the model exists now
    r = client.get(f"{API}/fe/carbody", params=COARSE, headers={"Authorization": "Bearer wrong"})
    assert r.status_code == 200


def test_a_build_in_progress_is_reported_without_the_token(make_client):
    client = make_client(api_token=TEST_TOKEN, fe_wait_s=0.0)
    auth = {"Authorization": f"Bearer {TEST_TOKEN}"}
    assert client.get(f"{API}/fe/frame", headers=auth).status_code == 202
    r = client.get(f"{API}/fe/frame")
    assert r.status_code == 202 and r.json()["status"] == "queued"


# -- the pairing of a body's modes with calibration targets ----------------------------------------


def test_pairing_of_the_exported_modes_with_typed_targets(make_client):
    """A real export of a coarse car body: a typed target pairs with the exported mode of its
    type although another lies nearer in frequency, an untyped one with the nearest free
    mode, a type the exported modes lack is unpaired with the reason; while the export is not
    built the answer is the export's own (202), and targets that do not parse are a 422
    there."""
    from flexride.fem.export import build_export, write_json_atomic

    client = make_client()
    params = {"element_size_m": 0.6, "cutoff_hz": 40.0, "max_modes": 10}
    spec = ExportSpec.create("carbody", load_preset("paper-metro").vehicle,
                             BodyModel(model="flexible", element_size_m=0.6, cutoff_hz=40.0), 10)
    r = client.get(f"{API}/fe/carbody/pairing", params={**params, "targets": "9:torsion"})
    assert r.status_code == 202 and r.json()["key"] == spec.key  # being built: as /fe/carbody
    write_json_atomic(services(client).fe.path_for(spec.key), build_export(spec))
    export = client.get(f"{API}/fe/carbody", params=params).json()
    modes = export["modes"]
    rhombic = [m["classification"] for m in modes].index("rhombic")
    assert rhombic > 0  # not the lowest: the lowest mode's frequency is the nearest otherwise
    lowest = modes[0]["frequency_hz"]
    r = client.get(f"{API}/fe/carbody/pairing", params={
        **params, "targets": f"{lowest:.3f}:rhombic,3.0,20:third lateral bending"})
    assert r.status_code == 200, r.text
    body = r.json()
    typed, untyped, missing = body["pairs"]
    assert typed["mode"] == rhombic + 1 and typed["model_type"] == "rhombic"
    assert typed["error"] == pytest.approx(modes[rhombic]["frequency_hz"] / lowest - 1, abs=1e-3)
    assert untyped["mode"] == 1 and untyped["model_hz"] == lowest  # the nearest free mode
    assert missing["mode"] is None and missing["model_hz"] is None
    assert "no mode of type 'third lateral bending'" in missing["message"]
    assert body["modes_considered"] == 10 and body["model"]["key"] == spec.key
    r = client.get(f"{API}/fe/carbody/pairing", params={**params, "targets": "5:twisting"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["query", "targets"]
    assert "torsion" in r.json()["detail"][0]["msg"]  # the allowed types are listed

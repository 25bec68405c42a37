"""Measured irregularities over the API are data (inline or uploaded), never a server path;
every job and FE build is sized before it is accepted."""

from __future__ import annotations

import hashlib

import pytest

API = "/api/v1"
CSV = b"distance_m,vertical,alignment\n0,0,0\n0.5,0.0004,0.0001\n1.0,0.0007,-0.0002\n1.5,0,0\n"


def _measured(**source):
    return {"preset": "paper-metro", "overrides": {"excitation": [{"kind": "measured",
                                                                   **source}]}}


@pytest.mark.parametrize("path", ["/proc/self/environ", "/etc/passwd", "../../flexride.db",
                                  "/dev/zero", "results.csv"])
@pytest.mark.parametrize("endpoint", ["/jobs/validate", "/jobs"])
def test_a_path_is_refused_at_the_field_and_never_read(sqlite_client, endpoint, path):
    r = sqlite_client.post(API + endpoint, json=_measured(path=path))
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == ["excitation", 0, "path"]
    assert "upload" in item["msg"] and path not in r.text


def test_a_path_set_by_a_study_axis_is_refused(sqlite_client):
    body = {"name": "s", "base": {"preset": "paper-metro", "overrides": {"excitation": [
        {"kind": "measured", "columns": ["distance_m", "vertical"], "rows": [[0, 0], [1, 0]]}]}},
        "parameters": [{"path": "excitation.0", "values": [{"kind": "measured",
                                                              "path": "/etc/passwd"}]}]}
    r = sqlite_client.post(API + "/studies", json=body)
    assert r.status_code == 422, r.text
    assert "/etc/passwd" not in r.text and r.json()["detail"][0]["loc"][-1] == "path"


def test_upload_round_trip_and_use_in_a_job(sqlite_client):
    r = sqlite_client.post(API + "/irregularities", content=CSV,
                           headers={"Content-Type": "text/csv"})
    assert r.status_code == 201, r.text
    info = r.json()
    assert info["id"] == hashlib.sha256(CSV).hexdigest()
    assert (info["rows"], info["columns"]) == (4, ["vertical", "alignment"])
    assert (info["distance_start_m"], info["distance_end_m"]) == (0.0, 1.5)
    assert r.headers["Location"].endswith(info["id"])
    again = sqlite_client.post(API + "/irregularities", content=CSV)
    assert again.status_code == 201 and again.json()["id"] == info["id"]
    assert sqlite_client.get(info["links"]["csv"]).content == CSV
    assert sqlite_client.get(info["links"]["self"]).json()["rows"] == 4
    r = sqlite_client.post(API + "/jobs", json=_measured(upload=info["id"]))
    assert r.status_code == 201, r.text
    scenario = sqlite_client.get(f"{API}/jobs/{r.json()['id']}/scenario").json()
    assert scenario["excitation"][0]["upload"] == info["id"]


def test_inline_rows_are_accepted_and_checked(sqlite_client):
    ok = _measured(columns=["distance_m", "vertical"], rows=[[0, 0], [1, 0.001], [2, 0]])
    assert sqlite_client.post(API + "/jobs/validate", json=ok).status_code == 200
    bad = _measured(columns=["distance_m", "vertical"], rows=[[0, 0], [2, 0.001], [1, 0]])
    r = sqlite_client.post(API + "/jobs/validate", json=bad)
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["excitation", 0, "rows"]
    assert "row 2" in r.json()["detail"][0]["msg"]


@pytest.mark.parametrize(("data", "needle"), [
    (b"\xff\xfe\x00secret", "not UTF-8"),
    (b"PATH=/usr/bin\nAPI_TOKEN=hunter2hunter2hunter2\n", "missing distance column"),
    (b"distance_m,vertical\n0,0\n", "two data rows"),
    (b"", "empty"),
])
def test_bad_uploads_are_422_without_their_content(sqlite_client, data, needle):
    r = sqlite_client.post(API + "/irregularities", content=data)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"] == ["body"] and needle in r.text
    assert b"hunter2" not in r.content and b"secret" not in r.content


def test_unknown_upload_is_404_and_a_bad_id_422(sqlite_client):
    assert sqlite_client.get(f"{API}/irregularities/{'a' * 64}").status_code == 404
    assert sqlite_client.get(f"{API}/irregularities/..%2F..%2Fetc%2Fpasswd").status_code in (
        404, 422)
    r = sqlite_client.post(API + "/jobs/validate", json=_measured(upload="b" * 64))
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["excitation", 0, "upload"]


def test_oversized_upload_is_413(make_client):
    client = make_client(max_body_bytes=2048)
    r = client.post(API + "/irregularities", content=b"distance_m,vertical\n" + b"1,0\n" * 2000)
    assert r.status_code == 413


def test_validate_and_upload_need_the_token(make_client):
    from service.svc_testkit import TEST_TOKEN

    client = make_client(api_token=TEST_TOKEN)
    assert client.post(API + "/jobs/validate", json={"preset": "paper-metro"}).status_code == 401
    assert client.post(API + "/irregularities", content=CSV).status_code == 401
    auth = {"Authorization": f"Bearer {TEST_TOKEN}"}
    assert client.post(API + "/jobs/validate", json={"preset": "paper-metro"},
                       headers=auth).status_code == 200


# ------------------------------------------------------------------------------- limits


def _item(r):
    assert r.status_code == 422, r.text
    return r.json()["detail"][0]


def test_too_many_output_points(sqlite_client):
    points = [{"name": f"P{i}", "x": (i % 40) * 0.5 - 10, "z": 1.2} for i in range(3000)]
    item = _item(sqlite_client.post(API + "/jobs", json={
        "preset": "paper-metro", "overrides": {"output.points": points}}))
    assert item["loc"] == ["output", "points"]
    assert "3006 recorded car-body points" in item["msg"] and "limit of 200" in item["msg"]


def test_too_many_steps(sqlite_client):
    # a given step (with solver.dt: auto, the presets' default, the step is chosen by the
    # set-up and the run's size is bounded by its results instead)
    item = _item(sqlite_client.post(API + "/jobs", json={
        "preset": "paper-metro",
        "overrides": {"duration_s": 3600, "distance_m": None, "solver.dt": 6.25e-5}}))
    assert item["loc"] == ["duration_s"]
    assert "57,600,000 time steps" in item["msg"] and "5,000,000" in item["msg"]


def test_result_size_is_estimated_from_channels_and_samples(make_client):
    client = make_client(max_result_mb=5.0)
    r = client.post(API + "/jobs/validate", json={
        "preset": "paper-metro", "overrides": {"duration_s": 4, "distance_m": None}})
    est = r.json()["estimate"]
    # 4 s at the 1 kHz default rate; 8 bytes per value
    assert est["samples"] == 4000 and est["result_bytes"] == est["channels"] * 4000 * 8
    item = _item(client.post(API + "/jobs", json={
        "preset": "paper-metro", "overrides": {"duration_s": 10, "distance_m": None}}))
    assert item["loc"] == ["duration_s"] and "limit of 5 MB" in item["msg"]
    assert f"{est['channels']} channels × 10,000 samples" in item["msg"]


@pytest.mark.parametrize(("query", "field", "needle"), [
    ("element_size_m=0.05&cutoff_hz=100", "element_size_m", "degrees of freedom"),
    ("element_size_m=0.2&cutoff_hz=300", "cutoff_hz", "limit of 100 Hz"),
])
def test_fe_builds_beyond_the_limits_are_refused(sqlite_client, query, field, needle):
    item = _item(sqlite_client.get(f"{API}/fe/carbody?{query}"))
    assert item["loc"] == ["query", field] and needle in item["msg"]


def test_flexible_job_beyond_the_fe_limit_is_refused(sqlite_client):
    item = _item(sqlite_client.post(API + "/jobs", json={
        "preset": "paper-metro", "overrides": {"bodies.carbody.model": "flexible",
                                               "bodies.carbody.element_size_m": 0.05}}))
    assert item["loc"] == ["bodies", "carbody", "element_size_m"]


def test_fe_size_estimate_is_an_upper_bound_near_the_exact_count():
    """The estimate against exact counts of the paper's car body (meshed here at 0.1 m)."""
    from flexride.fem.size import estimated_dofs
    from flexride.fem.vehicle_models import build_fe_model
    from flexride.scenario.presets import load_preset

    vehicle = load_preset("paper-metro").vehicle
    exact = build_fe_model("carbody", vehicle, element_size=0.1)[0].n_dof
    est = estimated_dofs("carbody", vehicle, 0.1)
    assert exact <= est <= 1.15 * exact
    assert estimated_dofs("carbody", vehicle, 0.3) == build_fe_model(
        "carbody", vehicle, element_size=0.3)[0].n_dof


def test_spectrogram_work_is_costed_before_computing(sqlite_client):
    """A 6 s job at 1 kHz: a 2 s window with overlap 0.9999 would slide by one sample (about
    4,000 slices × 1,001 bins); refused with the estimate, while the default overlap runs."""
    from flexride.analysis.timefreq import spectrogram_cells
    from service.svc_testkit import insert_finished_job, synthetic_results

    svc = sqlite_client.app.state.services
    job_id = insert_finished_job(svc.store, svc.files, synthetic_results(duration=6.0))
    url = f"{API}/jobs/{job_id}/spectrogram?channel=carbody.PC.acc.z&window_s=2"
    item = _item(sqlite_client.get(url + "&overlap=0.9999"))
    assert item["loc"] == ["query", "overlap"] and "limit of 5,000,000" in item["msg"]
    # the estimate: slices × one-sided bins; 2,000-sample windows one sample apart, every
    # position that overlaps the 6,000 samples: 6,000 + 2,000 − 1 slices of 1,001 bins
    assert spectrogram_cells(6000, 1000.0, 2.0, 0.9999) == 7999 * 1001
    assert sqlite_client.get(url + "&overlap=0.75").status_code == 200


def test_the_limits_are_in_the_openapi_document(make_client):
    client = make_client(max_steps=123_456, max_output_points=42)
    text = client.get(API + "/openapi.json").json()["info"]["description"]
    assert "123,456 time steps" in text and "42 recorded car-body points" in text
    assert "FLEXRIDE_MAX_RESULT_MB" in text and "FLEXRIDE_MAX_FE_DOFS" in text


def test_too_many_steps_of_the_automatic_step(sqlite_client):
    """With ``solver.dt: auto`` the steps are known once the submission check has chosen the
    step: a run whose results are small but whose steps are too many is refused then, at the
    length field."""
    item = _item(sqlite_client.post(API + "/jobs", json={
        "preset": "paper-metro",
        "overrides": {"duration_s": 3600, "distance_m": None, "output.rate_hz": 20.0}}))
    assert item["loc"] == ["duration_s"]
    assert "time steps" in item["msg"] and "5,000,000" in item["msg"]

"""Results endpoints on a finished job with known content (synthetic results file):
channels, decimated series, spectrum, PSD, spectrogram, Sperling breakdown, correlation,
download."""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from flexride.analysis import sperling
from service.svc_testkit import insert_finished_job, services, synthetic_results

API = "/api/v1"
PR_Z = "carbody.PR.acc.z"


@pytest.fixture
def finished(sqlite_client):
    svc = services(sqlite_client)
    res = synthetic_results()
    job_id = insert_finished_job(svc.store, svc.files, res)
    return sqlite_client, job_id, res


def test_channels_and_summary(finished):
    client, job_id, res = finished
    info = client.get(f"{API}/jobs/{job_id}/channels").json()
    assert info["sample_rate_hz"] == 1000.0 and info["n_samples"] == res.time.size
    pr = next(c for c in info["channels"] if c["name"] == PR_Z)
    assert (pr["body"], pr["point"], pr["quantity"], pr["direction"], pr["unit"]) == (
        "carbody", "PR", "acc", "z", "m/s^2")
    summary = client.get(f"{API}/jobs/{job_id}/summary").json()["summary"]
    peak = summary["points"]["PR"]["directions"]["z"]["peaks"]["max_abs"]
    assert peak == pytest.approx(np.max(np.abs(res.channels[PR_Z])))


@pytest.mark.parametrize("method", ["minmax", "lttb"])
def test_series_are_decimated_with_their_time_axis(finished, method):
    client, job_id, res = finished
    r = client.get(f"{API}/jobs/{job_id}/series",
                   params={"channels": [PR_Z, "carbody.PC.acc.y"], "max_points": 500,
                           "method": method, "distance": True})
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["decimated"] and body["n_samples"] == res.time.size
    ch = body["channels"][0]
    assert ch["name"] == PR_Z and ch["unit"] == "m/s^2"
    assert 2 < len(ch["time"]) == len(ch["values"]) == len(ch["distance"]) <= 500
    t, y = np.array(ch["time"]), np.array(ch["values"])
    assert np.all(np.diff(t) > 0)
    idx = np.round(t * 1000).astype(int)
    np.testing.assert_allclose(y, res.channels[PR_Z][idx])
    if method == "minmax":  # the envelope is exact: extremes survive
        assert y.max() == res.channels[PR_Z].max() and y.min() == res.channels[PR_Z].min()


def test_series_time_range_and_limits(finished):
    client, job_id, _ = finished
    body = client.get(f"{API}/jobs/{job_id}/series",
                      params={"channels": [PR_Z], "t_start": 2.0, "t_end": 3.0,
                              "method": "none", "max_points": 5000}).json()
    t = body["channels"][0]["time"]
    assert not body["decimated"] and len(t) == 1001 and t[0] == 2.0 and t[-1] == 3.0
    r = client.get(f"{API}/jobs/{job_id}/series",
                   params={"channels": [PR_Z], "method": "none", "max_points": 100})
    assert r.status_code == 422
    r = client.get(f"{API}/jobs/{job_id}/series", params={"channels": ["carbody.XX.acc.z"]})
    assert r.status_code == 422 and "carbody.PR.acc.z" in r.json()["message"]
    assert client.get(f"{API}/jobs/{job_id}/series").status_code == 422
    for job, code in (("5f0c1e9a00004000800000000000abcd", 404), ("nope", 422)):
        r = client.get(f"{API}/jobs/{job}/series", params={"channels": [PR_Z]})
        assert r.status_code == code, (job, r.text)


def test_spectrum_and_psd_find_the_sines(finished):
    client, job_id, _ = finished
    for path in ("spectrum", "psd"):
        r = client.get(f"{API}/jobs/{job_id}/{path}", params={"channels": [PR_Z], "fmax": 20})
        assert r.status_code == 200, r.text
        body = r.json()
        assert body["dynamic"] and max(body["frequencies"]) <= 20.0
        peaks = sorted(p["frequency"] for p in body["channels"][0]["peaks"][:2])
        assert peaks == pytest.approx([1.5, 7.0], abs=0.15)
    amp = client.get(f"{API}/jobs/{job_id}/spectrum",
                     params={"channels": [PR_Z], "dynamic": False}).json()
    top = amp["channels"][0]["peaks"][0]
    assert top["frequency"] == pytest.approx(1.5) and top["amplitude"] == pytest.approx(0.2,
                                                                                       rel=0.02)


def test_spectrogram(finished):
    client, job_id, _ = finished
    body = client.get(f"{API}/jobs/{job_id}/spectrogram",
                      params={"channel": PR_Z, "fmax": 10, "scaling": "magnitude"}).json()
    f = np.array(body["frequencies"])
    v = np.array(body["values"])
    assert v.shape == (f.size, len(body["times"])) and f.max() <= 10
    assert f[np.argmax(v.mean(axis=1))] == pytest.approx(1.5)


def test_sperling_breakdown_adds_up_to_the_index(finished):
    client, job_id, res = finished
    body = client.get(f"{API}/jobs/{job_id}/sperling",
                      params={"channels": [PR_Z, "carbody.PR.acc.y"]}).json()
    z = body["channels"][0]
    assert z["direction"] == "vertical" and body["dynamic"]
    w_i = np.array(z["line_w"])
    assert np.sum(w_i**10) ** 0.1 == pytest.approx(z["value"], rel=1e-9)
    bands = np.array([b["w"] for b in z["bands"] if b["w"] is not None])
    assert np.sum(bands**10) ** 0.1 == pytest.approx(z["value"], rel=1e-9)
    summary = client.get(f"{API}/jobs/{job_id}/summary").json()["summary"]
    assert z["value"] == pytest.approx(summary["points"]["PR"]["directions"]["z"]["sperling"]
                                       ["value"], rel=1e-9)
    raw = client.get(f"{API}/jobs/{job_id}/sperling",
                     params={"channels": [PR_Z], "dynamic": False}).json()["channels"][0]
    x = res.channels[PR_Z]
    assert raw["value"] == pytest.approx(sperling(x - x.mean(), 1000.0, "z").value, rel=1e-6)
    r = client.get(f"{API}/jobs/{job_id}/sperling", params={"channels": ["frame1.centre.acc.x"]})
    assert r.status_code == 422


def test_correlation_finds_the_delay(finished):
    client, job_id, _ = finished
    body = client.get(f"{API}/jobs/{job_id}/correlation",
                      params={"reference": "carbody.PRB.acc.z", "channels": [PR_Z],
                              "max_lag_s": 2.0}).json()
    ch = body["channels"][0]
    # PR leads PRB by 0.5 s: the maximum is at -0.5 s (as the paper's -0.57 s)
    assert ch["lag_at_max_s"] == pytest.approx(-0.5, abs=0.01)
    assert max(abs(v) for v in ch["lags_s"]) <= 2.0 + 1e-9
    r = client.get(f"{API}/jobs/{job_id}/correlation",
                   params={"reference": PR_Z, "channels": [PR_Z]})
    assert r.status_code == 422


def test_download_is_the_hdf5_file(finished, tmp_path):
    client, job_id, res = finished
    r = client.get(f"{API}/jobs/{job_id}/download")
    assert r.status_code == 200 and r.headers["content-type"] == "application/x-hdf5"
    assert f"{job_id}.h5" in r.headers["content-disposition"]
    p = tmp_path / "dl.h5"
    p.write_bytes(r.content)
    with h5py.File(p) as f:
        np.testing.assert_array_equal(f["channels"][PR_Z][()], res.channels[PR_Z])


def test_results_of_unfinished_jobs_are_409(sqlite_client):
    r = sqlite_client.post(f"{API}/jobs", json={"preset": "paper-random-straight-80",
                                                "overrides": {"duration_s": 1.0,
                                                              "distance_m": None}})
    job_id = r.json()["id"]
    for path in ("summary", "channels", "download"):
        res = sqlite_client.get(f"{API}/jobs/{job_id}/{path}")
        assert res.status_code == 409 and "queued" in res.json()["detail"]


# -- positions of the recorded points ----------------------------------------------------------

#: The paper's measurement points in the car-body frame (DESIGN §5 with its B-type metro
#: geometry: bogie centres at ±6.3 m, air springs ±0.95 m laterally, floor 1.10 m and roof
#: 3.80 m above top of rail) — written out here, not computed with flexride's rule.
PAPER_POINTS = {"PR": (6.3, 0.0, 3.80), "PFB": (6.3, 0.0, 1.10), "PC": (0.0, 0.0, 1.10),
                "PRB": (-6.3, 0.0, 1.10), "PLA": (-6.3, 0.95, 1.10), "PRA": (-6.3, -0.95, 1.10)}


def _paper_job(client, drop_points: bool = False):
    """A finished job whose file has the paper-metro scenario with a user point and a 2 m floor
    grid; with ``drop_points`` the file is made like one written before positions were stored."""
    from flexride.scenario.presets import load_preset

    svc = services(client)
    sc = load_preset("paper-metro", {"output.floor_grid_spacing_m": 2.0,
                                     "output.points": [{"name": "SEAT", "x": 3.0, "y": -0.7,
                                                        "z": 1.5}]})
    res = synthetic_results(duration=2.0)
    res.scenario = sc.model_dump(mode="json")
    res.channels["wheelset1.left.force.z"] = np.full(res.time.size, 8.0e4)
    res.units["wheelset1.left.force.z"] = "N"
    job_id = insert_finished_job(svc.store, svc.files, res)
    if drop_points:
        job = svc.store.get_job(job_id)
        with h5py.File(svc.files.path(job.result_file), "r+") as f:
            del f["points"]
            f.attrs["format_version"] = 1
    return job_id


@pytest.mark.parametrize("old_file", [False, True], ids=["stored", "derived-for-older-file"])
def test_channels_give_the_positions_of_the_paper_points(sqlite_client, old_file):
    job_id = _paper_job(sqlite_client, drop_points=old_file)
    info = sqlite_client.get(f"{API}/jobs/{job_id}/channels").json()
    where = {(p["body"], p["name"]): (p["x"], p["y"], p["z"]) for p in info["points"]}
    for name, xyz in PAPER_POINTS.items():
        assert where[("carbody", name)] == pytest.approx(xyz, abs=1e-12), name
    assert where[("carbody", "SEAT")] == pytest.approx((3.0, -0.7, 1.5))
    about = {p["name"]: p for p in info["points"] if p["body"] == "carbody"}
    assert (about["PR"]["kind"], about["PR"]["on_floor"]) == ("paper", False)
    assert (about["PC"]["kind"], about["PC"]["on_floor"]) == ("paper", True)
    assert about["PFB"]["description"].startswith("PFB: floor above the front bogie")
    assert (about["SEAT"]["kind"], about["SEAT"]["on_floor"]) == ("user", False)
    assert about["F0_0"]["kind"] == "grid"
    # the channels of a point carry its position; others (wheel forces) have none
    chans = {c["name"]: c for c in info["channels"]}
    assert chans[PR_Z]["position"] == pytest.approx([6.3, 0.0, 3.80])
    assert chans["carbody.PRB.acc.y"]["position"] == pytest.approx([-6.3, 0.0, 1.10])
    assert chans["frame1.centre.acc.z"]["position"][:2] == pytest.approx([6.3, 0.0])
    assert chans["wheelset1.left.force.z"]["position"] is None
    assert "top of rail" in info["point_frame"]
    # the floor grid: every 2 m from -9 m to 9 m along the body, at both sides (±1.2 m)
    floor = np.array(sorted(xyz for (_, n), xyz in where.items() if n.startswith("F")))
    np.testing.assert_allclose(floor, sorted((-9.0 + 2 * i, y, 1.10) for i in range(10)
                                             for y in (-1.2, 1.2)), atol=1e-12)
    assert where[("carbody", "F0_0")] == pytest.approx((-9.0, -1.2, 1.10))
    # frame and wheelset centres: at the bogie centres and axles (wheelbase 2.2 m)
    assert where[("frame2", "centre")][0] == pytest.approx(-6.3)
    assert where[("wheelset1", "centre")][:2] == pytest.approx((6.3 + 1.1, 0.0))

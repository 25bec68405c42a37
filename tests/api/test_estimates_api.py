"""POST /estimates against the real app: the answer is the library's estimate of the same
scenario (the oracle: :func:`flexride.frequency.estimate`), a sweep's series are the
individual estimates, and the refusals, limits and bounds of the endpoint."""

from __future__ import annotations

import json
import threading
from itertools import pairwise
from typing import Any

import pytest

from conftest import preset
from flexride.api.services import estimates as svc_est
from flexride.frequency import estimate
from flexride.frequency.quasilinear import WARM_START_RTOL
from service.svc_testkit import TEST_TOKEN

API = "/api/v1/estimates"
BASE = "paper-random-straight-80"


def _post(client, body: dict[str, Any], **kw: Any):
    return client.post(API, json=body, **kw)


def _without_timings(data: dict[str, Any]) -> dict[str, Any]:
    """An answer without the model's build timings (they differ from run to run)."""
    out = json.loads(json.dumps(data))
    info = out["model"]["info"]
    for k in [k for k in info if k.startswith("time_")]:
        del info[k]
    return out


def _close(a: Any, b: Any, rtol: float, path: str = "") -> None:
    """Recursive equality, floats within ``rtol``."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), path
        for k in a:
            _close(a[k], b[k], rtol, f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            _close(x, y, rtol, f"{path}[{i}]")
    elif isinstance(a, float) or isinstance(b, float):
        assert a == pytest.approx(b, rel=rtol, abs=1e-300), path
    else:
        assert a == b, path


def test_a_preset_answer_is_the_library_estimate(client):
    r = _post(client, {"preset": BASE, "points": ["PC", "PR"]})
    assert r.status_code == 200, r.text
    oracle = estimate(preset(BASE), points=["PC", "PR"]).to_dict()
    _close(_without_timings(r.json()), _without_timings(oracle), 1e-12)
    # the default points are the paper's six
    r = _post(client, {"scenario": {"preset": BASE, "speed_kmh": 70}})
    assert r.status_code == 200, r.text
    names = [p["name"] for p in r.json()["comfort"]["points"]]
    assert sorted(names) == sorted(["PR", "PFB", "PC", "PRB", "PLA", "PRA"])


def test_the_linearisation_option_is_the_library_estimate_with_it(sqlite_client):
    """``linearisation`` reaches the estimate (the default is the statistical one, stated in
    the model summary and the method); local gives the library's local estimate."""
    r = _post(sqlite_client, {"preset": BASE, "points": ["PC"]})
    assert r.status_code == 200, r.text
    assert r.json()["model"]["linearisation"]["method"] == "statistical"
    assert "quasi-linearised" in r.json()["comfort"]["method"]
    r = _post(sqlite_client, {"preset": BASE, "points": ["PC"], "linearisation": "local"})
    assert r.status_code == 200, r.text
    oracle = estimate(preset(BASE), points=["PC"], linearisation="local").to_dict()
    _close(_without_timings(r.json()), _without_timings(oracle), 1e-12)


def test_a_sweep_of_the_secondary_damping_gives_the_individual_estimates(sqlite_client):
    values = [2.0e4, 5.0e4, 1.0e5, 2.0e5]
    r = _post(sqlite_client, {"preset": BASE, "points": ["PC"], "sweep": {
        "parameter": "vehicle.secondary.cz", "values": values}})
    assert r.status_code == 200, r.text
    data = r.json()
    assert data["values"] == values and data["refused"] == []
    series = data["series"]["PC"]["z"]
    assert set(series) >= {"rms", "Wb", "Wk", "sperling", "sperling_filter", "a_p95", "peak"}
    assert all(len(v) == len(values) for v in series.values())
    assert len(data["nmv"]["PC"]) == len(values)
    bounce_zeta = []
    # a sweep starts each value's quasi-linear iteration (the presets' real profiles) from the
    # previous value's σ: equal to a fresh estimate within the iteration's tolerance
    # (tests/frequency/test_sweep.py), not to rounding
    rel = WARM_START_RTOL
    for i, v in enumerate(values):
        one = estimate(preset(BASE, vehicle__secondary__cz=v), points=["PC"]).comfort
        z = one.point("PC").directions["z"]
        assert series["rms"][i] == pytest.approx(z.rms, rel=rel)
        assert series["Wb"][i] == pytest.approx(z.iso["Wb"], rel=rel)
        assert series["sperling"][i] == pytest.approx(z.sperling, rel=rel)
        assert data["nmv"]["PC"][i] == pytest.approx(one.point("PC").nmv, rel=rel)
        bounce_zeta.append(z.modes[0]["damping_ratio"])
        assert z.modes[0]["label"] == "car-body bounce"
    # physics: a viscous damper's damping ratio c/(2√(k·m)) grows with c (2e4 → 5e4: ×2.5) …
    assert bounce_zeta[1] / bounce_zeta[0] == pytest.approx(2.5, rel=0.05)
    # … and beyond the optimum (ζ ≈ 0.14 at 2e4 N·s/m) more damping transmits more of the
    # track's content above √2 times the bounce frequency: the accelerations rise
    for name in ("rms", "Wb"):
        assert all(a < b for a, b in pairwise(series[name])), name


def test_the_curve_is_refused_with_the_reason_and_what_to_do(sqlite_client):
    r = _post(sqlite_client, {"preset": "paper-random-curve-80", "points": ["PC"],
                              "strict": True})
    assert r.status_code == 422, r.text
    body = r.json()
    item = body["detail"][0]
    assert item["type"] == "LinearisationError" and item["loc"] == ["strict"]
    assert item["ctx"]["reason"] == "flange_contact" and body["reason"] == "flange_contact"
    assert "flange contact" in item["msg"] and "/api/v1/jobs" in body["message"]
    r = _post(sqlite_client, {"preset": "paper-random-curve-80", "points": ["PC"],
                              "strict": False})
    assert r.status_code == 200, r.text
    assert any("flange contact" in f for f in r.json()["comfort"]["flags"])


def test_a_transient_excitation_is_refused_at_the_excitation(sqlite_client):
    r = _post(sqlite_client, {"preset": "paper-corrugation-80", "points": ["PC"]})
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == ["excitation"] and item["ctx"]["reason"] == "excitation"


def test_smooth_track_is_refused_like_a_transient_excitation(sqlite_client):
    r = _post(sqlite_client, {"preset": "paper-metro", "points": ["PC"]})  # no excitation
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == ["excitation"] and item["ctx"]["reason"] == "excitation"
    assert "no random irregularity" in item["msg"]


@pytest.mark.parametrize("name, reason, loc", [
    ("paper-random-curve-80", "flange_contact", ["strict"]),
    ("paper-corrugation-80", "excitation", ["excitation"]),
    ("paper-metro", "excitation", ["excitation"]),
])
def test_a_refusal_asked_as_an_answer_is_200_with_the_same_reasons(sqlite_client, name, reason,
                                                                   loc):
    """``refusal: "answer"``: whether the estimate applies, without an error status (what the
    dashboard's instant estimate asks); the reasons are those of the 422."""
    error = _post(sqlite_client, {"preset": name, "points": ["PC"]})
    r = _post(sqlite_client, {"preset": name, "points": ["PC"], "refusal": "answer"})
    assert error.status_code == 422 and r.status_code == 200, r.text
    body = r.json()
    assert body["applicable"] is False and body["reason"] == reason
    assert body["reasons"] == error.json()["detail"] and body["reasons"][0]["loc"] == loc
    assert body["message"] == error.json()["message"]


def test_an_estimate_that_applies_is_the_same_answer_either_way(sqlite_client):
    a = _post(sqlite_client, {"preset": BASE, "points": ["PC"]})
    b = _post(sqlite_client, {"preset": BASE, "points": ["PC"], "refusal": "answer"})
    assert a.status_code == b.status_code == 200 and a.content == b.content
    assert "applicable" not in b.json()
    r = _post(sqlite_client, {"preset": BASE, "points": ["PC"], "refusal": "maybe"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "refusal"]


@pytest.mark.parametrize("sweep, loc, words", [
    ({"parameter": "vehicle.secondary.cz", "values": [8.0e4, -1.0]}, ["sweep", "values", 1],
     "vehicle.secondary.cz = -1.0"),
    ({"parameter": "vehicle.secondary.cz", "values": ["soft"]}, ["sweep", "values", 0],
     "valid number"),
    ({"parameter": "vehicle.secondary.nope", "values": [1.0]}, ["sweep", "parameter"],
     "not a field"),
    ({"parameter": "speed_kmh", "values": list(range(30, 131))}, ["body", "sweep", "values"],
     "at most 100"),
    ({"parameter": "speed_kmh", "values": []}, ["body", "sweep", "values"], "at least 1"),
])
def test_bad_sweeps_are_422_at_the_value(sqlite_client, sweep, loc, words):
    r = _post(sqlite_client, {"preset": BASE, "points": ["PC"], "sweep": sweep})
    assert r.status_code == 422, r.text
    items = r.json()["detail"]
    assert items[0]["loc"] == loc and words in items[0]["msg"], items


@pytest.mark.parametrize("body, loc", [
    ({"preset": BASE, "points": ["PX"]}, ["points", 0]),
    ({"preset": BASE, "overrides": {"speed_kmh": 999}}, ["speed_kmh"]),
    ({"preset": BASE, "track": "soft"}, ["body", "track"]),
    ({"preset": BASE, "linearisation": "linear"}, ["body", "linearisation"]),
    ({"preset": "nope"}, ["preset"]),
    ({"preset": BASE, "scenario": {"preset": BASE}}, ["body"]),
])
def test_scenario_and_option_errors_are_located_as_for_jobs(sqlite_client, body, loc):
    r = _post(sqlite_client, body)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"] == loc


def test_a_profile_path_is_refused_without_reading_it(sqlite_client):
    r = _post(sqlite_client, {"preset": BASE, "overrides": {
        "contact": {"geometry": "profiles", "wheel": {"path": "/etc/passwd"}}}})
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][:2] == ["contact", "wheel"]
    assert "root:" not in r.text


def test_the_token_is_required_when_the_service_has_one(make_client):
    client = make_client(api_token=TEST_TOKEN)
    body = {"preset": BASE, "points": ["PC"]}
    assert _post(client, body).status_code == 401
    assert _post(client, body, headers={"Authorization": "Bearer wrong"}).status_code == 401
    r = _post(client, body, headers={"Authorization": f"Bearer {TEST_TOKEN}"})
    assert r.status_code == 200, r.text


def test_a_flexible_body_not_in_the_fe_cache_is_409_and_nothing_is_built(sqlite_client,
                                                                       monkeypatch):
    import flexride.fem.cache as fe_cache
    import flexride.fem.flexible as fe_flexible

    monkeypatch.setattr(fe_cache, "load", lambda key: None)

    def no_build(*_a: Any, **_k: Any) -> None:
        raise AssertionError("an FE model was built in the API process")

    monkeypatch.setattr(fe_flexible, "build_flexible_body", no_build)
    for extra in ({}, {"sweep": {"parameter": "vehicle.secondary.kz", "values": [3e5, 4e5]}}):
        r = _post(sqlite_client, {"preset": BASE, "points": ["PC"], **extra,
                                  "overrides": {"bodies.carbody.model": "flexible"}})
        assert r.status_code == 409, r.text
        msg = r.json()["message"]
        assert "FE cache" in msg and "build it first" in msg and "/fe/carbody" in msg


def test_busy_is_503_with_retry_after_and_a_kept_answer_needs_no_slot(sqlite_client,
                                                                     monkeypatch):
    body = {"preset": BASE, "points": ["PFB"], "overrides": {"speed_kmh": 77}}
    first = _post(sqlite_client, body)
    assert first.status_code == 200, first.text
    monkeypatch.setattr(svc_est, "_SLOTS", threading.BoundedSemaphore(1))
    assert svc_est._SLOTS.acquire(blocking=False)  # every slot taken
    r = _post(sqlite_client, {**body, "overrides": {"speed_kmh": 76}})
    assert r.status_code == 503 and int(r.headers["retry-after"]) > 0, r.text
    again = _post(sqlite_client, body)  # kept: answered without a slot, the same bytes
    assert again.status_code == 200 and again.content == first.content


def test_published_examples_are_answered(sqlite_client):
    spec = sqlite_client.get("/api/v1/openapi.json").json()
    op = spec["paths"][API]["post"]
    assert {"200", "401", "409", "422", "503"} <= set(op["responses"])
    assert "refused" in op["responses"]["422"]["content"]["application/json"]["examples"]
    schema = spec["components"]["schemas"]["EstimateCreate"]
    assert len(schema["examples"]) >= 2
    for example in schema["examples"]:
        r = _post(sqlite_client, example)
        assert r.status_code == 200, (example, r.text)


def test_spectra_are_the_library_psds_and_integrate_to_the_rms(sqlite_client):
    """With ``spectra`` the answer carries the grid and every channel's PSD (for the overlay on
    a job's Welch PSD); their integral is the channel's variance (trapezoid rule on the
    non-uniform grid, within 2 %)."""
    import numpy as np

    r = _post(sqlite_client, {"preset": BASE, "points": ["PC"], "spectra": True})
    assert r.status_code == 200, r.text
    resp = r.json()["response"]
    oracle = estimate(preset(BASE), points=["PC"]).to_dict(arrays=True)["response"]
    _close(resp["psd"], oracle["psd"], 1e-12)
    f = np.asarray(resp["frequencies_hz"])
    assert np.all(np.diff(f) > 0) and f[0] <= 0.2 and f[-1] >= 60.0
    for ch in ("carbody.PC.acc.y", "carbody.PC.acc.z"):
        var = np.trapezoid(np.asarray(resp["psd"][ch]), f)
        assert np.sqrt(var) == pytest.approx(resp["rms"][ch], rel=0.02), ch
    # the split's gain: the power a sine keeps through the analysis's quasi-static split
    from flexride.analysis import split_quasistatic

    fs, t = 200.0, np.arange(0.0, 400.0, 1.0 / 200.0)
    gain = np.asarray(resp["dynamic_part_gain"])
    for f0 in (0.2, 0.3, 0.4, 1.0):
        x = np.sin(2 * np.pi * f0 * t)
        mid = slice(t.size // 4, 3 * t.size // 4)  # away from the ends' extension
        kept = np.mean(split_quasistatic(x, fs).dynamic[mid] ** 2) / np.mean(x[mid] ** 2)
        assert np.interp(f0, f, gain) == pytest.approx(kept, rel=0.02, abs=1e-4), f0
    # without the option the answer stays small
    plain = _post(sqlite_client, {"preset": BASE, "points": ["PC"]}).json()["response"]
    assert "psd" not in plain and "frequencies_hz" not in plain
    assert "dynamic_part_gain" not in plain


@pytest.mark.parametrize("extra, words", [
    ({"sweep": {"parameter": "speed_kmh", "values": [60, 70]}}, "not with a sweep"),
    ({"points": ["PC"] * 25}, "at most 24 points"),
])
def test_spectra_are_bounded(sqlite_client, extra, words):
    r = _post(sqlite_client, {"preset": BASE, "points": ["PC"], "spectra": True, **extra})
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == ["body", "spectra"] and words in item["msg"], item


def test_a_floor_map_is_the_library_map_of_the_floor_grid(sqlite_client):
    r = _post(sqlite_client, {"preset": BASE, "points": ["PC"], "floor_map": {"spacing_m": 1.0}})
    assert r.status_code == 200, r.text
    data = r.json()
    oracle = estimate(preset(BASE), points=["PC"], floor_grid_m=1.0).to_dict()
    _close(data["floor_map"], oracle["floor_map"], 1e-12)
    fm = data["floor_map"]
    assert len(fm["x_m"]) == 19 and len(fm["y_m"]) == 3
    assert len(fm["indices"]["z"]["sperling"]) == 3 and len(fm["indices"]["z"]["sperling"][0]) == 19
    assert fm["weightings"] == {"z": "Wb", "y": "Wd"}
    assert [p["name"] for p in fm["points"]] == ["PFB", "PC", "PRB", "PLA", "PRA"]
    # the asked points' estimate is the one without the map
    assert [p["name"] for p in data["comfort"]["points"]] == ["PC"]
    plain = _post(sqlite_client, {"preset": BASE, "points": ["PC"]}).json()
    assert "floor_map" not in plain
    _close(data["comfort"]["points"], plain["comfort"]["points"], 1e-9)


@pytest.mark.parametrize("floor, loc, words", [
    ({"spacing_m": 0.3}, ["floor_map", "spacing_m"], "limit of 200"),
    ({"spacing_m": 0.1}, ["floor_map", "spacing_m"], "greater than or equal to 0.2"),
    ({"spacing_m": 0.0}, ["body", "floor_map", "spacing_m"], "greater than 0"),
    ({"spacing_m": 1.0, "nx": 3}, ["body", "floor_map", "nx"], "Extra inputs"),
])
def test_a_floor_map_is_bounded(sqlite_client, floor, loc, words):
    r = _post(sqlite_client, {"preset": BASE, "points": ["PC"], "floor_map": floor})
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == loc and words in item["msg"], item


def test_a_floor_map_too_fine_says_which_spacing_fits(sqlite_client):
    r = _post(sqlite_client, {"preset": BASE, "floor_map": {"spacing_m": 0.3}})
    msg = r.json()["detail"][0]["msg"]
    # 0.3 m: 61 × 9 grid points and the paper's six; 0.45 m: 41 × 6 + 6 = 252 > 200;
    # 0.5 m: 37 × 5 + 6 = 191
    assert "makes 555 recorded" in msg and "0.5 m fits" in msg, msg
    r = _post(sqlite_client, {"preset": BASE, "floor_map": {"spacing_m": 0.5}})
    assert r.status_code == 200, r.text


def test_a_floor_map_is_not_made_with_a_sweep(sqlite_client):
    r = _post(sqlite_client, {"preset": BASE, "floor_map": {"spacing_m": 1.0},
                              "sweep": {"parameter": "speed_kmh", "values": [60, 70]}})
    assert r.status_code == 422
    item = r.json()["detail"][0]
    assert item["loc"] == ["body", "floor_map"] and "not with a sweep" in item["msg"], item


def test_an_uploaded_measured_record_is_estimated_as_the_library_does(sqlite_client, tmp_path):
    """A measured irregularity uploaded as CSV (never a server path): the answer is the
    library's estimate of the same record; a record too short for its spectrum is 422 at the
    excitation."""
    import numpy as np

    from flexride.scenario.presets import CONICAL_TREAD
    from flexride.track.spectra import random_profile

    prof = random_profile(1500.0, "high", ("vertical", "alignment"), 1.0, 120.0, seed=2,
                          ds=0.5, fade_in_m=0.0)
    s = prof.s0 + prof.ds * np.arange(prof.z_left.size)
    rows = np.column_stack([s, prof.z_left, prof.z_right, prof.y_left, prof.y_right])
    text = "distance_m,z_left,z_right,y_left,y_right\n" + "\n".join(
        ",".join(f"{v:.9e}" for v in r) for r in rows)
    up = sqlite_client.post("/api/v1/irregularities", content=text.encode(),
                            headers={"Content-Type": "text/csv"})
    assert up.status_code == 201, up.text
    exc = [{"kind": "measured", "upload": up.json()["id"]}]
    body = {"preset": BASE, "overrides": {**CONICAL_TREAD, "excitation": exc}, "points": ["PC"]}
    r = _post(sqlite_client, body)
    assert r.status_code == 200, r.text
    path = tmp_path / "record.csv"
    path.write_text(text)
    lib = estimate(preset(BASE, **CONICAL_TREAD,
                          excitation=[{"kind": "measured", "path": str(path)}]), ["PC"])
    got = r.json()["comfort"]["points"][0]["directions"]
    for d in ("y", "z"):
        assert got[d]["rms"] == pytest.approx(lib.comfort.points[0].directions[d].rms, rel=1e-9)
    short = text.split("\n")[:400]  # 200 m: fewer than four 256 m segments
    up2 = sqlite_client.post("/api/v1/irregularities", content="\n".join(short).encode(),
                             headers={"Content-Type": "text/csv"})
    body["overrides"]["excitation"] = [{"kind": "measured", "upload": up2.json()["id"]}]
    r2 = _post(sqlite_client, body)
    assert r2.status_code == 422 and r2.json()["detail"][0]["loc"] == ["excitation"], r2.text

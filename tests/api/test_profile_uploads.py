"""Wheel and rail profiles over the API are uploaded data (never a server path): checked by the
same readers as the CLI, stored by content hash, used by jobs through their id."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

from flexride.contact.profiles import rail_60e1, s1002

API = "/api/v1"


def _text(profile, step: int = 20) -> bytes:
    """A profile as plain text of y, z in mm (flexride's convention)."""
    y, z = profile.y[::step] * 1e3, profile.z[::step] * 1e3
    return "".join(f"{a:.6f} {b:.6f}\n" for a, b in zip(y, z, strict=True)).encode()


@pytest.fixture(scope="module")
def wheel_text():
    return _text(s1002())


@pytest.fixture(scope="module")
def rail_text():
    return _text(rail_60e1())


def _post(client, data, **params):
    return client.post(API + "/profiles", params=params, content=data,
                       headers={"Content-Type": "application/octet-stream"})


def test_upload_round_trip_and_use_in_a_job(sqlite_client, wheel_text, rail_text):
    r = _post(sqlite_client, wheel_text, format="txt", kind="wheel")
    assert r.status_code == 201, r.text
    wheel = r.json()
    assert wheel["id"] == hashlib.sha256(wheel_text).hexdigest()
    assert (wheel["format"], wheel["kind"]) == ("txt", "wheel")
    assert r.headers["Location"].endswith(wheel["id"])
    # the points given back are the profile that was sent (mm, same convention)
    sent = np.loadtxt(wheel_text.decode().splitlines())
    assert wheel["points"] == len(sent)
    assert np.allclose(wheel["y_mm"], sent[:, 0]) and np.allclose(wheel["z_mm"], sent[:, 1])
    again = _post(sqlite_client, wheel_text, format="txt", kind="wheel")
    assert again.status_code == 201 and again.json()["id"] == wheel["id"]
    got = sqlite_client.get(wheel["links"]["self"], params={"kind": "wheel"})
    assert got.status_code == 200 and got.json()["points"] == wheel["points"]
    rail = _post(sqlite_client, rail_text, format="csv", kind="rail").json()
    body = {"preset": "paper-metro", "overrides": {
        "contact": {"geometry": "profiles", "flange_back_distance": 1.36,
                    "wheel": {"upload": wheel["id"]}, "rail": {"upload": rail["id"]}},
        "solver": {"dt": 6.25e-5}, "duration_s": 0.5}}
    r = sqlite_client.post(API + "/jobs/validate", json=body)
    assert r.status_code == 200, r.text
    r = sqlite_client.post(API + "/jobs", json=body)
    assert r.status_code == 201, r.text
    scenario = sqlite_client.get(f"{API}/jobs/{r.json()['id']}/scenario").json()
    assert scenario["contact"]["wheel"]["upload"] == wheel["id"]


def test_a_missing_upload_is_refused_at_the_field(sqlite_client):
    body = {"preset": "paper-metro", "overrides": {"contact": {
        "geometry": "profiles", "wheel": {"upload": "0" * 64}}}}
    r = sqlite_client.post(API + "/jobs/validate", json=body)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][-2:] == ["wheel", "upload"]


@pytest.mark.parametrize(("params", "loc", "words"), [
    ({"format": "txt"}, ["query", "kind"], "wheel or a rail"),
    ({"format": "prr", "kind": "wheel"}, ["query", "kind"], "rail profile"),
])
def test_the_kind_must_be_known_and_agree_with_the_format(sqlite_client, wheel_text, params,
                                                          loc, words):
    r = _post(sqlite_client, wheel_text, **params)
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == loc and words in item["msg"]


def _spoiled(text: bytes, how: str) -> bytes:
    lines = text.decode().splitlines(keepends=True)
    if how == "nan":
        lines[4] = "1.0 nan\n"
    elif how == "order":
        lines[5], lines[6] = lines[6], lines[5]
    else:
        return b"\xff\xfe\x00garbage"
    return "".join(lines).encode()


@pytest.mark.parametrize(("how", "words"), [("nan", "line 5"), ("order", "line 7"),
                                            ("bytes", "binary data")])
def test_bad_files_name_the_line_and_are_not_stored(sqlite_client, rail_text, how, words):
    data = _spoiled(rail_text, how)
    r = _post(sqlite_client, data, format="txt", kind="rail")
    assert r.status_code == 422, r.text
    item = r.json()["detail"][0]
    assert item["loc"] == ["body"] and words in item["msg"], item
    digest = hashlib.sha256(data).hexdigest()
    assert sqlite_client.get(f"{API}/profiles/{digest}", params={"kind": "rail"}
                             ).status_code == 404


def test_unknown_format_and_id(sqlite_client, wheel_text):
    r = _post(sqlite_client, wheel_text, format="exe", kind="wheel")
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["query", "format"]
    assert sqlite_client.get(f"{API}/profiles/{'a' * 64}").status_code == 404
    assert sqlite_client.get(f"{API}/profiles/../../etc").status_code == 404


def test_uploads_need_the_token(make_client, wheel_text):
    client = make_client(api_token="a-strong-token-of-32-characters!")
    r = _post(client, wheel_text, format="txt", kind="wheel")
    assert r.status_code == 401

"""``GET /api/v1/contact/geometry`` against the real app.

Oracles: the rows and the conicity equal ``flexride contact table --json`` and ``flexride
contact conicity --json`` for the same parameters (one source); Δr = 0 at Δy = 0 for the
symmetric S1002/60E1 pair; the reference conicity of S1002/60E1 at 1:40 without roll
(3 mm → 0.174, as tests/contact/test_contact_cli.py); the contact points lie on the drawn rail
and on the drawn wheel moved by the documented rigid motion; a rail uploaded as text works like
the built-in one; bounds, unknown ids, a profile of the other kind and path-like values answer
422 at ``["query", name]``.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

from flexride.api.schemas import ContactGeometryOut, ContactTableRow
from flexride.cli import app as cli_app
from flexride.contact.table_rows import TABLE_COLUMNS

API = "/api/v1"
URL = f"{API}/contact/geometry"


def _cli(*args: str) -> object:
    r = CliRunner().invoke(cli_app, ["contact", *args])
    assert r.exit_code == 0, r.output
    return json.loads(r.stdout)


def _get(client, **params):
    r = client.get(URL, params=params)
    assert r.status_code == 200, r.text
    return r.json()


def _error(client, **params):
    r = client.get(URL, params=params)
    assert r.status_code == 422, r.text
    return r.json()["detail"]


@pytest.mark.parametrize(("params", "placement", "grid"), [
    ({"roll": "false", "y_max_mm": 6}, ("--no-roll",), ("--y-max-mm", "6")),
    ({"inclination": "1:20", "flange_back_mm": 1353, "r0_mm": 420, "gauge_height_mm": 16,
      "y_max_mm": 8, "step_mm": 0.1},
     ("--inclination", "1:20", "--flange-back-mm", "1353", "--r0-mm", "420",
      "--gauge-height-mm", "16"), ("--y-max-mm", "8", "--step-mm", "0.1")),
])
def test_rows_and_conicity_are_the_clis(sqlite_client, params, placement, grid):
    got = _get(sqlite_client, **params)
    table = _cli("table", "--json", *placement, *grid)
    assert got["rows"] == table["rows"]
    assert got["columns"] == table["columns"]
    assert got["conicity"] == _cli("conicity", "--json", *placement)
    assert got["conicity_method"] == "integration" and got["conicity_note"] is None


def test_answer_matches_its_model_and_rows_and_contacts_align(sqlite_client):
    got = _get(sqlite_client)
    ContactGeometryOut.model_validate(got)
    assert list(ContactTableRow.model_fields) == [c for c, _ in TABLE_COLUMNS]
    assert len(got["rows"]) == len(got["contacts"]) == 481
    assert [r["dy_mm"] for r in got["rows"]] == [c["dy_mm"] for c in got["contacts"]]
    p = got["parameters"]
    assert (p["wheel"], p["rail"], p["inclination"], p["roll"]) == ("s1002", "60e1", "1:40",
                                                                    True)
    assert (p["gauge_mm"], p["flange_back_mm"], p["y_max_mm"], p["step_mm"]) == (
        1435.0, 1360.0, 12.0, 0.05)
    for kind in ("wheel", "rail"):
        line = got["profiles"][kind]
        assert 100 < len(line["y_mm"]) == len(line["z_mm"]) <= 1500 <= line["points"]
    assert got["profiles"]["gauge_point_y_mm"] == 717.5
    assert got["profiles"]["taping_line_y_mm"] == 750.0


def test_symmetric_pair_and_reference_conicity(sqlite_client):
    for roll in ("true", "false"):
        got = _get(sqlite_client, roll=roll)
        i0 = len(got["rows"]) // 2
        row, at0 = got["rows"][i0], got["contacts"][i0]
        assert row["dy_mm"] == 0.0
        assert abs(row["dr_mm"]) < 1e-6 and abs(row["roll_rad"]) < 1e-9
        assert at0["left_y_mm"] == pytest.approx(-at0["right_y_mm"], abs=1e-6)
        assert at0["left_z_mm"] == pytest.approx(at0["right_z_mm"], abs=1e-6)
        # Δr is odd in Δy for the symmetric pair
        dr = np.array([r["dr_mm"] for r in got["rows"]])
        assert np.allclose(dr, -dr[::-1], atol=1e-4)
    conicity = {c["amplitude_mm"]: c["tan_gamma_e"] for c in got["conicity"]}
    assert conicity[3.0] == pytest.approx(0.174, abs=0.002)


def _distance_to_line(px: float, pz: float, y: np.ndarray, z: np.ndarray) -> float:
    """Least distance (mm) of the point (px, pz) from the polyline (y, z)."""
    a = np.stack([y[:-1], z[:-1]], axis=1)
    b = np.stack([y[1:], z[1:]], axis=1)
    d = b - a
    t = np.clip(((px - a[:, 0]) * d[:, 0] + (pz - a[:, 1]) * d[:, 1])
                / np.maximum((d ** 2).sum(axis=1), 1e-30), 0.0, 1.0)
    q = a + t[:, None] * d
    return float(np.hypot(q[:, 0] - px, q[:, 1] - pz).min())


def _wheel_at(got: dict, i: int) -> tuple[np.ndarray, np.ndarray]:
    """The left wheel at row i by the rule documented in PlacedProfiles."""
    p = got["profiles"]
    y0, z0 = np.array(p["wheel"]["y_mm"]), np.array(p["wheel"]["z_mm"])
    dphi = got["rows"][i]["roll_rad"] - p["roll_rad"]
    c, s = math.cos(dphi), math.sin(dphi)
    dy, dz = y0 - p["axle_y_mm"], z0 - p["axle_z_mm"]
    at = got["contacts"][i]
    return at["dy_mm"] + c * dy - s * dz, at["axle_z_left_mm"] + s * dy + c * dz


@pytest.mark.parametrize("roll", ["true", "false"])
def test_contact_points_lie_on_the_drawn_profiles(sqlite_client, roll):
    got = _get(sqlite_client, roll=roll, inclination="1:20")
    rail = got["profiles"]["rail"]
    ry, rz = np.array(rail["y_mm"]), np.array(rail["z_mm"])
    assert rz.max() == pytest.approx(0.0, abs=0.01)  # the top of rail at z = 0
    n = len(got["rows"])
    for i in range(0, n, 20):
        at = got["contacts"][i]
        point = at["left_y_mm"], at["left_z_mm"]
        assert _distance_to_line(*point, ry, rz) < 0.01, (i, point)
        wy, wz = _wheel_at(got, i)
        assert _distance_to_line(*point, wy, wz) < 0.02, (i, point)
        # nowhere does the wheel sink into the rail (heights compared on the rail's span)
        inside = (wy > ry.min()) & (wy < ry.max())
        assert np.all(wz[inside] >= np.interp(wy[inside], ry, rz) - 0.02), i
        assert at["left_y_mm"] == got["rows"][i]["track_left_mm"]


@pytest.fixture
def uploaded_rail(sqlite_client, tmp_path):
    """The id of 60E1 uploaded as text written by ``flexride contact profile rail 60e1``."""
    f = tmp_path / "rail.txt"
    r = CliRunner().invoke(cli_app, ["contact", "profile", "rail", "60e1", "-o", str(f),
                                     "--every-mm", "0.1"])
    assert r.exit_code == 0, r.output
    r = sqlite_client.post(f"{API}/profiles", params={"format": "txt", "kind": "rail"},
                           content=f.read_bytes(),
                           headers={"Content-Type": "application/octet-stream"})
    assert r.status_code == 201, r.text
    return r.json()["id"]


def test_an_uploaded_rail_works_like_the_built_in_one(sqlite_client, uploaded_rail):
    got = _get(sqlite_client, rail=uploaded_rail, roll="false")
    builtin = _get(sqlite_client, roll="false")
    assert got["parameters"]["rail"] == uploaded_rail
    assert got["rail_name"] != builtin["rail_name"]
    c3 = {c["amplitude_mm"]: c["tan_gamma_e"] for c in got["conicity"]}[3.0]
    assert c3 == pytest.approx(0.174, abs=0.002)
    dr = np.array([r["dr_mm"] for r in got["rows"]])
    dr0 = np.array([r["dr_mm"] for r in builtin["rows"]])
    assert np.abs(dr - dr0).max() < 0.05  # mm, over ±12 mm (the profile every 0.1 mm)
    # the id names fixed content: a second request is the cached answer, byte for byte
    again = sqlite_client.get(URL, params={"rail": uploaded_rail, "roll": "false"})
    assert again.json() == got


def test_a_profile_of_the_other_kind_is_refused_at_the_field(sqlite_client, uploaded_rail):
    # a rail head passes the checks of a wheel profile (text says no kind): the contact says
    (item, *_) = _error(sqlite_client, wheel=uploaded_rail)
    assert item["loc"] == ["query", "wheel"]
    assert "do not rest on their rails at Δy = 0 (upload.txt on 60E1" in item["msg"]


@pytest.mark.parametrize("kind", ["wheel", "rail"])
def test_an_unknown_upload_is_refused_with_its_name(sqlite_client, kind):
    (item,) = _error(sqlite_client, **{kind: "ab" * 32})
    assert item["loc"] == ["query", kind]
    assert "no uploaded profile with id abababababab" in item["msg"]


@pytest.mark.parametrize("value", ["../../etc/passwd", "/etc/passwd", "s1002.prw",
                                   "C:\\profiles\\s1002.prw", "s1002/../x", "A" * 64])
def test_paths_are_refused(sqlite_client, value):
    for kind in ("wheel", "rail"):
        (item,) = _error(sqlite_client, **{kind: value})
        assert item["loc"] == ["query", kind]
        assert "should match pattern" in item["msg"]


@pytest.mark.parametrize(("name", "value", "bound"), [
    ("y_max_mm", 25, "≤ 20"),
    ("y_max_mm", 0, "≥ 0.1"),
    ("step_mm", 0.001, "≥ 0.01"),
    ("step_mm", 2, "≤ 1"),
    ("gauge_mm", 2000, "≤ 1700"),
    ("gauge_height_mm", 1, "≥ 5"),
    ("flange_back_mm", 800, "≥ 900"),
    ("r0_mm", 150, "> 200"),
    ("r0_mm", "nan", "≤ 700"),
])
def test_out_of_range_values_name_the_field_and_the_range(sqlite_client, name, value, bound):
    items = _error(sqlite_client, **{name: value})
    assert [it["loc"] for it in items] == [["query", name]]
    assert f"(allowed: {bound}" in items[0]["msg"]


def test_combinations_are_refused_at_the_field(sqlite_client):
    (item,) = _error(sqlite_client, y_max_mm=0.1, step_mm=0.5)
    assert item["loc"] == ["query", "step_mm"] and "must not exceed" in item["msg"]
    (item,) = _error(sqlite_client, gauge_mm=1300, flange_back_mm=1360)
    assert item["loc"] == ["query", "flange_back_mm"] and "smaller than the gauge" in item["msg"]
    items = _error(sqlite_client, gauge_mm=1700, flange_back_mm=900)
    assert [it["loc"] for it in items] == [["query", "gauge_mm"], ["query", "flange_back_mm"]]
    assert "do not rest on their rails at Δy = 0 (S1002" in items[0]["msg"]
    assert "check the gauge and the flange-back distance" in items[0]["msg"]
    (item,) = _error(sqlite_client, inclination="1:30")
    assert item["loc"] == ["query", "inclination"]


def test_openapi_documents_units_bounds_and_the_model(sqlite_client):
    spec = sqlite_client.get(f"{API}/openapi.json").json()
    op = spec["paths"][URL]["get"]
    params = {p["name"]: p for p in op["parameters"]}
    assert params["gauge_mm"]["schema"]["minimum"] == 1000.0
    assert params["gauge_mm"]["schema"]["maximum"] == 1700.0
    assert params["y_max_mm"]["schema"]["maximum"] == 20.0
    assert params["step_mm"]["schema"]["minimum"] == 0.01
    assert all("(mm)" in params[n]["description"] for n in params if n.endswith("_mm"))
    ok = op["responses"]["200"]["content"]["application/json"]["schema"]
    assert ok["$ref"].endswith("/ContactGeometryOut")
    rows = spec["components"]["schemas"]["ContactTableRow"]["properties"]
    assert rows["dr_mm"]["description"] == "rolling-radius difference r_left − r_right (mm)"

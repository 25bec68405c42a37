"""Profile readers: the shipped files read to consistent geometry; malformed files give located
errors.

Oracles: the raw numbers of the files parsed here in plain Python (SIMPACK: y z rows between
point.begin/point.end; the .ban is the .prr mirrored, as the shared README documents), the
S1002 definition (the EN 15302 wheel A is close to it), hand-computed transforms of the SIMPACK
processing keys on a synthetic file.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from contact.profile_data import en15302_file, mbench_file
from flexride.contact.profiles import read_profile, read_profile_bytes, s1002
from flexride.contact.profiles.s1002 import s1002_radius_raw
from flexride.errors import ScenarioError


def _simpack_rows(path) -> np.ndarray:
    rows = []
    inside = False
    for line in path.read_text().splitlines():
        text = line.split("!")[0].strip()
        if text == "point.begin":
            inside = True
        elif text == "point.end":
            inside = False
        elif inside and text:
            rows.append([float(v) for v in text.split()])
    return np.array(rows)


def test_prw_is_the_mirrored_wheel_in_m_with_z_up() -> None:
    path = mbench_file("MBench_S1002_v3.prw")
    raw = _simpack_rows(path)  # y = −s, z = radius increase (mm)
    p = read_profile(path)
    assert p.kind == "wheel" and p.name == "MBench_S1002_v3.prw" and p.n == raw.shape[0]
    order = np.argsort(-raw[:, 0])
    np.testing.assert_allclose(p.y, -raw[order, 0] * 1e-3, rtol=0, atol=1e-15)
    np.testing.assert_allclose(p.z, -raw[order, 1] * 1e-3, rtol=0, atol=1e-15)
    # flange tip: F = 28 mm at s = −55 mm, on the gauge side
    assert p.y[np.argmin(p.z)] * 1e3 == pytest.approx(-55.0, abs=0.4)
    assert p.z.min() * 1e3 == pytest.approx(-28.0, abs=1e-3)


def test_prr_is_read_with_z_up_and_its_origin_at_the_canted_top() -> None:
    path = mbench_file("MBench_UIC60_v3.prr")
    raw = _simpack_rows(path)
    p = read_profile(path)
    assert p.kind == "rail" and raw.shape[0] == 495
    # near-duplicate points (< 0.1 µm apart, on the vertical head sides) are dropped
    assert 480 <= p.n < 495
    i = int(np.argmax(p.z))
    assert abs(p.y[i]) < 5e-4 and abs(p.z[i]) < 1e-6
    # every kept point is a file point with z negated
    for y, z in zip(p.y[::37], p.z[::37], strict=True):
        k = int(np.argmin(np.abs(raw[:, 0] * 1e-3 - y)))
        assert raw[k, 1] * 1e-3 == pytest.approx(-z, abs=1e-15)


def test_ban_equals_the_mirrored_prr() -> None:
    prr = read_profile(mbench_file("MBench_UIC60_v3.prr"))
    ban = read_profile(mbench_file("MBench_UIC60_v3.ban"))
    assert ban.kind == "rail" and ban.n == prr.n
    np.testing.assert_allclose(ban.y, prr.y, rtol=0, atol=1e-12)
    np.testing.assert_allclose(ban.z, prr.z, rtol=0, atol=1e-12)
    assert ban.lines is not None and ban.lines[0] >= 30  # data start after the header


@pytest.mark.parametrize("name", ["RUIC519A.dat", "RUIC519B.dat", "RUIC519H.dat", "RUIC519I.dat"])
def test_en15302_reference_wheels(name: str) -> None:
    p = read_profile(en15302_file(name), "wheel")
    assert p.n == 1001
    assert p.y[0] * 1e3 == pytest.approx(-70.0) and p.y[-1] * 1e3 == pytest.approx(65.0)
    tip = int(np.argmin(p.z))
    assert p.z[tip] * 1e3 == pytest.approx(-28.0, abs=0.01)
    assert p.y[tip] * 1e3 == pytest.approx(-55.0, abs=0.2)


def test_wheel_a_is_close_to_s1002_on_the_tread() -> None:
    p = read_profile(en15302_file("RUIC519A.dat"), "wheel")
    s = p.y * 1e3
    m = (s > -30.0) & (s < 30.0)
    rms = float(np.sqrt(np.mean((-p.z[m] * 1e3 - s1002_radius_raw(s[m])) ** 2)))
    assert 0.05 < rms < 0.3  # README: rms 0.16 mm, close but not the exact analytic S1002


def test_en15302_reference_rail() -> None:
    p = read_profile(en15302_file("SUIC519A.dat"), "rail")
    assert p.n == 1001 and p.y[0] * 1e3 == pytest.approx(-32.5)
    i = int(np.argmax(p.z))
    assert p.y[i] > 0.0  # already in track orientation: the top lies toward the field side


def test_bytes_reader_reads_the_same_and_names_only_the_file() -> None:
    data = mbench_file("MBench_S1002_v3.prw").read_bytes()
    a = read_profile_bytes(data, "/srv/uploads/x/MBench_S1002_v3.prw")
    b = read_profile(mbench_file("MBench_S1002_v3.prw"))
    assert a.name == "MBench_S1002_v3.prw"
    np.testing.assert_array_equal(a.y, b.y)
    with pytest.raises(ScenarioError) as exc:
        read_profile_bytes(b"1 2\n3 x\n", "/srv/uploads/secret/w.txt", "wheel")
    assert str(exc.value).startswith("w.txt, line 2:") and "/srv" not in str(exc.value)


# --- SIMPACK processing keys on a synthetic rail ------------------------------------------

def _prr(points: list[tuple[float, float]], keys: str = "", kind: int = 0) -> bytes:
    rows = "\n".join(f"    {y:.9f} {z:.9f}" for y, z in points)
    return (
        "! synthetic\n  header.begin\n    version = 1\n"
        f"    type = {kind}  ! rail\n  header.end\n"
        "  spline.begin\n    units.len.f = 1000.0\n" + keys +
        "    point.begin\n" + rows + "\n    point.end\n  spline.end\n"
    ).encode()


def _crown(n: int = 41) -> list[tuple[float, float]]:
    # an R80 head in mm, z down (SIMPACK), y from −30 to 30
    return [(y, y * y / 160.0) for y in np.linspace(-30.0, 30.0, n)]


def test_simpack_units_and_z_down() -> None:
    p = read_profile_bytes(_prr(_crown()), "c.prr")
    np.testing.assert_allclose(p.y, np.linspace(-0.030, 0.030, 41), atol=1e-15)
    np.testing.assert_allclose(p.z, -(p.y * 1e3) ** 2 / 160.0 * 1e-3, atol=1e-15)


def test_simpack_shift_mirror_rotate_and_bounds() -> None:
    keys = ("    shift.y = 2.0\n    shift.z = 1.0\n    mirror.y = 1\n"
            "    bound.y.min = -20.0\n    bound.y.max = 25.0\n")
    p = read_profile_bytes(_prr(_crown(), keys), "c.prr")
    # shift then bound (on the shifted y) then mirror: y' = −(y + 2) for −20 ≤ y + 2 ≤ 25
    y_file = np.linspace(-30.0, 30.0, 41)
    keep = (y_file + 2.0 >= -20.0) & (y_file + 2.0 <= 25.0)
    exp_y = np.sort(-(y_file[keep] + 2.0)) * 1e-3
    np.testing.assert_allclose(p.y, exp_y, atol=1e-15)
    y_src = -p.y * 1e3 - 2.0
    np.testing.assert_allclose(p.z, -(y_src**2 / 160.0 + 1.0) * 1e-3, atol=1e-15)
    # rotation about x in the file's frame: y' = y cos α − z sin α, z' = y sin α + z cos α
    alpha = 0.02
    q = read_profile_bytes(_prr(_crown(), f"    rotate = {alpha}\n"), "c.prr")
    y0 = 10.5  # a file point
    z0 = y0 * y0 / 160.0
    ye = y0 * math.cos(alpha) - z0 * math.sin(alpha)
    ze = y0 * math.sin(alpha) + z0 * math.cos(alpha)
    k = int(np.argmin(np.abs(q.y - ye * 1e-3)))
    assert q.y[k] == pytest.approx(ye * 1e-3, abs=1e-14)
    assert q.z[k] == pytest.approx(-ze * 1e-3, abs=1e-14)


def test_simpack_wheel_type_checked_against_the_extension() -> None:
    with pytest.raises(ScenarioError, match=r"^c\.prw: header type = 0 marks a rail profile"):
        read_profile_bytes(_prr(_crown()), "c.prw")
    with pytest.raises(ScenarioError, match=r"expected a wheel"):
        read_profile_bytes(_prr(_crown()), "c.prr", "wheel")


# --- malformed files -----------------------------------------------------------------------

def _text(rows: list[str]) -> bytes:
    return ("\n".join(rows) + "\n").encode()


def _wheel_rows() -> list[str]:
    s = np.linspace(-60.0, 50.0, 40)
    return [f"{v:.4f} {-float(s1002_radius_raw(v)):.6f}" for v in s]


def test_good_text_wheel_with_header_and_comments() -> None:
    p = read_profile_bytes(_text(["# S1002 sampled", "y_mm,z_mm", *_wheel_rows()]), "w.csv",
                           "wheel")
    assert p.n == 40 and p.kind == "wheel"
    assert p.lines is not None and p.lines[0] == 3


def test_non_monotonic_file_names_the_line(tmp_path) -> None:
    rows = _wheel_rows()
    rows[10], rows[11] = rows[11], rows[10]
    f = tmp_path / "bad_order.txt"
    f.write_bytes(_text(rows))
    with pytest.raises(ScenarioError) as exc:
        read_profile(f, "wheel")
    msg = str(exc.value)
    assert msg.startswith("bad_order.txt, line 12:") and "not increasing" in msg
    assert str(tmp_path) not in msg


def test_too_few_points() -> None:
    with pytest.raises(ScenarioError, match=r"^w\.txt: a wheel profile needs at least 10"):
        read_profile_bytes(_text(_wheel_rows()[:5]), "w.txt", "wheel")


def test_nan_is_located() -> None:
    rows = _wheel_rows()
    rows[7] = "1.0 nan"
    with pytest.raises(ScenarioError, match=r"^w\.txt, line 8: coordinate is NaN"):
        read_profile_bytes(_text(rows), "w.txt", "wheel")


def test_wrong_orientation() -> None:
    mirrored = [f"{-float(r.split()[0]):.4f} {r.split()[1]}" for r in _wheel_rows()][::-1]
    with pytest.raises(ScenarioError, match=r"flange must lie at negative y"):
        read_profile_bytes(_text(mirrored), "w.txt", "wheel")
    z_down = [f"{r.split()[0]} {-float(r.split()[1]):.6f}" for r in _wheel_rows()]
    with pytest.raises(ScenarioError, match=r"flange must point down"):
        read_profile_bytes(_text(z_down), "w.txt", "wheel")
    crown_down = [f"{y:.3f} {y * y / 600:.6f}" for y in np.linspace(-30, 30, 30)]
    with pytest.raises(ScenarioError, match=r"head top must be the highest point"):
        read_profile_bytes(_text(crown_down), "r.txt", "rail")


def test_unreadable_files(tmp_path) -> None:
    with pytest.raises(ScenarioError, match=r"^nope\.prw: cannot read"):
        read_profile(tmp_path / "nope.prw")
    with pytest.raises(ScenarioError, match=r"binary data"):
        read_profile_bytes(b"\x00\x01\x02" * 50, "w.prw")
    with pytest.raises(ScenarioError, match=r"^w\.txt, line 1: expected two columns"):
        read_profile_bytes(b"1 2 3\n", "w.txt", "wheel")
    with pytest.raises(ScenarioError, match=r"give the kind"):
        read_profile_bytes(_text(_wheel_rows()), "w.txt")


def test_simpack_structure_errors() -> None:
    good = _prr(_crown()).decode()
    with pytest.raises(ScenarioError, match=r"^c\.prr: unexpected end of file inside the point"):
        read_profile_bytes(good.split("point.end")[0].encode(), "c.prr")
    bad = good.replace("    point.begin", "    point.begin\n    point.begin")
    with pytest.raises(ScenarioError, match=r"^c\.prr, line \d+: misplaced 'point.begin'"):
        read_profile_bytes(bad.encode(), "c.prr")
    bad = good.replace("type = 0", "type = 7")
    with pytest.raises(ScenarioError, match=r"^c\.prr, line 4: header type must be 0"):
        read_profile_bytes(bad.encode(), "c.prr")
    rows = good.splitlines()
    k = next(i for i, r in enumerate(rows) if "point.begin" in r) + 3
    rows[k] = "    1.0"
    with pytest.raises(ScenarioError, match=rf"^c\.prr, line {k + 1}: a point row needs"):
        read_profile_bytes("\n".join(rows).encode(), "c.prr")


def test_miniprof_errors() -> None:
    text = mbench_file("MBench_UIC60_v3.ban").read_text()
    cut = "\n".join(text.splitlines()[:-3]) + "\n"
    with pytest.raises(ScenarioError, match=r"XYPoints = 495 but the file has 492 data rows"):
        read_profile_bytes(cut.encode(), "m.ban")
    bad = text.replace("ColumnDef=X,Y", "ColumnDef=A,C")
    with pytest.raises(ScenarioError, match=r"^m\.ban, line \d+: ColumnDef must name"):
        read_profile_bytes(bad.encode(), "m.ban")
    with pytest.raises(ScenarioError, match=r"holds a rail profile, expected a wheel"):
        read_profile_bytes(text.encode(), "m.ban", "wheel")


def test_s1002_profile_round_trips_through_text() -> None:
    p = s1002(step=2e-4)
    rows = [f"{y * 1e3:.9f},{z * 1e3:.9f}" for y, z in zip(p.y, p.z, strict=True)]
    q = read_profile_bytes(_text(["y_mm,z_mm", *rows]), "s.csv", "wheel")
    np.testing.assert_allclose(q.y, p.y, atol=1e-12)
    np.testing.assert_allclose(q.z, p.z, atol=1e-12)


def test_miniprof_wheel_old_style_header() -> None:
    # old-style MiniProf wheel: free-text header, a blank line, X from the flange back toward
    # the field side, Y the radius increase (mm)
    s = np.linspace(-69.0, 60.0, 200)
    f = s1002_radius_raw(s)
    head = ['#MINIWHEELPROF', 'W01.whl', 'MINIPROF 2020', '" 32.50 28.00 10.79', '(Sd/Sh/qR)', '']
    rows = [f"{x + 70.0:.6f}    {y:.6f}" for x, y in zip(s, f, strict=True)]
    p = read_profile_bytes(_text(head + rows), "W01.whl")
    assert p.kind == "wheel" and p.n == 200
    np.testing.assert_allclose(p.y, s * 1e-3, atol=1e-9)  # 1e-6 mm in the file
    np.testing.assert_allclose(p.z, -f * 1e-3, atol=1e-9)
    assert p.lines is not None and p.lines[0] == 7

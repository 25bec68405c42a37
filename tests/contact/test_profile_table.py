"""Kernel tables of a profile pair: semantics against the existing conical table, the two-slot
layout, materials, caching and build time.

Oracles: for a cone on a round head (no roll) the table must equal what the independent
:func:`flexride.contact.geometry.conical_table` computes for the same conicity, radii and crown
radius (r = r0 ± λΔy, γ = atan λ, dz = r − r0, yc = −Δy up to a constant, Hertz factors and
Kalker coefficients); the rest are layout and bookkeeping checks.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest

from contact.profile_data import LAM, cone_wheel, crown_rail
from flexride.contact.geometry import TABLE_FIELDS, conical_table
from flexride.contact.hertz import hertz_constant
from flexride.contact.placement import Placement
from flexride.contact.profile_table import (
    GAP_NONE,
    POINT_FIELDS,
    POINT_PARAMS,
    contact_tables_from_geometry,
    profile_contact_table,
)
from flexride.contact.profiles import Profile, rail_60e1, s1002
from flexride.contact.search import SearchSettings, search_contact

E, NU = 2.1e11, 0.28


@pytest.fixture(autouse=True)
def _tmp_cache(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("FLEXRIDE_CACHE_DIR", str(tmp_path / "cache"))


@pytest.fixture(scope="module")
def s1002_table():
    return profile_contact_table(s1002(), rail_60e1(), use_cache=False)


def test_cone_table_equals_the_conical_table() -> None:
    geo = search_contact(cone_wheel(), crown_rail(), Placement(inclination=0.0),
                         SearchSettings(y_max=0.005, roll=False))
    tab = contact_tables_from_geometry(geo, E, NU).single_table()
    ref = conical_table(r0=0.46, conicity=LAM, b0=geo.placement.taping_line,
                        rail_head_radius=0.3, E=E, nu=NU, y_max=0.005, n=geo.n)
    assert tab.y0 == pytest.approx(ref.y0) and tab.dy == pytest.approx(ref.dy)
    # the cone's contact is not at its taping line: shift r and yc by that constant
    s0 = geo.at_rigid("s")[:, geo.i0]
    np.testing.assert_allclose(tab.r + LAM * s0[:, None], ref.r, atol=1e-9)
    np.testing.assert_allclose(tab.gamma, ref.gamma, atol=1e-6)
    np.testing.assert_allclose(tab.dz, ref.dz, atol=1e-9)
    np.testing.assert_allclose(tab.yc - tab.yc[:, geo.i0:geo.i0 + 1], ref.yc, atol=2e-7)
    for name in ("ca", "cb", "c11", "c22", "c23", "c33"):
        np.testing.assert_allclose(getattr(tab, name), getattr(ref, name), rtol=2e-3,
                                   err_msg=name)


def test_layout_for_the_kernel(s1002_table) -> None:
    t = s1002_table
    params, data = t.as_arrays()
    assert params.shape == (len(POINT_PARAMS),) and data.shape == (2, 2, len(POINT_FIELDS), t.n)
    assert data.flags.c_contiguous and not data.flags.writeable
    assert POINT_FIELDS[: len(TABLE_FIELDS)] == TABLE_FIELDS
    assert params[0] == pytest.approx(-0.012) and params[1] == pytest.approx(5e-5)
    assert params[4] == GAP_NONE and params[5] == pytest.approx(E / (2 * (1 + NU)))
    for slot in (0, 1):
        _, block = t.slot_table(slot).as_arrays()  # [10, 2, n]
        for side in (0, 1):
            np.testing.assert_array_equal(data[side, slot, : len(TABLE_FIELDS)], block[:, side])


def test_slots_and_the_single_table(s1002_table) -> None:
    t = s1002_table
    gap, dz = t.field("gap"), t.field("dz")
    rigid = t.rigid_slot
    i = np.arange(t.n)
    for side in (0, 1):
        assert np.all(gap[side, rigid[side], i] == 0.0)
        other = 1 - rigid[side]
        g2 = gap[side, other, i]
        assert np.all(g2 > 0.0)
        # dz of the other slot is the rigid one minus its gap
        np.testing.assert_allclose(dz[side, other, i], dz[side, rigid[side], i] - g2, atol=1e-15)
    # Δy = 0: tread on both wheels, no flange candidate (its gap is GAP_NONE)
    i0 = t.n // 2
    assert rigid[:, i0].tolist() == [0, 0] and np.all(gap[:, 1, i0] == GAP_NONE)
    # 8 mm to the left: the left wheel runs on its flange, the right one on its tread
    i8 = int(np.argmin(np.abs(t.y_grid - 0.008)))
    assert rigid[:, i8].tolist() == [1, 0]
    single = t.single_table()
    assert single.gamma[0, i8] == t.field("gamma")[0, 1, i8] > 0.8
    assert single.gamma[1, i8] == t.field("gamma")[1, 0, i8] < 0.1
    assert single.flange_stiffness == 0.0
    assert single.flange_clearance == pytest.approx(t.flange_onset)
    assert 0.0045 <= t.flange_onset <= 0.0055
    # Hertz constants: tread contacts stiffer than the conformal flange-root ones at 5 mm
    assert np.all(np.isfinite(t.field("gh"))) and np.all(t.field("gh") > 0.0)
    # the flanging left wheel touches its rail on the gauge side, toward the track centre (−y)
    assert t.field("yr")[0, 1, i8] < -0.02


def test_materials_and_normal_law() -> None:
    geo = search_contact(s1002(), rail_60e1(), settings=SearchSettings(y_max=0.004))
    a = contact_tables_from_geometry(geo, E, NU)
    b = contact_tables_from_geometry(geo, E, NU, shear_modulus=8.0e10, normal="zhai-worn")
    assert a.shear_modulus == pytest.approx(E / (2.0 * 1.28))
    assert b.shear_modulus == 8.0e10
    r = b.field("r")
    expect = np.vectorize(lambda v: hertz_constant(float(v), "worn"))(r)
    np.testing.assert_allclose(b.field("gh"), expect, rtol=1e-12)
    assert a.meta["normal"] == "hertz" and b.meta["normal"] == "zhai-worn"


def test_cache_by_content(tmp_path) -> None:
    w, r = s1002(), rail_60e1()
    t0 = time.perf_counter()
    a = profile_contact_table(w, r, settings=SearchSettings(y_max=0.006))
    t_build = time.perf_counter() - t0
    files = sorted((tmp_path / "cache").rglob("*.npz"))
    assert len(files) == 1
    same = Profile("wheel", np.array(w.y), np.array(w.z), w.name)  # equal content, new object
    t0 = time.perf_counter()
    b = profile_contact_table(same, r, settings=SearchSettings(y_max=0.006))
    t_hit = time.perf_counter() - t0
    np.testing.assert_array_equal(a.data, b.data)
    assert b.meta == a.meta and t_hit < t_build
    profile_contact_table(w, r, Placement(gauge=1.437), settings=SearchSettings(y_max=0.006))
    assert len(sorted((tmp_path / "cache").rglob("*.npz"))) == 2


def test_build_time_of_one_pair() -> None:
    w, r = s1002(), rail_60e1()
    profile_contact_table(w, r, use_cache=False)  # compiled kernels loaded
    t0 = time.perf_counter()
    profile_contact_table(w, r, use_cache=False)
    elapsed = time.perf_counter() - t0
    # target ≤ 1 s (measured ≈ 0.15 s); margin for a loaded shared CI machine
    assert elapsed < 2.0, f"table build took {elapsed:.2f} s"


def test_roll_is_the_kinematic_roll(s1002_table) -> None:
    t = s1002_table
    np.testing.assert_allclose(t.roll, -t.roll[::-1], atol=1e-12)
    i = int(np.argmin(np.abs(t.y_grid + 0.006)))
    assert t.roll[i] == pytest.approx(-6.5e-4, rel=0.1)  # right wheel on its flange root
    assert math.isfinite(float(t.roll.sum()))


def test_flange_angle_of_s1002_is_its_70_degree_flank():
    """EN 13715 draws the S1002 flange flank as a straight line at 70° to the axle: the largest
    flange contact angle of the table (what Nadal's limit uses) is that angle."""
    table = profile_contact_table(s1002(), rail_60e1(), Placement(), E=E, nu=NU)
    assert math.degrees(table.flange_angle()) == pytest.approx(70.0, abs=0.05)

"""Tests of the contact geometry table, its conical builder and the compiled helpers.

Oracles: the cone's closed-form kinematics (r = r0 ± λΔy, constant γ = arctan λ), mirror
symmetry of the track, exactness of linear interpolation on linear data and the dead-band
spring written out by hand.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from flexride.contact import (
    TABLE_FIELDS,
    TABLE_PARAMS,
    ContactTable,
    conical_table,
    flange_force,
    hertz_ellipse,
    interp_uniform,
    kalker_from_axes,
)
from flexride.errors import ScenarioError

LAM = 0.05
R0 = 0.42


@pytest.fixture(scope="module")
def table() -> ContactTable:
    return conical_table(r0=R0, conicity=LAM, n=401, y_max=0.02)


def test_grid(table: ContactTable) -> None:
    assert table.n == 401
    assert table.y0 == pytest.approx(-0.02)
    assert table.dy == pytest.approx(1e-4)
    assert table.y_grid[200] == pytest.approx(0.0, abs=1e-15)
    assert table.y_grid[-1] == pytest.approx(0.02, rel=1e-12)


def test_rolling_radius_difference_is_twice_conicity_times_shift(table: ContactTable) -> None:
    y = table.y_grid
    np.testing.assert_allclose(table.r[0] - table.r[1], 2.0 * LAM * y, rtol=0, atol=1e-15)
    np.testing.assert_allclose(table.r[0], R0 + LAM * y, rtol=1e-15, atol=0)


def test_wheelset_moved_left_rolls_on_larger_left_radius(table: ContactTable) -> None:
    i = int(np.searchsorted(table.y_grid, 0.005))
    assert table.y_grid[i] > 0.0
    assert table.r[0, i] > R0 > table.r[1, i]


@pytest.mark.parametrize("field", TABLE_FIELDS)
def test_left_right_mirror_symmetry(table: ContactTable, field: str) -> None:
    # The track is symmetric: wheel L at Δy sees what wheel R sees at −Δy. The lateral offset
    # yc is a coordinate along y (wheelset frame), so it changes sign under the mirror.
    arr = getattr(table, field)
    sign = -1.0 if field == "yc" else 1.0
    np.testing.assert_allclose(arr[0], sign * arr[1, ::-1], rtol=1e-12, atol=1e-15)


def test_cone_contact_angle_rise_and_shift(table: ContactTable) -> None:
    y = table.y_grid
    np.testing.assert_allclose(table.gamma, math.atan(LAM), rtol=1e-15)
    assert np.all(table.gamma > 0.0)  # the normal force pushes each wheel toward the centre
    np.testing.assert_allclose(table.dz, table.r - R0, rtol=0, atol=1e-16)
    np.testing.assert_allclose(table.dz[0], LAM * y, rtol=0, atol=1e-15)
    np.testing.assert_allclose(table.yc, np.stack([-y, -y]), rtol=0, atol=1e-15)


@pytest.mark.parametrize("index", [0, 137, 200, 400])
def test_ellipse_and_kalker_coefficients_match_the_contact_laws(table: ContactTable, index: int):
    for side in range(2):
        r = R0 + (LAM if side == 0 else -LAM) * table.y_grid[index]
        a_curv = 0.5 / (r / math.cos(math.atan(LAM)))  # wheel normal-section radius r/cos γ
        ca, cb = hertz_ellipse(a_curv, 0.5 / 0.3, 2.1e11, 0.28)
        assert (table.ca[side, index], table.cb[side, index]) == pytest.approx((ca, cb), rel=1e-12)
        coeffs = (table.c11, table.c22, table.c23, table.c33)
        assert tuple(c[side, index] for c in coeffs) == pytest.approx(
            kalker_from_axes(ca, cb, 0.28), rel=1e-12
        )


def test_patch_is_longer_than_wide_for_this_wheel_and_rail(table: ContactTable) -> None:
    # Wheel radius 0.42 m > rail crown radius 0.3 m → smaller curvature along x → a > b,
    # so the a > b branch of Kalker's table applies (C11 above the circular 3.40 … 5.20).
    assert np.all(table.ca > table.cb)
    assert np.all(table.c11 > 4.12)


def test_patch_size_plausible_at_static_wheel_load(table: ContactTable) -> None:
    # ~70 kN on a 0.42 m wheel and a 0.3 m crown: semi-axes of a few mm.
    n13 = 7.0e4 ** (1 / 3)
    assert 4e-3 < table.ca[0, 200] * n13 < 8e-3
    assert 3e-3 < table.cb[0, 200] * n13 < 7e-3


def test_as_arrays_layout(table: ContactTable) -> None:
    params, data = table.as_arrays()
    assert params.dtype == np.float64 and params.shape == (len(TABLE_PARAMS),)
    assert data.dtype == np.float64 and data.shape == (len(TABLE_FIELDS), 2, table.n)
    assert data.flags.c_contiguous
    for k, name in enumerate(TABLE_PARAMS):
        assert params[k] == getattr(table, name)
    for k, name in enumerate(TABLE_FIELDS):
        np.testing.assert_array_equal(data[k], getattr(table, name))
    # A kernel row is contiguous and interpolates like the dataclass field.
    row = data[TABLE_FIELDS.index("r"), 0]
    assert row.flags.c_contiguous
    assert interp_uniform(row, params[0], params[1], 0.0123) == pytest.approx(R0 + LAM * 0.0123)


def test_table_is_immutable(table: ContactTable) -> None:
    with pytest.raises(dataclasses.FrozenInstanceError):
        table.dy = 1.0  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        table.r[0, 0] = 1.0


# --- interp_uniform ---------------------------------------------------------------------------


def test_interpolation_exact_for_linear_data() -> None:
    y0, dy, n = -0.013, 2.5e-4, 97
    row = 3.0 - 7.5 * (y0 + dy * np.arange(n))
    rng = np.random.default_rng(1)
    for y in rng.uniform(y0, y0 + dy * (n - 1), 200):
        assert interp_uniform(row, y0, dy, y) == pytest.approx(3.0 - 7.5 * y, rel=1e-13)
    for i in (0, 1, 50, n - 1):
        assert interp_uniform(row, y0, dy, y0 + i * dy) == pytest.approx(row[i], rel=1e-14)


def test_interpolation_is_clamped_and_propagates_nan() -> None:
    row = np.array([1.0, 4.0, 2.0])
    assert interp_uniform(row, 0.0, 1.0, -5.0) == 1.0
    assert interp_uniform(row, 0.0, 1.0, 99.0) == 2.0
    assert interp_uniform(row, 0.0, 1.0, 0.5) == pytest.approx(2.5)
    assert interp_uniform(row, 0.0, 1.0, 1.25) == pytest.approx(3.5)
    assert math.isnan(interp_uniform(row, 0.0, 1.0, math.nan))


# --- flange_force -----------------------------------------------------------------------------


@pytest.mark.parametrize("dy_rel", [0.0, 0.004, -0.0079, 0.008, -0.008])
def test_flange_force_zero_inside_clearance(dy_rel: float) -> None:
    assert flange_force(dy_rel, 0.008, 1.5e8) == 0.0


@pytest.mark.parametrize(("dy_rel", "expected"), [(0.009, -1.5e5), (-0.010, 3.0e5)])
def test_flange_force_beyond_clearance(dy_rel: float, expected: float) -> None:
    # k = 1.5e8 N/m: 1 mm into the flange → 150 kN pushing back toward the centre.
    assert flange_force(dy_rel, 0.008, 1.5e8) == pytest.approx(expected, rel=1e-9)


def test_flange_force_is_odd() -> None:
    for d in (0.0085, 0.012, 0.03):
        assert flange_force(-d, 0.008, 1.5e8) == -flange_force(d, 0.008, 1.5e8)


# --- validation -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"r0": -0.42}, "r0"),
        ({"conicity": -0.05}, "conicity"),
        ({"conicity": 1.5}, "conicity"),
        ({"b0": 0.0}, "b0"),
        ({"flange_clearance": -0.001}, "flange_clearance"),
        ({"flange_stiffness": -1.0}, "flange_stiffness"),
        ({"rail_head_radius": 0.0}, "rail_head_radius"),
        ({"E": 0.0}, "Young"),
        ({"nu": 0.55}, "Poisson"),
        ({"y_max": -0.02}, "y_max"),
        ({"n": 1}, "grid points"),
        ({"n": 10.5}, "grid points"),
        ({"conicity": 0.9, "y_max": 0.5}, "conicity·y_max"),
    ],
)
def test_conical_table_rejects_bad_inputs(kwargs: dict, match: str) -> None:
    with pytest.raises(ScenarioError, match=match):
        conical_table(**kwargs)


def test_contact_table_rejects_inconsistent_arrays(table: ContactTable) -> None:
    with pytest.raises(ScenarioError, match="shape"):
        dataclasses.replace(table, gamma=np.zeros((2, 5)))
    with pytest.raises(ScenarioError, match=r"\[2, n\]"):
        dataclasses.replace(table, r=np.ones((3, table.n)))
    with pytest.raises(ScenarioError, match="NaN"):
        dataclasses.replace(table, c11=np.full((2, table.n), np.nan))
    with pytest.raises(ScenarioError, match="dy"):
        dataclasses.replace(table, dy=0.0)

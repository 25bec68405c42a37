"""Whole-floor comfort maps from the estimate (:mod:`flexride.frequency.floor`) against rigid-body
kinematics, the vehicle's symmetry and the estimate of a single point.

Oracles:

* **Rigid-body kinematics.** A rigid car body's vertical acceleration at floor point (x, y) is
  a_z = z̈ − x·θ̈ + y·φ̈ (bounce, pitch, roll of the body; signs aside), so per input component
  its FRF is A + x·B + y·C and its variance, a sum over components and frequencies of
  |A + xB + yC|², is a quadratic polynomial in (x, y): 1, x, y, x², xy, y². The same holds for
  any linear frequency weighting (ISO 2631 a_w²). The lateral acceleration at floor height
  (ÿ + x·ψ̈ + h·φ̈ + gφ) does not depend on y at all.
* **Symmetry.** On straight track the vehicle is symmetric left/right and the inputs are
  symmetric (vertical profile, alignment, gauge) or antisymmetric (cross level) and
  independent: every map is the same at y and −y.
* **One point.** A grid point's indices are those of the same point asked for by itself (a
  user point at its position in a scenario without the grid).
"""

from __future__ import annotations

import numpy as np
import pytest

from conftest import preset
from flexride.errors import ScenarioError
from flexride.frequency import estimate
from flexride.frequency.floor import floor_scenario

BASE = "paper-random-straight-80"


@pytest.fixture(scope="module")
def floor():
    return estimate(preset(BASE), floor_grid_m=1.0).floor


def _quadratic_residual(x: np.ndarray, y: np.ndarray, v: np.ndarray) -> float:
    """Largest misfit of the least-squares quadratic in (x, y), relative to the largest value."""
    basis = np.column_stack([np.ones_like(x), x, y, x**2, x * y, y**2])
    coef, *_ = np.linalg.lstsq(basis, v, rcond=None)
    return float(np.max(np.abs(basis @ coef - v)) / np.max(np.abs(v)))


def test_the_grid_is_the_floor_grid_of_the_scenario(floor):
    assert floor.x_m.tolist() == [float(x) for x in range(-9, 10)]
    assert floor.y_m.tolist() == [-1.2, 0.0, 1.2]
    assert floor.names[0][0] == "F0_0" and floor.names[2][18] == "F18_2"
    assert [p.name for p in floor.marked] == ["PFB", "PC", "PRB", "PLA", "PRA"]  # PR: roof


def test_rigid_vertical_variance_is_quadratic_over_the_floor(floor):
    x, y = np.meshgrid(floor.x_m, floor.y_m)
    for key in ("rms", "Wb", "Wk"):
        var = floor.values(key, "z") ** 2
        assert _quadratic_residual(x.ravel(), y.ravel(), var.ravel()) < 1e-8, key
    # pitch matters: the variance is not constant along the body
    rms = floor.values("rms", "z")
    assert rms[1].max() / rms[1].min() > 1.5


def test_rigid_lateral_response_does_not_depend_on_y(floor):
    for key in ("rms", "Wd", "sperling"):
        v = floor.values(key, "y")
        np.testing.assert_allclose(v, np.broadcast_to(v[1], v.shape), rtol=1e-9, err_msg=key)


def test_the_map_is_symmetric_left_and_right_on_straight_track(floor):
    for d, keys in (("z", ("rms", "Wb", "sperling", "sperling_filter")),
                    ("y", ("rms", "Wd", "sperling"))):
        for key in keys:
            v = floor.values(key, d)
            np.testing.assert_allclose(v, v[::-1], rtol=1e-8, err_msg=(d, key))


def test_a_grid_point_is_the_point_asked_for_by_itself(floor):
    j, i = 2, 3  # left edge, 6 m behind the centre
    x, y = float(floor.x_m[i]), float(floor.y_m[j])
    sc = preset(BASE, output__points=[{"name": "Q", "x": x, "y": y, "z": 1.10}])
    one = estimate(sc, points=["Q"]).comfort.point("Q")
    for d, keys in (("z", ("rms", "Wb", "sperling")), ("y", ("rms", "Wd", "sperling"))):
        for key in keys:
            alone = one.directions[d].iso.get(key, getattr(one.directions[d], key, None))
            assert floor.values(key, d)[j, i] == pytest.approx(alone, rel=1e-9), (d, key)
    assert floor.nmv()[j, i] == pytest.approx(one.nmv, rel=1e-9)


def test_the_estimate_of_the_other_points_is_unchanged_by_the_grid():
    with_grid = estimate(preset(BASE), points=["PC"], floor_grid_m=2.0)
    plain = estimate(preset(BASE), points=["PC"])
    a = with_grid.comfort.point("PC").directions["z"]
    b = plain.comfort.point("PC").directions["z"]
    assert a.rms == pytest.approx(b.rms, rel=1e-9)
    assert a.sperling == pytest.approx(b.sperling, rel=1e-9)
    assert [p.name for p in estimate(preset(BASE), floor_grid_m=2.0).comfort.points] == [
        "PR", "PFB", "PC", "PRB", "PLA", "PRA"]


def test_a_bad_spacing_or_a_taken_name_is_located_at_the_grid_spacing():
    with pytest.raises(ScenarioError) as err:
        floor_scenario(preset(BASE), 0.05)
    assert err.value.items[0].path == "output.floor_grid_spacing_m"
    sc = preset(BASE, output__points=[{"name": "F0_0", "x": 1.0, "y": 0.0, "z": 1.1}])
    with pytest.raises(ScenarioError) as err:
        floor_scenario(sc, 1.0)
    assert "F0_0" in str(err.value) and err.value.items[0].path == "output.floor_grid_spacing_m"

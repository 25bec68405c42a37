"""Quasi-static split on curves and running safety from wheel–rail forces."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.analysis import (
    derailment_coefficient,
    lateral_force_limit,
    running_safety,
    sperling,
    split_quasistatic,
    wheel_unloading,
    wheelset_lateral_force,
)
from flexride.errors import AnalysisError

FS = 200.0


def curve_profile(t, t_in=10.0, ramp=3.0, t_out=40.0, level=0.5):
    """Quasi-static lateral acceleration of a curve with transitions (trapezoid, m/s²)."""
    up = np.clip((t - t_in) / ramp, 0.0, 1.0)
    down = np.clip((t - t_out) / ramp, 0.0, 1.0)
    return level * (up - down)


def test_split_recovers_curve_and_vibration():
    t = np.arange(round(60 * FS)) / FS
    qs = curve_profile(t)
    vib = 0.2 * np.sin(2 * np.pi * 1.4 * t)
    split = split_quasistatic(qs + vib, FS)
    np.testing.assert_allclose(split.quasi_static + split.dynamic, qs + vib, atol=1e-12)
    plateau = (t > 16) & (t < 37)
    assert np.max(np.abs(split.quasi_static[plateau] - 0.5)) < 0.01
    assert np.max(np.abs(split.dynamic[plateau] - vib[plateau])) < 0.01
    assert split.cutoff_hz == 0.3 and "zero phase" in split.method


@pytest.mark.parametrize("form", ["spectral", "filter"])
def test_sperling_after_removal_matches_vibration_only(form):
    t = np.arange(round(60 * FS)) / FS
    vib = 0.05 * np.sin(2 * np.pi * 1.4 * t)
    curve = curve_profile(t, ramp=2.5, level=1.0)
    raw = sperling(curve + vib, FS, "y", form=form).value
    clean = sperling(vib, FS, "y", form=form).value
    dyn = sperling(split_quasistatic(curve + vib, FS).dynamic, FS, "y", form=form).value
    if form == "filter":
        assert raw > 1.05 * clean  # the curve's ramps leak into the B-weighted rms
    else:
        # the Hann-windowed spectral form keeps most of the ramps out of its band already
        assert raw >= clean
    assert dyn == pytest.approx(clean, rel=0.005)


def test_split_bad_input():
    with pytest.raises(AnalysisError, match="too short"):
        split_quasistatic(np.zeros(100), FS)
    with pytest.raises(AnalysisError, match="too low"):
        split_quasistatic(np.zeros(1000), 1.0)


SPEED = 20.0  # m/s


def test_constant_forces():
    n = round(10 * FS)
    left = derailment_coefficient(np.full(n, -30e3), np.full(n, 60e3), FS, SPEED, side="left")
    right = derailment_coefficient(np.full(n, 30e3), np.full(n, 60e3), FS, SPEED, side="right")
    both = derailment_coefficient(np.full(n, -30e3), np.full(n, 60e3), FS, SPEED)
    for r in (left, right, both):
        assert r.value == pytest.approx(0.5, rel=1e-9)
        assert r.limit == 1.2 and r.passed and r.utilisation == pytest.approx(0.5 / 1.2)
    # the lateral force pushing the left wheel outwards does not load its flange
    assert derailment_coefficient(np.full(n, 30e3), np.full(n, 60e3), FS, SPEED,
                                  side="left").value == pytest.approx(-0.5)
    wu = wheel_unloading(np.full(n, 60e3), 70e3, FS)
    assert wu.value == pytest.approx(1 / 7) and wu.limit == 0.65 and wu.passed
    ly = wheelset_lateral_force(np.full(n, -30e3), np.full(n, 10e3), 140e3, FS, SPEED)
    assert ly.value == pytest.approx(20.0) and ly.unit == "kN"
    assert ly.limit == pytest.approx(10 + 140 / 3) == lateral_force_limit(140e3)


def test_two_metre_window_averages_a_short_peak():
    """A 1 m long excursion of Y/Q to 1.5 is averaged over 2 m to 1.0: within the limit."""
    n = round(20 * FS)
    x = np.arange(n) / FS * SPEED
    q = np.where((x >= 200.0) & (x < 201.0), -90e3, -30e3)
    res = derailment_coefficient(q, np.full(n, 60e3), FS, SPEED, side="left", keep_series=True)
    assert res.value == pytest.approx(1.0, abs=0.01)
    assert res.passed and res.time_of_max == pytest.approx(200.5 / SPEED, abs=0.05)
    assert np.max(q / -60e3) == 1.5
    assert res.series is not None and np.diff(res.times)[0] == pytest.approx(0.5 / SPEED)
    assert "2 m" in res.processing and "20 Hz" in res.processing


def test_limits_exceeded():
    n = round(10 * FS)
    assert not derailment_coefficient(np.full(n, -80e3), np.full(n, 60e3), FS, SPEED,
                                      side="left").passed
    assert not wheel_unloading(np.full(n, 20e3), 70e3, FS).passed
    assert not wheelset_lateral_force(np.full(n, 40e3), np.full(n, 30e3), 140e3, FS,
                                      SPEED).passed


@pytest.mark.parametrize("meta_loads", ["nested", "flat", None])
def test_running_safety_bridge(results_factory, meta_loads):
    res = results_factory(fs=200.0, duration=10.0, wheelsets=2, meta_loads=meta_loads)
    rs = running_safety(res)
    assert len(rs.indices) == 2 * (2 * 2 + 1)
    assert rs.passed
    # P = 70 ± 2 kN at 3 Hz, Q = 10 kN: the 2 m mean (0.09 s) keeps almost 10/68
    assert rs.worst("derailment_coefficient").value == pytest.approx(10e3 / 68e3, rel=0.01)
    assert rs.worst("wheel_unloading").value == pytest.approx(2e3 / 70e3, rel=0.02)
    assert rs.worst("wheelset_lateral_force").value == pytest.approx(0.0, abs=1e-6)
    src = rs.static_wheel_loads["source"]
    assert ("meta" in src) if meta_loads else ("mean of force.z" in src)


def test_safety_bad_input():
    n = round(10 * FS)
    with pytest.raises(AnalysisError, match="too low"):
        derailment_coefficient(np.ones(400), np.ones(400), 40.0, SPEED)
    with pytest.raises(AnalysisError, match="shorter than the 2 m"):
        derailment_coefficient(np.ones(10), np.ones(10), FS, SPEED)
    with pytest.raises(AnalysisError, match="static wheel load"):
        wheel_unloading(np.ones(n), -1.0, FS)
    with pytest.raises(AnalysisError, match="differ"):
        derailment_coefficient(np.ones(n), np.ones(n + 1), FS, SPEED)
    with pytest.raises(AnalysisError, match="speed"):
        wheelset_lateral_force(np.ones(n), np.ones(n), 1e5, FS, 0.0)
    with pytest.raises(AnalysisError, match="NaN"):
        wheel_unloading(np.full(n, np.nan), 7e4, FS)


@pytest.mark.parametrize(("angle_deg", "mu", "expected"), [
    (70.0, 0.36, 1.2003),   # (tan 70° − 0.36)/(1 + 0.36 tan 70°): the classical 1.2
    (60.0, 0.30, 0.9424),
    (70.0, 0.00, 2.7475),   # no friction: tan γ
])
def test_nadal_limit_by_hand(angle_deg, mu, expected):
    from flexride.analysis.safety import nadal_limit

    assert nadal_limit(np.radians(angle_deg), mu) == pytest.approx(expected, abs=1e-4)


def test_nadal_limit_refuses_impossible_angles():
    from flexride.analysis.safety import nadal_limit

    for angle, mu in ((0.0, 0.3), (np.pi / 2, 0.3), (1.2, -0.1)):
        with pytest.raises(AnalysisError, match="Nadal"):
            nadal_limit(angle, mu)


def test_running_safety_against_nadal_with_a_flange_angle(results_factory):
    res = results_factory(fs=200.0, duration=10.0, wheelsets=2, meta_loads="nested")
    assert running_safety(res).nadal is None  # conical tread: no flange angle
    res.meta.update(flange_angle_rad=float(np.radians(70.0)), friction=0.36)
    nadal = running_safety(res).nadal
    assert nadal["limit"] == pytest.approx(1.2003, abs=1e-4)
    assert nadal["worst"] == pytest.approx(10e3 / 68e3, rel=0.01) and nadal["passed"]
    assert nadal["utilisation"] == pytest.approx(nadal["worst"] / nadal["limit"])

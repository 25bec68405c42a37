"""Excitations to one profile: measured CSV files (mapping to the rails, errors) and the sum of
a scenario's excitations (grid step, fade-in of the random part)."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.errors import ScenarioError
from flexride.scenario.excitation import (
    Corrugation,
    MeasuredIrregularity,
    RandomIrregularity,
    Settlement,
)
from flexride.track.defects import corrugation_profile, settlement_profile
from flexride.track.excitation import build_profile, measured_profile
from flexride.track.spectra import random_profile

# --------------------------------------------------------------------------- measured CSV


def _write(path, text):
    path.write_text(text, encoding="utf-8")
    return path


def test_measured_round_trip_per_rail(tmp_path):
    ref = random_profile(200.0, seed=9, ds=0.25)
    rows = ["distance_m,z_left,z_right,y_left,y_right,speed_kmh"]
    rows += [
        f"{float(s)!r},{float(a)!r},{float(b)!r},{float(c)!r},{float(d)!r},80"
        for s, a, b, c, d in zip(
            ref.s, ref.z_left, ref.z_right, ref.y_left, ref.y_right, strict=True
        )
    ]
    path = _write(tmp_path / "rec.csv", "# recorded 2024\n" + "\n".join(rows) + "\n")
    p = measured_profile(path)
    assert p.s0 == 0.0 and p.ds == pytest.approx(0.25) and p.n == ref.n
    for key in ("z_left", "z_right", "y_left", "y_right"):
        np.testing.assert_allclose(getattr(p, key), getattr(ref, key), rtol=0, atol=1e-15)
    half = measured_profile(str(path), scale=0.5)
    np.testing.assert_allclose(half.z_left, 0.5 * ref.z_left, rtol=1e-12, atol=1e-18)


def test_measured_component_columns(tmp_path):
    path = _write(
        tmp_path / "comp.csv",
        "s,vertical,alignment,cross_level,gauge\n"
        "10.0,0.001,0.002,0.004,0.006\n"
        "11.0,0.003,-0.002,0.0,-0.002\n"
        "12.0,0.0,0.0,0.0,0.0\n",
    )
    p = measured_profile(path, distance_column="s")
    assert p.s0 == 10.0 and p.ds == 1.0
    # cross_level = z_L − z_R, gauge = y_L − y_R (widening positive)
    np.testing.assert_allclose(p.z_left, [0.003, 0.003, 0.0])
    np.testing.assert_allclose(p.z_right, [-0.001, 0.003, 0.0])
    np.testing.assert_allclose(p.y_left, [0.005, -0.003, 0.0])
    np.testing.assert_allclose(p.y_right, [-0.001, -0.001, 0.0])
    zl, _, _, _ = p.sample([9.0, 10.5, 13.0])
    np.testing.assert_allclose(zl, [0.0, 0.003, 0.0])


@pytest.mark.parametrize(
    ("text", "needles"),
    [
        ("", ["empty"]),
        ("# only a comment\n\n", ["empty"]),
        ("s,vertical\n0,0\n1,0\n", ["line 1", "distance_m", "missing"]),
        ("distance_m,speed\n0,1\n1,2\n", ["line 1", "no irregularity column"]),
        ("distance_m,vertical\n0,0.001\n1,abc\n2,0\n", ["line 3", "'vertical'", "not a number"]),
        ("distance_m,vertical\n0,0.001\n1,\n2,0\n", ["line 3", "'vertical'", "empty"]),
        ("distance_m,vertical\n0,0.001\n1,nan\n2,0\n", ["line 3", "'vertical'", "finite"]),
        ("distance_m,vertical\n0,0\n2,0\n1,0\n", ["line 4", "'distance_m'", "increasing"]),
        ("distance_m,vertical\n0,0\n1,0\n1,0\n", ["line 4", "increasing"]),
        ("distance_m,vertical\n0,0\n1,0,5\n", ["line 3", "cells"]),
        ("distance_m,vertical\n0,0\n", ["two data rows"]),
        ("distance_m,vertical,vertical\n0,0,0\n1,0,0\n", ["duplicate", "vertical"]),
    ],
)
def test_measured_malformed_files_raise_scenario_error(tmp_path, text, needles):
    path = _write(tmp_path / "bad_track.csv", text)
    with pytest.raises(ScenarioError) as info:
        measured_profile(path)
    msg = str(info.value)
    assert "bad_track.csv" in msg
    assert str(tmp_path) not in msg and "abc" not in msg  # no directory, no cell text
    for needle in needles:
        assert needle in msg, (needle, msg)


def test_measured_missing_file(tmp_path):
    with pytest.raises(ScenarioError, match=r"nope\.csv"):
        measured_profile(tmp_path / "nope.csv")


# --------------------------------------------------------------------------- build_profile


def test_build_profile_empty_is_flat():
    p = build_profile([], 100.0)
    assert p.ds == 0.05 and p.n == 2001 and p.s0 == 0.0
    assert not any(getattr(p, k).any() for k in ("z_left", "z_right", "y_left", "y_right"))


def test_build_profile_sums_and_picks_ds(tmp_path):
    csv_path = _write(tmp_path / "m.csv", "distance_m,z_left\n0,0\n100,0.002\n200,0.002\n300,0\n")
    excs = [
        RandomIrregularity(seed=4),
        Settlement(),
        Corrugation(start_m=150.0, length_m=10.0),
        MeasuredIrregularity(path=str(csv_path), scale=2.0),
    ]
    p = build_profile(excs, 250.0)
    assert p.ds == pytest.approx(0.025)  # corrugation 0.5 m / 20
    assert p.n == 10_001
    expected = (
        random_profile(250.0, "high", seed=4, ds=p.ds)
        + settlement_profile(250.0, ds=p.ds)
        + corrugation_profile(250.0, 0.5, 0.001, 150.0, 10.0, ds=p.ds)
    )
    meas = 2.0 * np.interp(p.s, [0, 100, 200, 300], [0, 0.002, 0.002, 0])
    np.testing.assert_allclose(p.z_left, expected.z_left + meas, rtol=0, atol=1e-15)
    np.testing.assert_allclose(p.z_right, expected.z_right, rtol=0, atol=1e-15)
    np.testing.assert_allclose(p.y_left, expected.y_left, rtol=0, atol=1e-15)
    # settlement alone needs nothing finer than the default step
    assert build_profile([Settlement()], 100.0).ds == 0.05
    # random with a short band asks for λ_min/20
    assert build_profile([RandomIrregularity(wavelength_min_m=0.5)], 50.0).ds == 0.025
    # explicit step is used as given
    assert build_profile([Settlement()], 100.0, ds=0.2).ds == 0.2


def test_build_profile_bad_measured_file_propagates(tmp_path):
    bad = _write(tmp_path / "broken.csv", "distance_m,vertical\n0,x\n1,0\n")
    with pytest.raises(ScenarioError, match=r"broken\.csv"):
        build_profile([MeasuredIrregularity(path=str(bad))], 10.0)


def test_build_profile_random_part_fades_in():
    p = build_profile([RandomIrregularity(seed=8)], 100.0)
    plain = random_profile(100.0, seed=8, ds=p.ds, fade_in_m=0.0)
    s = p.s
    w = np.where(s < 20.0, 0.5 * (1.0 - np.cos(np.pi * s / 20.0)), 1.0)
    np.testing.assert_allclose(p.z_left, w * plain.z_left, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(p.y_right, w * plain.y_right, rtol=1e-12, atol=1e-18)
    assert p.z_left[0] == 0.0 and p.y_left[0] == 0.0

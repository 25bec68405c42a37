"""Local defects: settlement and corrugation (one cosine-dip shape) against the closed form."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.errors import ScenarioError
from flexride.scenario.excitation import Corrugation
from flexride.track.defects import corrugation_profile, settlement_profile
from flexride.track.excitation import build_profile

# --------------------------------------------------------------------------- local defects


def test_settlement_depth_and_wavelength_exact():
    depth, lam, s0 = 0.1, 20.0, 50.0
    p = settlement_profile(200.0, lam, depth, s0, ds=0.05)
    s = p.s
    assert p.z_left.min() == pytest.approx(-depth, rel=1e-12)
    assert s[np.argmin(p.z_left)] == pytest.approx(s0 + lam / 2, abs=1e-9)
    outside = (s < s0 - 1e-9) | (s > s0 + lam + 1e-9)
    assert np.all(p.z_left[outside] == 0.0)
    assert np.all(p.z_left[~outside][1:-1] < 0.0)  # the dip spans exactly λ
    i_quarter = np.argmin(np.abs(s - (s0 + lam / 4)))
    assert p.z_left[i_quarter] == pytest.approx(-depth / 2, rel=1e-9)
    np.testing.assert_array_equal(p.z_left, p.z_right)
    assert not p.y_left.any() and not p.y_right.any()
    # between grid points: the closed form within the linear-interpolation error
    sq = np.random.default_rng(0).uniform(0, 200, 1000)
    ref = np.where(
        (sq >= s0) & (sq <= s0 + lam),
        -depth / 2 * (1 - np.cos(2 * np.pi * (sq - s0) / lam)),
        0.0,
    )
    zl, _, _, _ = p.sample(sq)
    np.testing.assert_allclose(zl, ref, atol=depth * (np.pi * 0.05 / lam) ** 2)


def test_settlement_one_rail():
    p = settlement_profile(100.0, 10.0, 0.02, 30.0, rails="right")
    assert not p.z_left.any()
    assert p.z_right.min() == pytest.approx(-0.02)


def test_corrugation_depth_and_wavelength():
    lam, depth = 0.5, 0.001
    p = corrugation_profile(100.0, lam, depth, ds=0.025)
    z = p.z_left
    assert z.max() - z.min() == pytest.approx(depth, rel=1e-12)
    assert z.max() == pytest.approx(0.0, abs=1e-18)
    # FFT peak over a whole number of wavelengths
    seg = z[: round(80 * lam / p.ds)]
    spec = np.abs(np.fft.rfft(seg - seg.mean()))
    f = np.fft.rfftfreq(seg.size, d=p.ds)
    assert f[np.argmax(spec)] == pytest.approx(1 / lam, rel=1e-9)
    np.testing.assert_array_equal(p.z_left, p.z_right)
    assert not p.y_left.any()


def test_corrugation_stretch_and_rails():
    p = corrugation_profile(
        100.0, 0.5, 0.001, start_m=10.0, corrugated_length_m=20.3, rails="left", ds=0.025
    )
    s = p.s
    nz = s[p.z_left != 0.0]
    assert nz.min() > 10.0 and nz.max() < 30.0 + 1e-9  # rounded down to 40 whole waves
    assert nz.max() > 29.9
    assert not p.z_right.any()
    # default grid: λ/20; a grid that cannot carry the wave is refused
    assert corrugation_profile(10.0, 0.3).ds == pytest.approx(0.015)
    with pytest.raises(ScenarioError, match="too coarse"):
        corrugation_profile(10.0, 0.3, ds=0.2)
    with pytest.raises(ScenarioError, match="too coarse"):
        build_profile([Corrugation()], 10.0, ds=0.3)




def test_settlement_is_one_wavelength_of_corrugation():
    # one shape: a settlement is a corrugated stretch of exactly one wavelength
    lam, depth, s0 = 12.0, 0.03, 17.0
    for rails in ("both", "left", "right"):
        a = settlement_profile(80.0, lam, depth, s0, rails=rails, ds=0.05)
        b = corrugation_profile(80.0, lam, depth, s0, corrugated_length_m=lam, rails=rails,
                                ds=0.05)
        for key in ("z_left", "z_right", "y_left", "y_right"):
            np.testing.assert_array_equal(getattr(a, key), getattr(b, key))
    with pytest.raises(ScenarioError, match="settlement wavelength"):
        settlement_profile(10.0, 0.0)
    with pytest.raises(ScenarioError, match="corrugation wavelength"):
        corrugation_profile(10.0, -0.5)
    with pytest.raises(ScenarioError, match="rails"):
        settlement_profile(100.0, rails="middle")

"""Track irregularities: spectra, random synthesis, local defects, measured CSV, combination.

The oracles are independent of the code under test: the German spectra are written out again
here from DESIGN §6, integrated with scipy quad, and the spectra of generated profiles are
estimated with scipy.signal.welch directly. Rail → component mapping used to check (b = 0.75 m):
vertical = (z_L + z_R)/2, cross-level angle = (z_L − z_R)/(2b), alignment = (y_L + y_R)/2,
gauge = y_L − y_R.
"""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from scipy import integrate, signal

from flexride.errors import ScenarioError
from flexride.model.excitation import (
    Corrugation,
    MeasuredIrregularity,
    RandomIrregularity,
    Settlement,
)
from flexride.track.irregularities import (
    IrregularityProfile,
    band_rms,
    build_profile,
    corrugation_profile,
    german_psd,
    measured_profile,
    random_profile,
    settlement_profile,
    spatial_psd,
)

B = 0.75
COMPONENTS = ("vertical", "alignment", "cross_level", "gauge")
# DESIGN §6, written out independently
WC, WR, WS = 0.8246, 0.0206, 0.4380
A = {
    "high": {"v": 1.080e-6, "a": 6.125e-7, "g": 1.032e-7},
    "low": {"v": 4.032e-7, "a": 2.119e-7, "g": 5.32e-8},
}


def target_psd(om, component, level="high"):
    """One-sided German spectrum, m²/(rad/m); cross level as the angle, rad²/(rad/m)."""
    om = np.asarray(om, dtype=float)
    a = A[level]
    den2 = (om**2 + WR**2) * (om**2 + WC**2)
    den3 = den2 * (om**2 + WS**2)
    if component == "vertical":
        return a["v"] * WC**2 / den2
    if component == "alignment":
        return a["a"] * WC**2 / den2
    if component == "cross_level":
        return (a["v"] / B**2) * WC**2 * om**2 / den3
    if component == "gauge":
        return a["g"] * WC**2 * om**2 / den3
    raise AssertionError(component)


def target_variance(component, lam_min, lam_max, level="high"):
    val, _ = integrate.quad(
        lambda w: float(target_psd(w, component, level)),
        2 * math.pi / lam_max,
        2 * math.pi / lam_min,
        limit=200,
        epsabs=0.0,  # variances are ~1e-5 m² or less: the default epsabs is too loose
        epsrel=1e-10,
    )
    return val


def components_of(p: IrregularityProfile) -> dict[str, np.ndarray]:
    return {
        "vertical": 0.5 * (p.z_left + p.z_right),
        "alignment": 0.5 * (p.y_left + p.y_right),
        "cross_level": (p.z_left - p.z_right) / (2 * B),
        "gauge": p.y_left - p.y_right,
    }


# --------------------------------------------------------------------------- spectra


@pytest.mark.parametrize("level", ["high", "low", "german-high"])
@pytest.mark.parametrize("component", COMPONENTS)
def test_german_psd_matches_design_formulas(component, level):
    om = np.geomspace(1e-3, 20.0, 50)
    expected = target_psd(om, component, level.removeprefix("german-"))
    np.testing.assert_allclose(german_psd(om, component, level), expected, rtol=1e-13)


def test_german_psd_short_wave_cross_level_is_four_times_vertical_as_height():
    # Δz = 2b·angle: at Ω ≫ Ω_s the rail height difference has 4× the vertical spectrum
    om = np.array([30.0, 60.0])
    ratio = 4 * B**2 * german_psd(om, "cross_level") / german_psd(om, "vertical")
    np.testing.assert_allclose(ratio, 4.0 / (1.0 + WS**2 / om**2), rtol=1e-12)
    assert np.all(ratio > 3.99)


def test_german_psd_rejects_bad_input():
    with pytest.raises(ScenarioError, match="component"):
        german_psd(1.0, "twist")
    with pytest.raises(ScenarioError, match="level"):
        german_psd(1.0, "vertical", "medium")
    with pytest.raises(ScenarioError, match=">= 0"):
        german_psd(np.array([-1.0, 1.0]), "vertical")


@pytest.mark.parametrize("component", COMPONENTS)
def test_band_rms_against_independent_integral(component):
    for lam_min, lam_max in [(1.0, 120.0), (3.0, 25.0), (0.5, 300.0)]:
        expected = math.sqrt(target_variance(component, lam_min, lam_max, "low"))
        assert band_rms("german-low", component, lam_min, lam_max) == pytest.approx(
            expected, rel=1e-8
        )
    with pytest.raises(ScenarioError):
        band_rms("high", component, 10.0, 5.0)


def test_spatial_psd_units_on_a_sine_and_white_noise():
    ds = 0.1
    s = np.arange(2**16) * ds
    amp, lam = 0.002, 8.0
    om, psd = spatial_psd(amp * np.sin(2 * np.pi * s / lam), ds, nperseg=4096)
    d_om = om[1] - om[0]
    assert d_om == pytest.approx(2 * np.pi / (4096 * ds))
    assert psd.sum() * d_om == pytest.approx(amp**2 / 2, rel=0.02)  # variance
    assert om[np.argmax(psd)] == pytest.approx(2 * np.pi / lam, abs=d_om)
    # white noise of variance σ² over 0..π/ds rad/m: level σ²·ds/π
    x = np.random.default_rng(3).normal(0.0, 0.01, 2**16)
    om, psd = spatial_psd(x, ds)
    assert np.mean(psd[1:-1]) == pytest.approx(1e-4 * ds / np.pi, rel=0.05)


# --------------------------------------------------------------------------- random synthesis

N_SEEDS = 16
LENGTH = 5000.0


@pytest.fixture(scope="module")
def ensemble() -> list[dict[str, np.ndarray]]:
    return [
        components_of(random_profile(LENGTH, "german-high", seed=seed)) for seed in range(N_SEEDS)
    ]


OCTAVES = [(0.075, 0.15), (0.15, 0.3), (0.3, 0.6), (0.6, 1.2), (1.2, 2.4), (2.4, 4.8)]


@pytest.mark.parametrize("component", COMPONENTS)
def test_generated_psd_matches_target_in_octave_bands(ensemble, component):
    ds = 1.0 / 20.0  # default: λ_min/20
    estimates = []
    for member in ensemble:
        f, g = signal.welch(member[component], fs=1 / ds, nperseg=8192)
        estimates.append(g)
    om = 2 * np.pi * f
    psd = np.mean(estimates, axis=0) / (2 * np.pi)  # m²/(cycle/m) → m²/(rad/m)
    target = target_psd(om, component)
    for lo, hi in OCTAVES:
        sel = (om >= lo) & (om < hi)
        assert sel.sum() >= 5
        ratio = psd[sel].mean() / target[sel].mean()
        assert abs(ratio - 1) < 0.10, (component, lo, hi, ratio)


def test_band_edges_are_hard(ensemble):
    # nothing outside 2π/120 … 2π/1 rad/m (up to window leakage)
    f, g = signal.welch(ensemble[0]["vertical"], fs=20.0, nperseg=8192)
    om = 2 * np.pi * f
    inside = g[(om > 1.0) & (om < 6.0)].min()
    assert g[om > 7.0].max() < 1e-3 * inside


@pytest.mark.parametrize("component", COMPONENTS)
def test_ensemble_variance_matches_band_integral(component):
    # a coarser grid (λ_min/4) keeps this cheap; sampling does not change the variance
    var = [
        np.var(components_of(random_profile(10_000.0, "high", seed=s, ds=0.25))[component])
        for s in range(100, 148)
    ]
    rms = math.sqrt(np.mean(var))
    assert rms == pytest.approx(math.sqrt(target_variance(component, 1.0, 120.0)), rel=0.03)


def test_zero_mean(ensemble):
    for member in ensemble:
        for comp, x in member.items():
            assert abs(x.mean()) < 0.05 * x.std(), comp


def test_reproducible_by_seed_and_independent_across_seeds():
    a = random_profile(800.0, seed=5)
    b = random_profile(800.0, seed=5)
    c = random_profile(800.0, seed=6)
    for key in ("z_left", "z_right", "y_left", "y_right"):
        np.testing.assert_array_equal(getattr(a, key), getattr(b, key))
        assert not np.array_equal(getattr(a, key), getattr(c, key))
    # longer route so the correlation estimate is tight
    a = components_of(random_profile(20_000.0, seed=11, ds=0.25))
    c = components_of(random_profile(20_000.0, seed=12, ds=0.25))
    for comp in COMPONENTS:
        assert abs(np.corrcoef(a[comp], c[comp])[0, 1]) < 0.1, comp
        for other in COMPONENTS:
            if other != comp:
                assert abs(np.corrcoef(a[comp], a[other])[0, 1]) < 0.1, (comp, other)


def test_components_have_their_own_streams_and_map_to_rails():
    full = random_profile(1000.0, seed=3)
    fc = components_of(full)
    vert = random_profile(1000.0, seed=3, components=["vertical"])
    np.testing.assert_allclose(vert.z_left, fc["vertical"], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(vert.z_left, vert.z_right)
    assert not vert.y_left.any() and not vert.y_right.any()
    cl = random_profile(1000.0, seed=3, components=["cross_level"])
    np.testing.assert_array_equal(cl.z_left, -cl.z_right)
    np.testing.assert_allclose(cl.z_left / B, fc["cross_level"], rtol=0, atol=1e-15)
    ga = random_profile(1000.0, seed=3, components=["gauge"])
    np.testing.assert_array_equal(ga.y_left, -ga.y_right)  # widening: left +y, right −y
    np.testing.assert_allclose(2 * ga.y_left, fc["gauge"], rtol=0, atol=1e-15)
    al = random_profile(1000.0, seed=3, components=["alignment"])
    np.testing.assert_array_equal(al.y_left, al.y_right)


def test_scale_and_level():
    a = random_profile(500.0, seed=2)
    b = random_profile(500.0, seed=2, scale=2.5)
    np.testing.assert_allclose(b.z_left, 2.5 * a.z_left, rtol=1e-12, atol=1e-15)
    lo = random_profile(500.0, "low", seed=2, components=["vertical"])
    hi = random_profile(500.0, "high", seed=2, components=["vertical"])
    assert lo.z_left.std() < hi.z_left.std()


def test_grid_and_validation():
    p = random_profile(100.0, wavelength_min_m=2.0, wavelength_max_m=50.0)
    assert p.s0 == 0.0 and p.ds == pytest.approx(0.1)
    assert p.s_end >= 100.0 and p.n == 1001
    with pytest.raises(ScenarioError, match="too coarse"):
        random_profile(100.0, ds=0.6)
    with pytest.raises(ScenarioError):
        random_profile(100.0, wavelength_min_m=10.0, wavelength_max_m=5.0)
    with pytest.raises(ScenarioError, match="component"):
        random_profile(100.0, components=["twist"])


def test_five_km_at_fine_step_is_fast():
    random_profile(100.0, ds=0.025)  # warm-up
    t0 = time.perf_counter()
    p = random_profile(5000.0, ds=0.025)
    elapsed = time.perf_counter() - t0
    assert p.n == 200_001
    assert elapsed < 0.5


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


# --------------------------------------------------------------------------- profile object


def test_profile_sample_and_add():
    a = IrregularityProfile(0.0, 0.5, *(np.arange(5.0) * k for k in (1, 2, 3, 4)))
    zl, _, _, yr = a.sample([0.25, 1.0, 1.75, 2.0, -0.1, 2.1])
    np.testing.assert_allclose(zl, [0.5, 2.0, 3.5, 4.0, 0.0, 0.0])
    np.testing.assert_allclose(yr, 4 * np.array([0.5, 2.0, 3.5, 4.0, 0.0, 0.0]))
    b = IrregularityProfile(1.0, 0.25, *(np.ones(9) for _ in range(4)))  # 1.0 … 3.0
    c = a + b
    assert c.s0 == 0.0 and c.ds == 0.25 and c.s_end == pytest.approx(3.0)
    zl, _, _, _ = c.sample(np.array([0.5, 1.0, 1.25, 2.0, 2.5, 3.0]))
    np.testing.assert_allclose(zl, [1.0, 3.0, 3.5, 5.0, 1.0, 1.0])
    same = a + a
    np.testing.assert_array_equal(same.z_left, 2 * a.z_left)
    total = sum([a, a, a])
    np.testing.assert_array_equal(total.y_left, 3 * a.y_left)
    with pytest.raises(ValueError):
        IrregularityProfile(0.0, 0.1, np.zeros(3), np.zeros(3), np.zeros(2), np.zeros(3))
    with pytest.raises(ValueError):
        IrregularityProfile(0.0, 0.0, *(np.zeros(3) for _ in range(4)))


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

"""German spectra and random synthesis: spectra, band rms, Welch estimate, generated profiles,
fade-in.

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
from scipy import fft as sp_fft
from scipy import integrate, signal

from flexride.errors import ScenarioError
from flexride.track.profile import IrregularityProfile
from flexride.track.spectra import (
    band_rms,
    german_psd,
    next_fast_len,
    random_profile,
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




def test_random_profile_fades_in_over_20_m():
    # raised cosine from 0 at s = 0 to 1 at s = 20 m, then the stationary realisation unchanged
    faded = random_profile(200.0, seed=7)
    plain = random_profile(200.0, seed=7, fade_in_m=0.0)
    s = plain.s
    w = np.where(s < 20.0, 0.5 * (1.0 - np.cos(np.pi * s / 20.0)), 1.0)
    for key in ("z_left", "z_right", "y_left", "y_right"):
        a, b = getattr(faded, key), getattr(plain, key)
        np.testing.assert_allclose(a, w * b, rtol=1e-12, atol=1e-18)
        assert a[0] == 0.0
        np.testing.assert_array_equal(a[s >= 20.0], b[s >= 20.0])
    shorter = random_profile(200.0, seed=7, fade_in_m=5.0)
    np.testing.assert_array_equal(shorter.z_left[s >= 5.0], plain.z_left[s >= 5.0])
    with pytest.raises(ScenarioError, match="fade_in_m"):
        random_profile(100.0, fade_in_m=-1.0)


def test_fast_fft_length_is_scipys():
    """The synthesis length is SciPy's next fast length for real transforms (5-smooth), the
    oracle, for every length up to 2·10⁵ and at a few large ones."""
    lengths = [*range(1, 200_001), 999_983, 1_048_577, 4_782_969 + 1, 9_765_626]
    assert [next_fast_len(n) for n in lengths] == [
        sp_fft.next_fast_len(n, real=True) for n in lengths]

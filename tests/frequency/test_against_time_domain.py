"""The frequency-domain estimate against the time-domain solver, random straight track at 80
and 50 km/h, rigid bodies, conical tread.

The comparison needs a contact geometry that is linear in the wheelset's displacement: the
conical tread (``CONICAL``). The presets' S1002/60E1 pair jumps between contact points at
0.2–0.5 mm, so a linearisation about the centred wheelset (local conicity 0.11) is not what a
wheelset oscillating by millimetres sees (equivalent conicity 0.18–0.36); how far the estimate
is then from the solver is measured in docs/analysis.md.

Two links, each with its own oracle:

1. **linear model vs the nonlinear solver, same realisation.** The time-domain run and the
   linear model (FFT of the same rail profile through the model's FRFs,
   :func:`~flexride.frequency.linear_time_history`) see the same irregularities, so their
   difference is nonlinearity and the frozen rail window only, not statistics: rms, ISO
   weighted rms, Sperling and one-third-octave band powers are compared record to record.
   The runs here have the flangeway clearance widened to 30 mm: with the preset's 8 mm the
   wheelsets touch the flange 1–2.4 % of the time (σ of the wheel–rail lateral displacement
   3 mm), which the linear model cannot represent and flags; that costs the lateral response
   2–4 % (Wd-weighted 5 %, see docs/analysis.md) and leaves the vertical one unchanged.
2. **the spectral estimate vs long records of the linear model.** The expectations computed
   from the PSDs (:func:`~flexride.frequency.comfort`) against the same indices of the linear
   model's response to a 30 km realisation of the German spectrum (long enough that the
   statistical scatter is a few percent), computed with :mod:`flexride.analysis`.

An 18 s run is too short for a direct statistical comparison (its rms scatters by ±10 %
around the expectation; the numbers are in docs/analysis.md).

3. **real profiles, quasi-linear estimate vs long solver records.** With the presets'
   S1002/60E1 the contact is linearised statistically (:mod:`flexride.frequency.quasilinear`)
   and the estimate's expectations are compared with the solver's indices over 10 km
   (7.5 min at 80 km/h, 12 min at 50 km/h; the rms of a 10 km record scatters by 2–3 %).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from conftest import CONICAL, preset
from flexride.analysis import apply_weighting, sperling, split_quasistatic, welch_psd
from flexride.frequency import comfort, estimate, linear_model, linear_time_history, response
from flexride.frequency.indices import dynamic_part_gain
from flexride.solver.assemble import assemble
from flexride.solver.simulate import simulate
from flexride.track.spectra import random_profile

pytestmark = pytest.mark.slow

SKIP_S = 3.0  # start of the run: the linear model starts from rest, the solver from statics
POINTS = ("PR", "PFB", "PC", "PRB", "PLA", "PRA")


def third_octave_bands(f_lo: float = 0.5, f_hi: float = 20.0) -> list[tuple[float, float]]:
    """(lower, upper) edges of the base-10 one-third-octave bands with centres in the range."""
    ks = range(round(10 * np.log10(f_lo)), round(10 * np.log10(f_hi)) + 1)
    return [(10 ** (k / 10 - 0.05), 10 ** (k / 10 + 0.05)) for k in ks]


def band_powers(f: np.ndarray, psd: np.ndarray, bands) -> np.ndarray:
    """∫ PSD over each band, exact band edges (trapezoidal cumulative integral, interpolated;
    summing whole bins would misplace up to a bin at each edge: ±14 % in a 0.5 Hz band of
    1/64 Hz bins)."""
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (psd[1:] + psd[:-1]) * np.diff(f))])
    return np.array([np.interp(hi, f, cum) - np.interp(lo, f, cum) for lo, hi in bands])


@pytest.fixture(scope="module", params=[80, 50])
def case(request):
    sc = preset(f"paper-random-straight-{request.param}", **CONICAL,
                contact__flange_clearance=0.03)
    res = simulate(sc)
    model = linear_model(sc)
    lin = linear_time_history(model, assemble(sc).irregularity, res.time)
    return sc, res, model, lin


def _records(res, lin, ch):
    skip = int(SKIP_S * res.sample_rate)
    return res.channels[ch][skip:], lin[ch][skip:]


@pytest.mark.parametrize("point", POINTS)
def test_same_realisation_rms_iso_and_sperling(case, point):
    _sc, res, _model, lin = case
    fs = res.sample_rate
    for d, weighting in (("z", "Wb"), ("y", "Wd")):
        td, ln = _records(res, lin, f"carbody.{point}.acc.{d}")
        assert np.std(ln) == pytest.approx(np.std(td), rel=0.05), d
        aw = [np.std(apply_weighting(x, fs, weighting)) for x in (td, ln)]
        assert aw[1] == pytest.approx(aw[0], rel=0.05), d
        w = [sperling(x, fs, d).value for x in (td, ln)]
        assert w[1] == pytest.approx(w[0], rel=0.03), d


@pytest.mark.parametrize("point", ["PR", "PC", "PLA"])
def test_same_realisation_third_octaves(case, point):
    """Bands of 0.5–20 Hz inside the excitation band (f ≤ V/λ_min) within ±15 %."""
    sc, res, _model, lin = case
    fs = res.sample_rate
    f_max = sc.speed_mps / sc.excitation[0].wavelength_min_m
    bands = [b for b in third_octave_bands() if b[1] <= f_max]
    for d in ("z", "y"):
        td, ln = _records(res, lin, f"carbody.{point}.acc.{d}")
        p = [band_powers(*signal.welch(x, fs=fs, nperseg=int(5 * fs)), bands)
             for x in (td, ln)]
        np.testing.assert_allclose(p[1], p[0], rtol=0.15, err_msg=d)


@pytest.fixture(scope="module")
def long_record(case):
    """The linear model over a 30 km realisation, at 256 Hz (ISO weightings need ≥ 250 Hz)."""
    sc, _res, model, _lin = case
    exc = sc.excitation[0]
    prof = random_profile(30_000.0, "high", exc.components, exc.wavelength_min_m,
                          exc.wavelength_max_m, seed=11, ds=0.05)
    fs = 256.0
    t = np.arange(int((30_000.0 - 500.0) / model.speed * fs)) / fs
    rec = linear_time_history(model, prof, t)
    skip = int(10 * fs)
    return model, fs, {k: v[skip:] for k, v in rec.items()}


def test_expectations_against_a_long_record(long_record):
    model, fs, rec = long_record
    table = comfort(response(model))
    for p in POINTS:
        for d, weighting in (("z", "Wb"), ("y", "Wd")):
            x = rec[f"carbody.{p}.acc.{d}"]
            est = table.point(p).directions[d]
            assert est.rms == pytest.approx(np.std(x), rel=0.05), (p, d)
            aw = np.std(apply_weighting(x, fs, weighting))
            assert est.iso[weighting] == pytest.approx(aw, rel=0.05), (p, d)
            assert est.sperling == pytest.approx(sperling(x, fs, d).value, rel=0.03), (p, d)
            assert est.sperling_filter == pytest.approx(
                sperling(x, fs, d, form="filter").value, rel=0.03), (p, d)


def test_expected_third_octaves_against_a_long_record(long_record):
    """Band powers within ±15 %, or within three standard deviations of a band power measured
    over T seconds (1/√(B·T) for a band of width B: 8 % at 0.5 Hz over 22 min) where that is
    larger — below about 1.2 Hz."""
    model, fs, rec = long_record
    f = np.arange(0.05, 40.0, 0.005)
    resp = response(model, frequencies=f)
    f_max = model.speed / model.scenario.excitation[0].wavelength_min_m
    bands = [b for b in third_octave_bands() if b[1] <= f_max]
    duration = next(iter(rec.values())).size / fs
    tol = np.array([max(0.15, 3.0 / np.sqrt((hi - lo) * duration)) for lo, hi in bands])
    for p in ("PR", "PC", "PLA"):
        for d in ("z", "y"):
            ch = f"carbody.{p}.acc.{d}"
            est = band_powers(f, resp.psd[resp.index(ch)], bands)
            meas = band_powers(*signal.welch(rec[ch], fs=fs, nperseg=int(64 * fs)), bands)
            assert np.all(np.abs(meas / est - 1.0) <= tol), (ch, (meas / est).round(3))


def test_the_overlay_on_a_jobs_welch_psd_compares_like_with_like(long_record):
    """What the job view overlays (the estimate's PSD times the quasi-static split's gain,
    ``dynamic_part_gain`` of POST /estimates with ``spectra``) against what it is drawn over
    (the job's Welch PSD as GET /jobs/{id}/psd computes it: the dynamic part of the record,
    :func:`~flexride.analysis.welch_psd` with its 8 s segments): band rms over 0.5–20 Hz within
    5 %, the rms tolerance above (the band power of 20 Hz over 22 min scatters by 0.6 %)."""
    model, fs, rec = long_record
    resp = response(model)
    f = resp.frequencies
    for p in ("PR", "PC", "PLA"):
        for d in ("z", "y"):
            ch = f"carbody.{p}.acc.{d}"
            est = band_powers(f, resp.psd[resp.index(ch)] * dynamic_part_gain(f),
                              [(0.5, 20.0)])
            welch = welch_psd(split_quasistatic(rec[ch], fs).dynamic, fs, segment_s=8.0)
            meas = band_powers(welch.frequencies, welch.values, [(0.5, 20.0)])
            assert np.sqrt(est[0]) == pytest.approx(np.sqrt(meas[0]), rel=0.05), ch


def test_the_conical_case_flags_flange_contact():
    """With the cone's 8 mm clearance the estimate says that flange contact is likely."""
    table = comfort(response(linear_model(preset("paper-random-straight-80", **CONICAL))))
    assert any("flange contact likely" in f for f in table.flags)


#: Length of the solver's records with real profiles (m).
PROFILE_RECORD_M = 10_000.0
#: Skipped at their start (s): the solver starts from statics and the profile fades in.
PROFILE_SKIP_S = 10.0


@pytest.fixture(scope="module", params=[80, 50])
def profile_record(request):
    """The solver over 10 km of ``paper-random-straight-{80,50}`` with its S1002/60E1
    profiles (rigid bodies), and the default (quasi-linear) estimate of the same scenario; the
    record's ``input`` is the four rail irregularities (z left, z right, y left, y right) under
    the leading wheelset."""
    sc = preset(f"paper-random-straight-{request.param}", distance_m=PROFILE_RECORD_M,
                duration_s=None)
    res = simulate(sc)
    skip = int(PROFILE_SKIP_S * res.sample_rate)
    est = estimate(sc)
    rec = {k: v[skip:] for k, v in res.channels.items()}
    lead = float(np.max(est.model.wheelset_x))
    rec["input"] = np.array(assemble(sc).irregularity.sample(np.asarray(res.distance)[skip:]
                                                             + lead))
    return sc, res.sample_rate, rec, est


@pytest.mark.parametrize("point, rel", [("PC", 0.10), ("PFB", 0.10), ("PR", 0.05)])
def test_profiles_quasi_linear_lateral_rms_against_the_solver(profile_record, point, rel):
    """Car-body lateral rms within 5 % at PR, 10 % at PC and PFB: there the solver's response
    carries more nonlinear power than a linear model gives (the next test says how much).
    Measured −7.9 … −0.9 % (docs/analysis.md); the local linearisation was −2 … +20 %."""
    _sc, _fs, rec, est = profile_record
    td = float(np.std(rec[f"carbody.{point}.acc.y"]))
    assert est.comfort.point(point).directions["y"].rms == pytest.approx(td, rel=rel)
    assert est.model.quasi_linear.converged


def _coherent_share(y: np.ndarray, u: np.ndarray, fs: float, f_max: float,
                    segment_s: float = 8.0) -> float:
    """Share of the power of ``y`` that any linear time-invariant model of the inputs ``u``
    (rows) can reproduce: the multiple coherence's power S_yu·S_uu⁻¹·S_uy summed over the
    Welch bins from 0.2 Hz to ``f_max`` (where the inputs have power), over all of y's power."""
    nper = int(segment_s * fs)
    f, syy = signal.welch(y, fs=fs, nperseg=nper)
    n = u.shape[0]
    suu = np.stack([np.stack([signal.csd(u[i], u[j], fs=fs, nperseg=nper)[1]
                              for j in range(n)], -1) for i in range(n)], -2)
    suy = np.stack([signal.csd(u[i], y, fs=fs, nperseg=nper)[1] for i in range(n)], -1)
    band = (f >= 0.2) & (f <= f_max)
    sol = np.linalg.solve(suu[band], suy[band][..., None])[..., 0]
    coherent = np.real(np.einsum("fi,fi->f", suy[band].conj(), sol))
    return float(coherent.sum() / syy.sum())


@pytest.mark.parametrize("point", ["PC", "PFB", "PR"])
def test_profiles_lateral_gap_is_within_the_solvers_nonlinear_share(profile_record, point):
    """Which side is wrong where the estimate is 5–8 % low at PC and PFB: neither. Only 75–88 %
    of the solver's lateral power is coherent with the four rail irregularities (multiple
    coherence over the input's band; the rest: the contact's nonlinearity — flange contacts,
    creep coefficients and patch modulated by Δy — and power outside the input's band). A linear
    model's output is all coherent with the input: √(share) is the rms a linear model with the
    solver's own transfer functions would give. The quasi-linear estimate gives at least that
    (−1 … +9 % above it): it misses part of the nonlinear power, none of the linear.
    (tools/studies/quasilinear_diagnosis.py: the solver is converged at this amplitude, and the
    local model matches it within 3.5 % where the contact is linear, at 1 % of the amplitude.)"""
    sc, fs, rec, est = profile_record
    y = rec[f"carbody.{point}.acc.y"]
    f_max = 0.95 * sc.speed_mps / sc.excitation[0].wavelength_min_m
    share = _coherent_share(y - y.mean(), rec["input"], fs, f_max)
    ratio = est.comfort.point(point).directions["y"].rms / float(np.std(y))
    assert share < 0.9  # measured 0.75–0.88
    assert ratio >= np.sqrt(share) - 0.03  # measured −0.011 (PFB, 80 km/h) … +0.086


def test_profiles_quasi_linear_lateral_sperling_at_pc(profile_record):
    """Lateral Sperling at PC within 3 % (measured −2.1 / −2.2 % at 80 / 50 km/h; local
    +7.2 / +4.5 %); the vertical one is unchanged by the contact's linearisation (within 3 %
    too)."""
    _sc, fs, rec, est = profile_record
    pc = est.comfort.point("PC").directions
    for d in ("y", "z"):
        assert pc[d].sperling == pytest.approx(sperling(rec[f"carbody.PC.acc.{d}"], fs, d).value,
                                               rel=0.03), d

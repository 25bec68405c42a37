"""A measured irregularity as an input of the frequency-domain estimate
(``frequency/measured_input.py``): its Welch spectra against the German spectra it was drawn
from. The record is a realisation of the time-domain generator (``track.spectra.random_profile``)
written as a measured CSV per rail, so the conversion rails → components (means, cross-level
angle, gauge) and the spectral estimate are both checked against the analytic spectrum."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.frequency.errors import LinearisationError
from flexride.frequency.measured_input import measured_input
from flexride.scenario.excitation import MeasuredIrregularity
from flexride.track.spectra import GERMAN_HALF_GAUGE, german_psd, random_profile

B = GERMAN_HALF_GAUGE
COMPONENTS = ("vertical", "alignment", "cross_level", "gauge")


def write_record(path, length_m: float, wavelength_max_m: float, seed: int):
    """A German high realisation (1 m … ``wavelength_max_m``, 0.25 m spacing, no fade-in)
    written as a per-rail measured CSV at ``path`` (m)."""
    prof = random_profile(length_m, "high", COMPONENTS, 1.0, wavelength_max_m, seed=seed,
                          ds=0.25, fade_in_m=0.0)
    s = prof.s0 + prof.ds * np.arange(prof.z_left.size)
    np.savetxt(path, np.column_stack([s, prof.z_left, prof.z_right, prof.y_left, prof.y_right]),
               delimiter=",", header="distance_m,z_left,z_right,y_left,y_right", comments="",
               fmt="%.9e")
    return path


@pytest.fixture(scope="module")
def record(tmp_path_factory):
    """The spectra of 4 km of German high irregularity, 1–80 m, read from a per-rail CSV."""
    path = write_record(tmp_path_factory.mktemp("measured") / "record.csv", 4000.0, 80.0, 3)
    return measured_input(MeasuredIrregularity(path=str(path)), B)


@pytest.mark.parametrize("component", COMPONENTS)
@pytest.mark.parametrize("band_m", [(2.0, 4.0), (4.0, 8.0), (8.0, 16.0), (16.0, 32.0),
                                    (32.0, 64.0)])
def test_band_variance_matches_the_german_spectrum(record, component, band_m):
    """Variance in octave bands of wavelength, ∫ G df at 80 km/h, within 15 % of the German
    spectrum's (one 4 km realisation, about 40 Welch segments of 256 m)."""
    v = 80.0 / 3.6
    f = np.linspace(v / band_m[1], v / band_m[0], 2001)
    measured = np.trapezoid(record.temporal_psd(component, f, v, B), f)
    omega = 2.0 * np.pi * f / v
    expected = np.trapezoid(2.0 * np.pi / v * german_psd(omega, component, "high", B), f)
    assert measured == pytest.approx(expected, rel=0.15)


def test_the_record_states_its_band_and_averaging(record):
    d = record.to_dict()
    assert d["components"] == list(COMPONENTS)
    assert d["welch_segments"] >= 30 and d["spacing_m"] == pytest.approx(0.25)
    assert d["wavelength_max_m"] >= 200.0 and d["wavelength_min_m"] == pytest.approx(0.5)
    # outside the resolved band the input is zero
    v = 20.0
    assert record.temporal_psd("vertical", np.array([v / 400.0, v / 0.4]), v, B).tolist() == [
        0.0, 0.0]


def test_a_short_record_has_no_spectrum(tmp_path):
    rows = [[0.25 * i, 1e-3 * np.sin(i)] for i in range(200)]  # 50 m
    exc = MeasuredIrregularity(columns=["distance_m", "vertical"], rows=rows)
    with pytest.raises(LinearisationError, match="too short"):
        measured_input(exc, B)


@pytest.fixture(scope="module")
def long_record_csv(tmp_path_factory):
    """6 km of the preset's irregularity (German high, 1–120 m, seed 1) as a per-rail CSV."""
    return write_record(tmp_path_factory.mktemp("measured-long") / "record.csv", 6000.0,
                        120.0, 1)


@pytest.mark.slow
def test_an_estimate_from_a_measured_record_matches_its_spectrums_estimate(long_record_csv):
    """The estimate of ``paper-random-straight-80`` (cone: linear contact) from a measured
    realisation of its own spectrum against the estimate from the spectrum: rms and Sperling
    at the car body within the scatter of a 6 km record's Welch spectrum (rms 8 %, W 3 %)."""
    from flexride.frequency import estimate
    from flexride.scenario.presets import CONICAL_TREAD, load_preset

    spectrum = load_preset("paper-random-straight-80", CONICAL_TREAD)
    measured = load_preset("paper-random-straight-80", {
        **CONICAL_TREAD, "excitation": [{"kind": "measured", "path": str(long_record_csv)}]})
    points = ["PC", "PR"]
    a = {p.name: p for p in estimate(spectrum, points).comfort.points}
    b = {p.name: p for p in estimate(measured, points).comfort.points}
    for name in points:
        for d in ("y", "z"):
            ra, rb = a[name].directions[d], b[name].directions[d]
            assert rb.rms == pytest.approx(ra.rms, rel=0.08), (name, d)
            assert rb.sperling == pytest.approx(ra.sperling, rel=0.03), (name, d)

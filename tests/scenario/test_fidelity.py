"""The cut-off rule of flexible bodies (``scenario/fidelity.py``) against hand values: an
excitation of wavelength λ at the speed V drives f = V/λ; a body should keep modes up to
1.5·f rounded up to 10 Hz, and a run that does not says so in its summary's notes."""

from __future__ import annotations

import pytest

from flexride.analysis import analyze
from flexride.scenario.fidelity import cutoff_notes, excitation_frequency_hz, sufficient_cutoff_hz
from flexride.scenario.presets import load_preset
from flexride.solver.simulate import simulate

CORRUGATION_80 = "paper-corrugation-80"


def test_corrugation_at_80_kmh_drives_44_hz():
    sc = load_preset(CORRUGATION_80)
    assert excitation_frequency_hz(sc) == pytest.approx(80.0 / 3.6 / 0.5)  # 44.44 Hz
    assert sufficient_cutoff_hz(80.0 / 3.6 / 0.5, 40.0) == 70.0  # 1.5 · 44.4 = 66.7 → 70
    assert sufficient_cutoff_hz(10.0, 40.0) == 40.0  # the body's own when higher


def test_a_flexible_car_body_below_the_rule_is_named_with_the_cut_off_that_would_do():
    sc = load_preset(CORRUGATION_80, {"bodies.carbody.model": "flexible"})
    (note,) = cutoff_notes(sc)
    assert note.startswith("bodies.carbody.cutoff_hz = 40 Hz")
    assert "44.4 Hz" in note and "bodies.carbody.cutoff_hz ≥ 70 Hz" in note
    ok = load_preset(CORRUGATION_80, {"bodies.carbody.model": "flexible",
                                      "bodies.carbody.cutoff_hz": 70.0})
    assert cutoff_notes(ok) == []


@pytest.mark.parametrize("overrides", [
    {},  # rigid bodies keep no modes to miss
    {"bodies.carbody.model": "flexible", "excitation": []},  # nothing drives them
])
def test_no_note_without_a_flexible_body_or_an_excitation(overrides):
    assert cutoff_notes(load_preset(CORRUGATION_80, overrides)) == []


def test_random_irregularity_down_to_1_m_at_80_kmh_is_within_40_hz():
    """German spectra down to λ_min = 1 m at 80 km/h: 22.2 Hz, 1.5× = 33 Hz < 40 Hz."""
    sc = load_preset("paper-random-straight-80", {"bodies.frames.model": "flexible"})
    assert excitation_frequency_hz(sc) == pytest.approx(
        80.0 / 3.6 / sc.excitation[0].wavelength_min_m)
    assert sc.excitation[0].wavelength_min_m >= 80.0 / 3.6 * 1.5 / 40.0
    assert cutoff_notes(sc) == []


def test_a_runs_notes_reach_its_summary_first():
    res = simulate(load_preset(CORRUGATION_80, {"distance_m": 6.0}))
    res.meta["notes"] = ["bodies.carbody.cutoff_hz = 40 Hz keeps fewer elastic modes …"]
    assert analyze(res).notes[0] == res.meta["notes"][0]

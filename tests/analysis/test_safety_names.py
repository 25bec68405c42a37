"""Running safety under EN 14363's names (Q vertical, Y lateral wheel force): every index carries
its symbol and title, the summary says how GB 5599 names the same quantities; the JSON names of
the indices are unchanged."""

from __future__ import annotations

import numpy as np

from flexride.analysis import SAFETY_SYMBOLS, analyze, wheel_unloading
from flexride.analysis.safety import CONVENTION, SafetyIndex

from .conftest import make_results


def test_every_index_has_its_en14363_symbol_and_title():
    d = analyze(make_results(duration=8.0, wheelsets=2)).to_dict()
    symbols = {(i["name"], i["symbol"], i["title"]) for i in d["safety"]["indices"]}
    assert symbols == {("derailment_coefficient", "Y/Q", "derailment quotient"),
                       ("wheel_unloading", "ΔQ/Q", "wheel unloading"),
                       ("wheelset_lateral_force", "ΣY", "track-shifting force")}
    assert d["settings"]["safety"]["convention"] == CONVENTION
    assert "Q/P is Y/Q" in CONVENTION and "ΔP/P is ΔQ/Q" in CONVENTION
    assert d["settings"]["safety"]["limits"]["wheelset_lateral_force_kN"] == "10 + 2Q0/3"


def test_processing_texts_use_q_for_the_vertical_force():
    fs = 500.0
    q = 60e3 + 1e3 * np.sin(2 * np.pi * 3 * np.arange(2000) / fs)
    idx = wheel_unloading(q, 60e3, fs)
    assert idx.symbol == "ΔQ/Q" and idx.processing.startswith("ΔQ/Q = (Q0 − Q)/Q0")
    assert "P0" not in idx.processing


def test_symbols_are_filled_from_the_name():
    idx = SafetyIndex("wheelset_lateral_force", "wheelset1", 1.0, 2.0, 0.5, True, 1.0, 0.0,
                      "kN", "", "")
    assert (idx.symbol, idx.title) == SAFETY_SYMBOLS["wheelset_lateral_force"]

"""Time-step convergence of the car-body response."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import PROFILES_DT, preset
from flexride.solver.simulate import simulate


def test_halving_the_step_changes_carbody_rms_by_less_than_one_percent():
    """Conical tread at Δt = 1e-4 s against 5e-5 s."""
    base = {"duration_s": 4.0, "output.rate_hz": 1000.0, "contact.geometry": "conical"}
    a = simulate(preset("paper-metro-random", **base, **{"solver.dt": 1.0e-4}))
    b = simulate(preset("paper-metro-random", **base, **{"solver.dt": 5.0e-5}))
    for ch in ("carbody.PC.acc.z", "carbody.PR.acc.z", "carbody.PC.acc.y"):
        ra = np.sqrt(np.mean(a.channels[ch] ** 2))
        rb = np.sqrt(np.mean(b.channels[ch] ** 2))
        assert ra == pytest.approx(rb, rel=0.01), ch


def test_profiles_at_their_step_are_converged():
    """Real profiles (S1002/60E1) at 6.25e-5 s against half of it, 2 s."""
    base = {"duration_s": 2.0, "output.rate_hz": 1000.0, "contact.geometry": "profiles"}
    a = simulate(preset("paper-metro-random", **base, **{"solver.dt": PROFILES_DT}))
    b = simulate(preset("paper-metro-random", **base, **{"solver.dt": PROFILES_DT / 2}))
    for ch in ("carbody.PC.acc.z", "carbody.PR.acc.z", "carbody.PC.acc.y"):
        ra = np.sqrt(np.mean(a.channels[ch] ** 2))
        rb = np.sqrt(np.mean(b.channels[ch] ** 2))
        assert ra == pytest.approx(rb, rel=0.01), ch

"""Published findings of the paper that the rigid model must reproduce qualitatively.

§7 / Fig. 21: under the settlement (long-wave) excitation the peak car-body vertical
acceleration increases linearly with speed, with fitting factors R² > 0.99, and the floor
centre PC sees the smallest value.
"""

from __future__ import annotations

import numpy as np

from flexride.analysis import linear_regression
from flexride.scenario.presets import PAPER_SPEEDS_KMH, load_preset
from flexride.solver import simulate


def test_settlement_peak_acceleration_is_linear_in_speed():
    points = ("PR", "PFB", "PC", "PRB")
    peaks = {p: [] for p in points}
    for v in PAPER_SPEEDS_KMH:
        res = simulate(load_preset(f"paper-settlement-{v}"))
        for p in points:
            peaks[p].append(float(np.abs(res.channels[f"carbody.{p}.acc.z"]).max()))
    speeds = np.array(PAPER_SPEEDS_KMH, dtype=float)
    for p in points:
        fit = linear_regression(speeds, np.array(peaks[p]))
        assert fit.slope > 0 and fit.r_squared > 0.99, (p, fit)
    for i in range(len(speeds)):
        assert peaks["PC"][i] == min(peaks[p][i] for p in points)

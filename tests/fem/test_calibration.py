"""Model updating: the calibration recovers known parameters; the default is calibrated."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.fem.calibration import calibrate_carbody, carbody_frequencies
from flexride.fem.defaults import PAPER_TABLE1_HZ, default_carbody_params
from flexride.fem.vehicle_models import carbody_params_for, carbody_target


def test_calibration_recovers_a_known_stiffness(vehicle):
    target = carbody_target(vehicle)
    base = carbody_params_for(vehicle)
    truth = base.with_values(floor_depth=base.floor_depth * 1.25)
    f_true, _, _ = carbody_frequencies(truth, target, 1.0, 2)
    res = calibrate_carbody(
        f_true,
        target,
        base=base,
        variables=("floor_depth",),
        element_size=1.0,
        regularisation=0.0,
        max_evaluations=20,
        tolerance=0.01,
    )
    assert res.success, res.table()
    assert res.values["floor_depth"] == pytest.approx(truth.floor_depth, rel=0.05)
    assert "floor_depth" in res.table()


@pytest.mark.slow
def test_default_carbody_matches_paper_table1(vehicle):
    """The stored calibration: first six elastic modes of the 0.2 m model within ±5 %."""
    f, _, _ = carbody_frequencies(
        carbody_params_for(vehicle, default_carbody_params()), carbody_target(vehicle), 0.2, 6
    )
    err = f / np.asarray(PAPER_TABLE1_HZ) - 1.0
    assert np.all(np.abs(err) < 0.05), (f, err)

"""Geometric filtering: the car-body bounce response at the floor centre to the vertical
profile vanishes where the two bogies (L = 12.6 m) or the two wheelsets of a bogie (2.2 m)
excite in antiphase, f = (2k+1)V/(2L)."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import preset
from flexride.frequency import linear_model
from flexride.frequency.response import _sub, channel_frf


@pytest.fixture(scope="module")
def model():
    """Local linearisation: the notches are exact for identical wheelsets; the quasi-linear
    contact gives the leading and trailing wheelsets of a bogie their own gains (their lateral
    σ differ: 2.1 and 1.5 mm), which leaves 0.5 % of the response in the wheelbase notch."""
    return linear_model(preset("paper-random-straight-80"), linearisation="local")


@pytest.mark.parametrize("spacing", [12.6, 2.2])
def test_notches_of_the_bounce_response(model, spacing):
    speed = model.speed
    out = _sub(model.accelerations, ["carbody.PC.acc.z"])
    vertical = np.array([[1.0, 1.0, 0.0, 0.0]])
    for k in range(3):
        f0 = (2 * k + 1) * speed / (2 * spacing)
        if f0 > 20.0:
            continue
        f = np.array([0.85 * f0, f0, 1.15 * f0])
        y = np.abs(channel_frf(model, out, f, vertical)[0][:, 0, 0])
        assert y[1] < 1e-3 * min(y[0], y[2]), (spacing, k, y)


def test_the_delays_are_the_wheelset_spacings(model):
    assert model.delays() * model.speed == pytest.approx([0.0, 2.2, 12.6, 14.8], abs=1e-9)

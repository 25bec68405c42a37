"""The rail irregularity profile: sampling between grid points, sums of profiles, checks."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.track.profile import IrregularityProfile

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



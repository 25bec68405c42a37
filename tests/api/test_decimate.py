"""Decimation for plotting: min/max envelope and LTTB against a plain reference."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.api.services.decimate import decimate_indices, lttb_indices, minmax_indices


def _lttb_reference(x, y, n_out):
    """Straightforward LTTB (Steinarsson 2013)."""
    n = len(x)
    every = (n - 2) / (n_out - 2)
    out, a = [0], 0
    for i in range(n_out - 2):
        s0 = int(np.floor((i + 1) * every)) + 1
        s1 = min(int(np.floor((i + 2) * every)) + 1, n)
        if s0 >= s1:
            s0, s1 = n - 1, n
        ax, ay = np.mean(x[s0:s1]), np.mean(y[s0:s1])
        r0, r1 = int(np.floor(i * every)) + 1, min(int(np.floor((i + 1) * every)) + 1, n - 1)
        areas = [abs((x[a] - ax) * (y[j] - y[a]) - (x[a] - x[j]) * (ay - y[a]))
                 for j in range(r0, r1)]
        a = r0 + int(np.argmax(areas))
        out.append(a)
    out.append(n - 1)
    return np.array(out)


@pytest.mark.parametrize("n, m", [(1000, 100), (20_000, 10_000), (997, 13)])
def test_lttb_matches_the_reference(n, m):
    rng = np.random.default_rng(n)
    x = np.arange(n) / 1000.0
    y = np.cumsum(rng.standard_normal(n))
    idx = lttb_indices(x, y, m)
    np.testing.assert_array_equal(idx, np.unique(_lttb_reference(x, y, m)))
    assert idx[0] == 0 and idx[-1] == n - 1 and len(idx) <= m


def test_minmax_keeps_every_extreme():
    rng = np.random.default_rng(1)
    y = rng.standard_normal(10_001)
    y[1234], y[8888] = 50.0, -50.0
    idx = minmax_indices(y, 200)
    assert len(idx) <= 200 and np.all(np.diff(idx) > 0)
    assert 1234 in idx and 8888 in idx
    buckets = np.array_split(np.arange(y.size), 100)
    assert y[idx].max() == y.max() and y[idx].min() == y.min()
    assert len(buckets) == 100


def test_short_records_are_returned_whole():
    y = np.arange(5.0)
    for method in ("minmax", "lttb", "none"):
        np.testing.assert_array_equal(decimate_indices(y, y, 10, method), np.arange(5))
    with pytest.raises(ValueError):
        decimate_indices(np.arange(50.0), np.arange(50.0), 10, "bogus")

"""Comfort maps over many nodes agree with the single-channel functions."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.analysis import (
    comfort_map,
    continuous_comfort,
    mtvv,
    sperling_filter,
    sperling_spectral,
    vdv,
    weighted_rms,
)
from flexride.analysis.weighting import apply_weighting
from flexride.errors import AnalysisError

FS = 250.0


@pytest.fixture(scope="module")
def nodes():
    rng = np.random.default_rng(3)
    t = np.arange(round(12 * FS)) / FS
    amps = rng.uniform(0.05, 0.6, 40)
    freqs = rng.choice([1.0, 2.0, 6.0, 8.0, 12.0], 40)
    acc = amps[:, None] * np.sin(2 * np.pi * freqs[:, None] * t) \
        + 0.02 * rng.standard_normal((40, t.size))
    coords = np.column_stack([np.linspace(-9, 9, 40), np.zeros(40)])
    return acc, coords


@pytest.mark.parametrize("block_samples", [4_000_000, 7_000])  # one block / many blocks
def test_sperling_map_matches_rows(nodes, block_samples):
    acc, coords = nodes
    m = comfort_map(acc, FS, coordinates=coords, block_samples=block_samples)
    ref = [sperling_spectral(a, FS, "z").value for a in acc]
    np.testing.assert_allclose(m.values, ref, rtol=1e-12)
    assert m.argmax == int(np.argmax(ref)) and m.max_value == pytest.approx(max(ref))
    assert len(m.grades) == 40 and "spectral" in m.method and m.unit == "-"
    assert m.coordinates.shape == (40, 2)
    mf = comfort_map(acc, FS, direction="y", form="filter", block_samples=block_samples)
    np.testing.assert_allclose(mf.values[:3], [sperling_filter(a, FS, "y").value
                                               for a in acc[:3]], rtol=1e-12)


def test_other_measures_match(nodes):
    acc, _ = nodes
    m = comfort_map(acc, FS, measure="weighted_rms", direction="z", block_samples=9_000)
    np.testing.assert_allclose(m.values[:4], [weighted_rms(a, FS, "Wb").value for a in acc[:4]])
    m = comfort_map(acc, FS, measure="weighted_rms", direction="z", weighting="Wk")
    assert m.values[0] == pytest.approx(weighted_rms(acc[0], FS, "Wk").value)
    m = comfort_map(acc, FS, measure="cc_max", direction="y")
    assert m.values[5] == pytest.approx(continuous_comfort(acc[5], FS, "y").maximum)
    m = comfort_map(acc, FS, measure="mtvv")
    assert m.values[2] == pytest.approx(mtvv(apply_weighting(acc[2], FS, "Wb"), FS))
    m = comfort_map(acc, FS, measure="vdv")
    assert m.values[2] == pytest.approx(vdv(apply_weighting(acc[2], FS, "Wb"), FS))
    assert m.unit == "m/s^1.75"
    np.testing.assert_allclose(comfort_map(acc, FS, measure="peak").values,
                               np.max(np.abs(acc), axis=1))
    np.testing.assert_allclose(comfort_map(acc, FS, measure="rms").values,
                               np.sqrt(np.mean(acc**2, axis=1)))


def test_comfort_map_bad_input(nodes):
    acc, _ = nodes
    with pytest.raises(AnalysisError, match="dimension"):
        comfort_map(acc[0], FS)
    with pytest.raises(AnalysisError, match="coordinates"):
        comfort_map(acc, FS, coordinates=np.zeros((3, 2)))
    with pytest.raises(AnalysisError, match="unknown comfort measure"):
        comfort_map(acc, FS, measure="happiness")
    with pytest.raises(AnalysisError, match="vertical and lateral"):
        comfort_map(acc, FS, direction="x")
    with pytest.raises(AnalysisError, match="NaN"):
        comfort_map(np.full((3, 3000), np.nan), FS)

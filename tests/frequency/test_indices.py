"""Comfort indices from a PSD (:mod:`flexride.frequency.indices`) against their definitions:
the spectral Sperling index's expected line powers against the direct sum over the window's
kernel, and a narrow band against the closed-form index of a sine of the same mean square;
the response's shortcuts (the wheels' σ alone, the modal coordinates kept on the model)
against the full response."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import preset
from flexride.analysis.sperling import frequency_correction
from flexride.frequency import indices as ix
from flexride.frequency import linear_model, response
from flexride.frequency.grid import frequency_grid
from flexride.frequency.response import modal_input, wheel_variance


def _smooth_psd(f: np.ndarray) -> np.ndarray:
    """A broadband PSD with two resonances ((m/s²)²/Hz)."""
    return (1e-3 / (1 + ((f - 1.2) / 0.15) ** 2) + 4e-4 / (1 + ((f - 9.0) / 0.8) ** 2)
            + 1e-5 * np.exp(-f / 30.0))


def test_line_powers_equal_the_sum_over_the_kernel():
    """δ·Σ_j G(f_j)·K(f_j − f_i) computed directly for every line (the definition) and by the
    polyphase diagonal sums: the same, every line to its own size (also the weak ones far
    from the resonances, whose grouping into peaks the index depends on)."""
    lk = ix._line_kernel(80.0, 5.0)
    g = _smooth_psd(lk.fine)[None, :]
    offsets = (lk.fine[None, :] - lk.lines[:, None]) * 5.0
    direct = lk.step * (ix._window_gain(offsets) @ g[0])
    # the sum stops ±64 lines from each line (the window's gain there < 2e-12 of its centre):
    # 2e-10 of the weak lines between the resonances, whose Lorentzian tails reach far
    np.testing.assert_allclose(lk.line_power(g)[0], direct, rtol=1e-9)
    # the grid has every line on it, s steps apart
    s = lk.per_line
    np.testing.assert_allclose(lk.fine[s - 1::s][:lk.lines.size], lk.lines, rtol=1e-12)


@pytest.mark.parametrize("f0, direction", [(2.4, "z"), (6.8, "y"), (1.2, "y")])
def test_narrow_band_has_the_sperling_index_of_a_sine(f0, direction):
    """A band 0.05 Hz wide around f0 holding the mean square σ² is a sine of amplitude √2·σ
    for 5 s segments: W = 0.896·((100·a)³·F(f0)/f0)^(1/10) (EN 12299 Annex / Sperling), with
    the dynamic part's gain at f0 (≈ 1 above 1 Hz). f0 on a line (k/5 s): the Hann window
    puts all of it within ±1 line, the one peak the index sums (between two lines 2 % of the
    power lands 1.5 lines off and forms a peak of its own, in the time domain as here)."""
    sigma = 0.05  # m/s²
    f = np.unique(np.concatenate([np.linspace(0.1, 80.0, 4000),
                                  np.linspace(f0 - 0.025, f0 + 0.025, 201)]))
    psd = np.where(np.abs(f - f0) <= 0.025, sigma**2 / 0.05, 0.0)
    w = ix.sperling_spectral_from_psd(f, psd[None, :], direction)[0]
    a = np.sqrt(2.0 * sigma**2 * ix.dynamic_part_gain(np.array([f0]))[0])
    d = "vertical" if direction == "z" else "lateral"
    expected = 0.896 * ((100.0 * a) ** 3 * frequency_correction(np.array([f0]), d)[0] / f0) ** 0.1
    assert w == pytest.approx(expected, rel=2e-4)


@pytest.fixture(scope="module")
def model():
    return linear_model(preset("paper-random-straight-80"))


def test_wheel_variance_is_the_responses(model):
    """The wheels' σ channels alone give the variances the full response gives them."""
    full = response(model)
    names = [n for n in full.wheel_channels if n.endswith(".rel_disp.y")]
    rows = [full.wheel_channels.index(n) for n in names]
    np.testing.assert_allclose(wheel_variance(model, names),
                               full.variance(full.wheel_psd)[rows], rtol=1e-12)


def test_modal_coordinates_are_kept_for_the_same_grid_only(model):
    f = frequency_grid(model.modes)
    maps = model.spectra.rail_maps()
    first = modal_input(model, f, maps)
    assert modal_input(model, f, maps) is first
    assert not first.flags.writeable
    other = modal_input(model, f[::2], maps)
    assert other.shape[0] == first[::2].shape[0]
    np.testing.assert_allclose(other, first[::2], rtol=1e-12)

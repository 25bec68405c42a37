"""Comfort indices from a one-sided acceleration PSD G(f) on a (non-uniform) frequency grid,
each the expectation of the time-domain definition in :mod:`flexride.analysis` for a stationary
Gaussian response.

* rms: √∫G df.
* ISO 2631 / EN 12299 weighted rms: √∫|W(f)|² G df with W the analogue weighting of
  :func:`flexride.analysis.weighting.weighting_response` (the same definitions the filters are
  built from).
* Sperling, filter form: 4.42·a_B^0.3, a_B = √∫|B(f)|² G_d df.
* Sperling, spectral form: the time-domain version cuts the record into 5 s Hann segments,
  power-averages the mean square of every line f_i = k/5 s, merges the lines into spectral
  peaks (:func:`flexride.analysis.sperling.peak_lines`) and sums W¹⁰ = 0.896¹⁰·a³F(f)/f over
  the peaks in 0.5–40 Hz. For a stationary process the expected mean square of line i is
  ∫G(f)·K(f − f_i) df with K the window's spectral kernel (|Ŵ|²/(N Σw²), ∫K df = 1/T; so
  G(f_i)/T for a smooth G); the same peaks are formed from these expectations: the index a
  long record converges to.
* G_d is the dynamic part the analysis applies Sperling to: G times the squared magnitude
  (1 − 1/(1 + (f/0.3)⁸))² of its quasi-static split.
* EN 12299 N_MV: the 5 s mean square of the weighted acceleration is treated as σ²χ²_ν/ν with
  ν = 2σ⁴/Var, Var = (2/T)∫₋ᵀᵀ(1 − |τ|/T)R(τ)² dτ (R the autocorrelation of the weighted
  signal); its 95th percentile gives a_P95.
* Expected largest |a| over a duration D (Davenport): σ(√(2 ln N) + 0.5772/√(2 ln N)) with
  N = 2ν₀D peaks of either sign, ν₀ = √(m₂/m₀) the zero up-crossing rate.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
from scipy import signal, stats

from flexride.analysis.quasistatic import QUASISTATIC_DEFAULTS
from flexride.analysis.sperling import PEAK_HALF_WIDTH, SPERLING_DEFAULTS, index_of_spectrum
from flexride.analysis.weighting import weighting_response

__all__ = ["dynamic_part_gain", "expected_peak", "nmv_block_p95", "sperling_filter_from_psd",
           "sperling_spectral_from_psd", "weighted_rms"]

#: largest step of the uniform grid the window's kernel is applied on (Hz)
FINE_DF = 0.01
_EULER = 0.5772156649


def dynamic_part_gain(f: np.ndarray) -> np.ndarray:
    """Squared magnitude of the analysis's dynamic part (record − quasi-static part) (-)."""
    fc, order = QUASISTATIC_DEFAULTS["cutoff_hz"], QUASISTATIC_DEFAULTS["order"]
    r = (np.asarray(f, float) / fc) ** (2 * order)
    return (r / (1.0 + r)) ** 2


def weighted_rms(f: np.ndarray, df: np.ndarray, psd: np.ndarray, name: str | None) -> np.ndarray:
    """√∫|W|²G df of every row of ``psd`` ((m/s²)²/Hz); ``name`` None for no weighting."""
    w2 = 1.0 if name is None else np.abs(weighting_response(name, f)) ** 2
    return np.sqrt(np.atleast_2d(psd * w2) @ df)


def sperling_filter_from_psd(f: np.ndarray, df: np.ndarray, psd: np.ndarray,
                             direction: str) -> np.ndarray:
    """Filter-form Sperling index 4.42·a_B^0.3 of the dynamic part of every row (-)."""
    name = "Bv" if direction == "z" else "Bh"
    return 4.42 * weighted_rms(f, df, psd * dynamic_part_gain(f), name) ** 0.3


def sperling_spectral_from_psd(f: np.ndarray, psd: np.ndarray, direction: str,
                               segment_s: float = SPERLING_DEFAULTS["segment_s"]) -> np.ndarray:
    """Spectral-form Sperling index of the dynamic part of every row (module docstring).

    Parameters
    ----------
    f : numpy.ndarray
        (n_f,) sorted grid (Hz).
    psd : numpy.ndarray
        (n_rows, n_f) one-sided acceleration PSD ((m/s²)²/Hz).
    direction : {"z", "y"}
        Vertical or lateral frequency correction.
    segment_s : float
        Segment length of the time-domain definition (s).
    """
    lk = _line_kernel(float(f[-1]), float(segment_s))
    g = np.atleast_2d(psd) * dynamic_part_gain(f)
    logg = np.log(np.maximum(g, 1e-300))
    gf = np.exp(np.array([np.interp(lk.fine, f, row, left=-690.0, right=-690.0)
                          for row in logg]))
    power = lk.line_power(gf)  # (rows, lines): expected mean square per line, (m/s²)²
    d = "vertical" if direction == "z" else "lateral"
    return np.array([index_of_spectrum(row, lk.lines, d) for row in power])


#: Lines on either side of a line whose spectrum enters its expected power: the pinned Hann
#: window's gain 64 lines from its centre is below 2e-12 of the centre's (it falls as ν⁻⁶).
KERNEL_HALF_LINES = 64


@dataclasses.dataclass(frozen=True)
class _LineKernel:
    """The lines the spectral form looks at, a uniform fine grid that has every line on it,
    and the window's spectral kernel on that grid, split into its polyphase blocks.

    Attributes
    ----------
    lines : numpy.ndarray
        (n_lines,) line frequencies k/T (Hz).
    fine : numpy.ndarray
        (n,) the grid j·δ, j = 1 … n (Hz), δ = 1/(s·T) ≤ :data:`FINE_DF` (s steps per line).
    per_line : int
        s.
    blocks : numpy.ndarray
        (2Q, s) the kernel at offsets q + p/s lines, q = −Q … Q − 1 (Q =
        :data:`KERNEL_HALF_LINES`), p = 0 … s − 1.
    step : float
        δ (Hz).
    """

    lines: np.ndarray
    fine: np.ndarray
    per_line: int
    blocks: np.ndarray
    step: float

    def line_power(self, gf: np.ndarray) -> np.ndarray:
        """Expected mean square of every line, δ·Σ_j G(f_j)·K(f_j − f_i) over the kernel's
        ±Q lines, for every row of ``gf`` ((rows, n) PSD on :attr:`fine`, (m/s²)²/Hz) →
        (rows, n_lines) ((m/s²)²).

        The lines lie every s grid steps, so the sum is polyphase: with the PSD cut into
        blocks of s steps, line i is Σ_q (block i + q)·(kernel block q), the diagonal sums of
        one matrix product. Every term is positive: each line is accurate relative to its own
        size (a weak line beside a strong peak too, which decides how the index merges
        lines into peaks), as the sum over the dense kernel matrix is.
        """
        s, q2 = self.per_line, self.blocks.shape[0]
        rows, n = gf.shape
        n_lines = self.lines.size
        pad = q2 // 2 * s
        u = np.zeros((rows, (n + 2 * pad) // s + 1, s))
        flat = u.reshape(rows, -1)
        flat[:, pad - (s - 1):pad - (s - 1) + n] = gf  # line i's centre starts block Q + i
        # (rows, blocks, 2Q): block b against kernel block q
        d = (u.reshape(-1, s) @ self.blocks.T).reshape(rows, -1, q2)
        diag = np.lib.stride_tricks.as_strided(
            d, (rows, n_lines, q2), (d.strides[0], d.strides[1], d.strides[1] + d.strides[2]),
            writeable=False)
        return self.step * diag.sum(axis=-1)


@functools.lru_cache(maxsize=8)
def _line_kernel(f_max: float, segment_s: float) -> _LineKernel:
    """The lines, fine grid and kernel of the spectral form up to ``f_max`` (Hz) for segments
    of ``segment_s`` (s): a line's expected mean square is ∫G(f)·K(f − f_i) df,
    K = |Ŵ((f − f_i)T)|²/(N Σw²) of the pinned window (∫K df = 1/T).
    """
    hi = SPERLING_DEFAULTS["band_hz"][1]
    n_lines = math.floor(hi * segment_s + 1e-9) + PEAK_HALF_WIDTH + 1
    per_line = max(1, math.ceil(1.0 / (segment_s * FINE_DF) - 1e-9))  # grid steps per line
    step = 1.0 / (segment_s * per_line)
    # the grid up to the last line plus the kernel's half width (what the sums read), within
    # f_max (beyond it the PSD is zero)
    n = min(max(math.ceil(f_max / step - 1e-9) - 1, per_line * n_lines),
            per_line * (n_lines + KERNEL_HALF_LINES))
    q = np.arange(-KERNEL_HALF_LINES, KERNEL_HALF_LINES)
    blocks = _window_gain(q[:, None] + np.arange(per_line)[None, :] / per_line)
    lines = np.arange(1, n_lines + 1) / segment_s
    fine = np.arange(1, n + 1) * step
    for a in (lines, fine, blocks):
        a.setflags(write=False)
    return _LineKernel(lines, fine, per_line, blocks, step)


def _window_gain(offset: np.ndarray, n: int = 4096, pad: int = 32) -> np.ndarray:
    """|Ŵ(ν)|²/(N Σw²) of the pinned Sperling window at ``offset`` lines from its centre,
    interpolated from a zero-padded FFT of an ``n``-sample window (continuous-time limit).
    """
    w = signal.get_window(SPERLING_DEFAULTS["window"], n, fftbins=True)
    spec = np.abs(np.fft.fft(w, n * pad)) ** 2 / (n * np.sum(w**2))
    nu = np.fft.fftfreq(n * pad, 1.0 / n)  # in lines (cycles per window)
    order = np.argsort(nu)
    return np.interp(offset, nu[order], spec[order], left=0.0, right=0.0)


def _autocorrelation(f: np.ndarray, df: np.ndarray, g: np.ndarray, tau: np.ndarray
                     ) -> np.ndarray:
    """R(τ) = ∫ G(f) cos(2πfτ) df of every row of ``g``: (rows, n_tau)."""
    return np.atleast_2d(g * df) @ _cosines(f, tau)


def _cosines(f: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """cos(2πfτ) (n_f × n_tau), kept for the last few grids (both directions of an estimate
    use the same).
    """
    key = (np.ascontiguousarray(f, dtype=float).tobytes(),
           np.ascontiguousarray(tau, dtype=float).tobytes())
    return _cosines_cached(key)


@functools.lru_cache(maxsize=4)
def _cosines_cached(key: tuple[bytes, bytes]) -> np.ndarray:
    f, tau = (np.frombuffer(k, dtype=float) for k in key)
    n = tau.size
    step = (tau[-1] - tau[0]) / (n - 1) if n > 1 else 0.0
    if n < 4 or tau[0] != 0.0 or not np.allclose(tau, step * np.arange(n), rtol=0.0,
                                                  atol=1e-12 * abs(tau[-1])):
        out = np.cos(2.0 * np.pi * np.outer(f, tau))
    else:
        # e^{jθk} for k = b·k1 + k0 as e^{jθbk1}·e^{jθk0}: n complex products per frequency
        # instead of n cosines (rounding 1e-13 of the argument's size)
        b = int(np.ceil(np.sqrt(n)))
        theta = 2.0 * np.pi * f * step
        low = np.exp(1j * np.outer(theta, np.arange(b)))
        high = np.exp(1j * np.outer(theta, b * np.arange(-(-n // b))))
        out = (high[:, :, None] * low[:, None, :]).reshape(f.size, -1)[:, :n].real.copy()
    out.setflags(write=False)
    return out


def nmv_block_p95(f: np.ndarray, df: np.ndarray, psd: np.ndarray, name: str,
                  block_s: float = 5.0, quantile: float = 0.95) -> np.ndarray:
    """95th percentile of the 5 s rms of the ``name``-weighted acceleration, every row (m/s²)."""
    g = np.atleast_2d(psd) * np.abs(weighting_response(name, f)) ** 2
    tau = np.linspace(0.0, block_s, 501)
    R = _autocorrelation(f, df, g, tau)
    var0 = R[:, 0]
    tri = (1.0 - tau / block_s) * R**2
    var_ms = 2.0 / block_s * 2.0 * np.trapezoid(tri, tau, axis=-1)
    nu = np.where(var_ms > 0, 2.0 * var0**2 / np.maximum(var_ms, 1e-300), 1e6)
    return np.sqrt(var0 * stats.chi2.ppf(quantile, nu) / nu)


def expected_peak(f: np.ndarray, df: np.ndarray, psd: np.ndarray, duration: float
                  ) -> np.ndarray:
    """Expected largest |a| over ``duration`` s for a Gaussian process, every row (m/s²)."""
    g = np.atleast_2d(psd)
    m0 = g @ df
    m2 = g @ (df * f**2)
    nu0 = np.sqrt(m2 / np.maximum(m0, 1e-300))
    k = np.sqrt(2.0 * np.log(np.maximum(2.0 * nu0 * duration, math.e)))
    return np.sqrt(m0) * (k + _EULER / k)

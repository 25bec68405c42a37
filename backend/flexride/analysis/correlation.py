"""Cross-correlation between two channels, with the lag of the maximum and all local maxima.

Convention
----------
R_ab(k) = Σ_n a[n] · b[n + k] (both records with their means removed by default), computed by
:func:`scipy.signal.correlate` with lags from :func:`scipy.signal.correlation_lags`; the lag
τ = k / fs is in seconds. A maximum at τ > 0 means that ``b`` lags ``a`` by τ:
b(t) ≈ a(t − τ). For the paper's Fig. 26 pair (PRB, PR) the roof point above the front bogie
leads, so R_{PR,PRB} peaks at τ ≈ +0.57 s at 80 km/h and R_{PRB,PR} at −0.57 s.

``raw`` is the sum itself, in (m/s²)² (it grows with the record length, as in the paper's
figure); ``normalised`` is R_ab / √(Σa² Σb²), which lies in [−1, 1] and equals 1 at τ = 0 for
identical records. The lag of the maximum is refined to a fraction of a sample by a parabola
through the three largest samples (``lag_at_max_interpolated``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import fft as sp_fft
from scipy import signal

from flexride.analysis._common import check_rate, check_signal
from flexride.errors import AnalysisError

__all__ = ["CrossCorrelation", "cross_correlation", "cross_correlations"]


@dataclass
class CrossCorrelation:
    """Cross-correlation of two records.

    Attributes
    ----------
    lag_at_max : float
        Lag of the largest value of R_ab in s (on the sample grid).
    lag_at_max_interpolated : float
        Same, refined by parabolic interpolation (s).
    value_at_max : float
        Raw R_ab at that lag ((m/s²)²).
    normalised_at_max : float
        Normalised value there (-).
    local_maxima : list of dict
        Every local maximum with its ``lag`` (s), ``value`` (raw) and ``normalised`` value,
        ordered by lag (filtered by ``min_prominence`` if given).
    lags : numpy.ndarray
        Lags in s.
    raw, normalised : numpy.ndarray
        R_ab and its normalised form at ``lags``.
    """

    lag_at_max: float
    lag_at_max_interpolated: float
    value_at_max: float
    normalised_at_max: float
    local_maxima: list[dict[str, float]]
    lags: np.ndarray = field(metadata={"json": False})
    raw: np.ndarray = field(metadata={"json": False})
    normalised: np.ndarray = field(metadata={"json": False})
    convention: str = "R_ab(k) = sum_n a[n] b[n+k]; max at lag > 0: b lags a"
    demeaned: bool = True
    max_lag_s: float | None = None


def cross_correlation(
    a: np.ndarray,
    b: np.ndarray,
    fs: float,
    *,
    max_lag_s: float | None = None,
    demean: bool = True,
    min_prominence: float = 0.0,
) -> CrossCorrelation:
    """Cross-correlate two channels (see module docs for the convention).

    Parameters
    ----------
    a, b : array_like
        Records (same sample rate), shape ``(n_a,)`` and ``(n_b,)``.
    fs : float
        Sample rate in Hz.
    max_lag_s : float, optional
        Keep lags with |τ| ≤ max_lag_s (s); default all.
    demean : bool
        Remove the means first (default True).
    min_prominence : float
        Local maxima must have at least this prominence in the *normalised* correlation
        (default 0: all local maxima).

    Returns
    -------
    CrossCorrelation
    """
    fs = check_rate(fs)
    a = check_signal(a, fs, name="first channel", min_samples=2, ndim=(1,),
                     method="cross-correlation")
    b = check_signal(b, fs, name="second channel", min_samples=2, ndim=(1,),
                     method="cross-correlation")
    if max_lag_s is not None and max_lag_s < 0:
        raise AnalysisError(f"max_lag_s must be non-negative, got {max_lag_s!r}")
    if demean:
        a = a - a.mean()
        b = b - b.mean()
    raw = signal.correlate(b, a, mode="full", method="auto")
    lags = signal.correlation_lags(b.size, a.size, mode="full").astype(np.float64) / fs
    if max_lag_s is not None:
        keep = np.abs(lags) <= max_lag_s + 0.5 / fs
        raw, lags = raw[keep], lags[keep]
    energy = float(np.sqrt(np.sum(a * a) * np.sum(b * b)))
    return _finish(raw, lags, energy, fs, demean, max_lag_s, min_prominence)


def _finish(raw: np.ndarray, lags: np.ndarray, energy: float, fs: float, demean: bool,
            max_lag_s: float | None, min_prominence: float) -> CrossCorrelation:
    norm = raw / energy if energy > 0.0 else np.zeros_like(raw)
    i = int(np.argmax(raw))
    lag_i = float(lags[i])
    if 0 < i < raw.size - 1:
        y0, y1, y2 = raw[i - 1], raw[i], raw[i + 1]
        den = y0 - 2.0 * y1 + y2
        delta = 0.5 * (y0 - y2) / den if den < 0.0 else 0.0
        lag_fine = lag_i + float(np.clip(delta, -0.5, 0.5)) / fs
    else:
        lag_fine = lag_i
    peaks, _ = signal.find_peaks(norm, prominence=min_prominence if min_prominence > 0 else None)
    maxima = [{"lag": float(lags[p]), "value": float(raw[p]), "normalised": float(norm[p])}
              for p in peaks]
    return CrossCorrelation(lag_at_max=lag_i, lag_at_max_interpolated=lag_fine,
                            value_at_max=float(raw[i]), normalised_at_max=float(norm[i]),
                            local_maxima=maxima, lags=lags, raw=raw, normalised=norm,
                            demeaned=demean, max_lag_s=max_lag_s)


def cross_correlations(
    reference: np.ndarray,
    others: np.ndarray,
    fs: float,
    *,
    max_lag_s: float,
    demean: bool = True,
    min_prominence: float = 0.0,
) -> list[CrossCorrelation]:
    """Cross-correlate one reference channel with many channels of the same length at once.

    Same convention and results as :func:`cross_correlation` (``a`` = reference, ``b`` = each
    row of ``others``), computed together by FFT for lags |τ| ≤ ``max_lag_s``.

    Parameters
    ----------
    reference : array_like
        Reference record, shape ``(n,)``.
    others : array_like
        Records, shape ``(m, n)``.
    fs : float
        Sample rate in Hz.
    max_lag_s : float
        Largest lag kept (s).
    demean : bool
        Remove the means first.
    min_prominence : float
        Minimum prominence of the listed local maxima (normalised correlation).
    """
    fs = check_rate(fs)
    a = check_signal(reference, fs, name="reference channel", min_samples=2, ndim=(1,),
                     method="cross-correlation")
    bs = check_signal(others, fs, name="channels", min_samples=2, ndim=(2,),
                      method="cross-correlation")
    if bs.shape[-1] != a.size:
        raise AnalysisError("batched cross-correlation needs records of equal length")
    if not max_lag_s >= 0:
        raise AnalysisError(f"max_lag_s must be non-negative, got {max_lag_s!r}")
    n = a.size
    lag_n = min(n - 1, int(np.floor(max_lag_s * fs + 0.5)))
    if demean:
        a = a - a.mean()
        bs = bs - bs.mean(axis=-1, keepdims=True)
    nfft = sp_fft.next_fast_len(n + lag_n, real=True)
    spec = np.conj(sp_fft.rfft(a, nfft))[np.newaxis, :] * sp_fft.rfft(bs, nfft, axis=-1)
    circ = sp_fft.irfft(spec, nfft, axis=-1)
    raw = np.concatenate([circ[:, nfft - lag_n:], circ[:, : lag_n + 1]], axis=-1)
    lags = np.arange(-lag_n, lag_n + 1) / fs
    ea = float(np.sum(a * a))
    eb = np.sum(bs * bs, axis=-1)
    return [_finish(raw[k], lags, float(np.sqrt(ea * eb[k])), fs, demean, max_lag_s,
                    min_prominence) for k in range(bs.shape[0])]

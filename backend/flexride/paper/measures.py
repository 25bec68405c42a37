"""Small numerical measures the paper's findings are judged by: confidence intervals over
irregularity realisations, band levels and peaks of a spectrum, the share of a band around the
largest peak, straight-line fits against speed and the lag of a cross-correlation's maximum.

Pure functions of arrays (frequencies in Hz, PSDs in (m/s²)²/Hz, speeds in km/h), tested
against hand-made values in ``tests/paper``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import signal, stats

from flexride.analysis.correlation import cross_correlation
from flexride.analysis.statistics import linear_regression

__all__ = [
    "Estimate",
    "band_rms",
    "band_share",
    "lag_at_max",
    "line_fit",
    "mean_ci",
    "peak_dominance",
    "spectral_peaks",
]


@dataclass(frozen=True)
class Estimate:
    """Mean of one quantity over irregularity realisations, with its 95 % confidence interval.

    Attributes
    ----------
    mean : float
        Sample mean (unit of the quantity).
    ci95 : float or None
        Half-width of the two-sided 95 % confidence interval of the mean (Student t with
        n − 1 degrees of freedom); None for one value.
    n : int
        Number of values.
    """

    mean: float
    ci95: float | None
    n: int

    def to_dict(self) -> dict[str, float | int | None]:
        """``{"value", "ci95", "n"}``, JSON-ready (non-finite numbers become None)."""
        def num(v: float | None) -> float | None:
            return None if v is None or not math.isfinite(v) else float(f"{v:.5g}")

        return {"value": num(self.mean), "ci95": num(self.ci95), "n": self.n}

    def text(self, digits: int = 3) -> str:
        """``1.234 ± 0.056`` (or the mean alone for one value)."""
        if self.ci95 is None:
            return f"{self.mean:.{digits}g}"
        return f"{self.mean:.{digits}g} ± {self.ci95:.2g}"


def mean_ci(values: Sequence[float], level: float = 0.95) -> Estimate:
    """Mean and the half-width of its confidence interval (Student t, two-sided).

    Parameters
    ----------
    values : sequence of float
        One value per realisation (non-finite values are an error of the caller).
    level : float
        Confidence level (-), default 0.95.

    Returns
    -------
    Estimate
        ``ci95`` is t_{(1+level)/2, n−1}·s/√n, None for a single value.
    """
    x = np.asarray(values, dtype=float)
    if x.size == 0:
        raise ValueError("no values to average")
    if x.size == 1:
        return Estimate(float(x[0]), None, 1)
    half = float(stats.t.ppf(0.5 + level / 2.0, x.size - 1) * x.std(ddof=1) / math.sqrt(x.size))
    return Estimate(float(x.mean()), half, int(x.size))


def band_rms(f: np.ndarray, psd: np.ndarray, lo: float, hi: float) -> float:
    """Root mean square of the part of a one-sided PSD between ``lo`` and ``hi`` Hz.

    Parameters
    ----------
    f : numpy.ndarray
        Uniformly spaced frequencies (Hz).
    psd : numpy.ndarray
        One-sided PSD at ``f`` ((unit)²/Hz).
    lo, hi : float
        Band edges (Hz), lines with lo ≤ f < hi count.

    Returns
    -------
    float
        √(Σ PSD·Δf) over the band (unit).
    """
    f = np.asarray(f, dtype=float)
    p = np.asarray(psd, dtype=float)
    df = float(f[1] - f[0]) if f.size > 1 else 0.0
    keep = (f >= lo) & (f < hi)
    return float(math.sqrt(max(float(np.sum(p[keep])) * df, 0.0)))


def band_share(f: np.ndarray, psd: np.ndarray, bands: Sequence[tuple[float, float]],
               total: tuple[float, float]) -> float:
    """Share of the variance in ``total`` that lies in the union of ``bands`` (-).

    Bands are half-open [lo, hi) in Hz and should not overlap.
    """
    whole = band_rms(f, psd, *total) ** 2
    if whole <= 0.0:
        return math.nan
    part = sum(band_rms(f, psd, max(lo, total[0]), min(hi, total[1])) ** 2 for lo, hi in bands)
    return part / whole


def spectral_peaks(f: np.ndarray, psd: np.ndarray, band: tuple[float, float],
                   min_ratio: float = 2.0) -> list[float]:
    """Frequencies (Hz) of the peaks of a PSD inside ``band``, most prominent first.

    A peak is a local maximum of log10(PSD) that stands at least ``min_ratio`` (a factor,
    default 2) above the higher of its two surrounding minima (``scipy.signal.find_peaks``
    prominence, computed over the whole spectrum so that band edges do not make peaks).
    """
    f = np.asarray(f, dtype=float)
    p = np.asarray(psd, dtype=float)
    logp = np.log10(np.maximum(p, np.max(p) * 1e-14 + 1e-300))
    idx, props = signal.find_peaks(logp, prominence=math.log10(min_ratio))
    keep = (f[idx] >= band[0]) & (f[idx] <= band[1])
    idx, prom = idx[keep], props["prominences"][keep]
    return [float(f[i]) for i in idx[np.argsort(-prom)]]


def peak_dominance(f: np.ndarray, psd: np.ndarray, band: tuple[float, float],
                   half_width: float = 0.25) -> tuple[float, float]:
    """The largest PSD line in ``band`` and the share of the band's variance within
    ± ``half_width`` Hz of it.

    Returns
    -------
    (float, float)
        Frequency of the largest line (Hz) and the share (-): near 1 for one dominant
        frequency, small for broadband vibration.
    """
    f = np.asarray(f, dtype=float)
    p = np.asarray(psd, dtype=float)
    keep = (f >= band[0]) & (f <= band[1])
    if not np.any(keep):
        return math.nan, math.nan
    f_peak = float(f[keep][int(np.argmax(p[keep]))])
    near = band_rms(f, p, max(band[0], f_peak - half_width), f_peak + half_width + 1e-9) ** 2
    whole = band_rms(f, p, band[0], band[1] + 1e-9) ** 2
    return f_peak, (near / whole if whole > 0 else math.nan)


def line_fit(speeds: Sequence[float], values: Sequence[float]) -> dict[str, float]:
    """Least-squares line of a quantity against speed: ``slope`` (unit per km/h),
    ``intercept`` (unit) and ``r_squared`` (-; 1 for exact linear data).
    """
    fit = linear_regression(list(speeds), list(values), x_unit="km/h")
    return {"slope": fit.slope, "intercept": fit.intercept, "r_squared": fit.r_squared}


def lag_at_max(reference: np.ndarray, other: np.ndarray, fs: float,
               max_lag_s: float = 3.0) -> float:
    """Lag (s) of the maximum of the cross-correlation R(reference, other), refined by a
    parabola: positive when ``other`` lags ``reference`` (convention of
    :mod:`flexride.analysis.correlation`, the paper's Fig. 26).
    """
    return cross_correlation(reference, other, fs, max_lag_s=max_lag_s).lag_at_max_interpolated

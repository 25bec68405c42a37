"""Peak statistics per channel and linear regression of a quantity against speed.

* :func:`peak_statistics` — largest absolute value and when it occurs, max, min, mean, rms,
  standard deviation, peak-to-peak and the 99.85th percentile of |x| (the EN 14363 statistic),
  per channel (2-D input: one set per row).
* :func:`linear_regression` — least-squares line y = slope·x + intercept with
  R² = 1 − SS_res/SS_tot (1 for exact linear data, also when y is constant),
  :func:`scipy.stats.linregress` for the standard errors.
* :func:`regress_on_speed` — the same with the speed as x, e.g. the paper's Fig. 21
  (peak acceleration against speed, R² > 0.99).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy import stats

from flexride.analysis._common import check_rate, check_signal
from flexride.errors import AnalysisError

__all__ = ["LinearFit", "PeakStats", "linear_regression", "peak_statistics", "regress_on_speed"]


@dataclass
class PeakStats:
    """Statistics of one channel (values in the channel's unit; arrays for 2-D input).

    Attributes
    ----------
    max_abs : float
        Largest |x|; ``time_of_max_abs`` when it occurs (s from the record start + t0).
    max, min, mean, rms, std, peak_to_peak : float
        Usual statistics.
    p99_85_abs : float
        99.85th percentile of |x| (linear interpolation).
    n : int
        Number of samples.
    unit : str
        Unit of the channel.
    """

    max_abs: float | np.ndarray
    time_of_max_abs: float | np.ndarray
    max: float | np.ndarray
    min: float | np.ndarray
    mean: float | np.ndarray
    rms: float | np.ndarray
    std: float | np.ndarray
    peak_to_peak: float | np.ndarray
    p99_85_abs: float | np.ndarray
    n: int
    unit: str = ""


def _scalar(v: np.ndarray) -> float | np.ndarray:
    return float(v) if np.ndim(v) == 0 else v


def peak_statistics(
    x: np.ndarray, fs: float, *, t0: float = 0.0, unit: str = ""
) -> PeakStats:
    """Peak statistics of a record (per row for 2-D input).

    Parameters
    ----------
    x : array_like
        Signal, shape ``(n,)`` or ``(m, n)``.
    fs : float
        Sample rate in Hz.
    t0 : float
        Time of the first sample in s.
    unit : str
        Unit of the signal, copied to the result.
    """
    fs = check_rate(fs)
    x = check_signal(x, fs, name="signal", min_samples=1, method="peak statistics")
    ax = np.abs(x)
    i = np.argmax(ax, axis=-1)
    return PeakStats(
        max_abs=_scalar(np.max(ax, axis=-1)),
        time_of_max_abs=_scalar(t0 + i / fs),
        max=_scalar(np.max(x, axis=-1)),
        min=_scalar(np.min(x, axis=-1)),
        mean=_scalar(np.mean(x, axis=-1)),
        rms=_scalar(np.sqrt(np.mean(x * x, axis=-1))),
        std=_scalar(np.std(x, axis=-1)),
        peak_to_peak=_scalar(np.ptp(x, axis=-1)),
        p99_85_abs=_scalar(np.percentile(ax, 99.85, axis=-1)),
        n=int(x.shape[-1]),
        unit=unit,
    )


@dataclass
class LinearFit:
    """Least-squares line y = slope·x + intercept.

    Attributes
    ----------
    slope, intercept : float
        Fit coefficients (units y_unit/x_unit and y_unit).
    r_squared : float
        Coefficient of determination R² (-).
    n : int
        Number of points.
    stderr_slope, stderr_intercept : float
        Standard errors (NaN with two points).
    x_unit, y_unit : str
        Units.
    """

    slope: float
    intercept: float
    r_squared: float
    n: int
    stderr_slope: float
    stderr_intercept: float
    x_unit: str = ""
    y_unit: str = ""
    method: str = "ordinary least squares, R² = 1 − SS_res/SS_tot"

    def predict(self, x: float | np.ndarray) -> float | np.ndarray:
        """Fitted y at ``x``."""
        return self.slope * np.asarray(x) + self.intercept


def linear_regression(
    x: Sequence[float] | np.ndarray,
    y: Sequence[float] | np.ndarray,
    *,
    x_unit: str = "",
    y_unit: str = "",
) -> LinearFit:
    """Fit y = slope·x + intercept by least squares.

    Raises
    ------
    AnalysisError
        Fewer than two points, different lengths, non-finite values or constant x.
    """
    xa = check_signal(x, name="x", min_samples=2, ndim=(1,), method="a linear regression")
    ya = check_signal(y, name="y", min_samples=2, ndim=(1,), method="a linear regression")
    if xa.shape != ya.shape:
        raise AnalysisError(f"x and y differ in length ({xa.size} and {ya.size})")
    if np.ptp(xa) == 0.0:
        raise AnalysisError("linear regression needs at least two different x values")
    res = stats.linregress(xa, ya)
    slope, intercept = float(res.slope), float(res.intercept)
    resid = ya - (slope * xa + intercept)
    ss_res = float(np.sum(resid**2))
    ss_tot = float(np.sum((ya - ya.mean()) ** 2))
    scale = max(float(np.sum(ya**2)), 1e-300)
    if ss_tot <= 1e-24 * scale:
        r2 = 1.0 if ss_res <= 1e-24 * scale else 0.0
    else:
        r2 = max(0.0, 1.0 - ss_res / ss_tot)
    se_s = float(res.stderr) if xa.size > 2 else float("nan")
    se_i = float(res.intercept_stderr) if xa.size > 2 else float("nan")
    return LinearFit(slope=slope, intercept=intercept, r_squared=r2, n=int(xa.size),
                     stderr_slope=se_s, stderr_intercept=se_i, x_unit=x_unit, y_unit=y_unit)


def regress_on_speed(
    speeds: Sequence[float] | np.ndarray,
    values: Sequence[float] | np.ndarray,
    *,
    speed_unit: str = "km/h",
    value_unit: str = "",
) -> LinearFit:
    """Linear fit of a quantity (peak acceleration, Sperling index...) against running speed.

    Parameters
    ----------
    speeds : array_like
        Running speeds, in ``speed_unit`` (km/h by default, as in the paper's figures).
    values : array_like
        The quantity at each speed, in ``value_unit``.
    """
    return linear_regression(speeds, values, x_unit=speed_unit, y_unit=value_unit)


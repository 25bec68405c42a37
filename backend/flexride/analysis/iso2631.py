"""RMS indices of whole-body vibration per ISO 2631-1:1997 (and ISO 2631-4:2001 for rail).

* unweighted rms, frequency-weighted rms a_w (Wk vertical, Wd horizontal, Wb vertical in rail
  vehicles; weightings from :mod:`flexride.analysis.weighting`);
* running rms with linear integration over τ = 1 s (ISO 2631-1 §6.3.1, eq. 4) and its maximum,
  the maximum transient vibration value MTVV;
* fourth-power vibration dose value VDV = (∫ a_w⁴ dt)^(1/4) (§6.3.2), in m/s^1.75;
* crest factor max|a_w| / a_w (§6.2.1; the basic method is adequate up to 9) and the ratios
  MTVV/a_w (> 1.5) and VDV/(a_w T^(1/4)) (> 1.75) that call for the additional methods (§6.3.3);
* the comfort bands of Annex C.2.3 (public transport), which overlap on purpose;
* the point vibration total value a_v = (k_x² a_wx² + k_y² a_wy² + k_z² a_wz²)^(1/2) (§8.2).

Every value is computed along the last axis, so a 2-D array ``(channels, samples)`` is
evaluated at once.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from flexride.analysis._common import check_rate, check_signal
from flexride.analysis.weighting import WEIGHTINGS, WeightingMethod, apply_weighting
from flexride.errors import AnalysisError

__all__ = [
    "ISO2631_BANDS",
    "Iso2631Result",
    "WeightedRms",
    "comfort_band",
    "crest_factor",
    "iso2631_comfort",
    "mtvv",
    "rms",
    "running_rms",
    "vdv",
    "vibration_total_value",
    "weighted_rms",
]

#: ISO 2631-1:1997 Annex C.2.3 comfort reactions (m/s², inclusive ranges that overlap).
ISO2631_BANDS: tuple[tuple[float, float, str], ...] = (
    (0.0, 0.315, "not uncomfortable"),
    (0.315, 0.63, "a little uncomfortable"),
    (0.5, 1.0, "fairly uncomfortable"),
    (0.8, 1.6, "uncomfortable"),
    (1.25, 2.5, "very uncomfortable"),
    (2.0, np.inf, "extremely uncomfortable"),
)

_STANDARD = "ISO 2631-1:1997"


def rms(x: np.ndarray) -> float | np.ndarray:
    """Unweighted root-mean-square along the last axis (same unit as ``x``)."""
    x = check_signal(x, name="signal", min_samples=1, method="rms")
    r = np.sqrt(np.mean(x * x, axis=-1))
    return float(r) if r.ndim == 0 else r


@dataclass
class WeightedRms:
    """A frequency-weighted rms and how it was made (``float(result)`` gives the value).

    Attributes
    ----------
    value : float or numpy.ndarray
        a_w in m/s² (one per row for 2-D input).
    weighting : str
        Weighting used.
    standard : str
        Standard (edition) defining the weighting.
    method : str
        Filter realisation and averaging.
    """

    value: float | np.ndarray
    weighting: str
    standard: str
    method: str

    def __float__(self) -> float:
        """The value (m/s²), so the result can be used as a number."""
        return float(self.value)


def weighted_rms(
    x: np.ndarray, fs: float, weighting: str = "Wk", method: WeightingMethod = "iir"
) -> WeightedRms:
    """Frequency-weighted rms a_w (m/s²) of an acceleration record.

    Parameters
    ----------
    x : array_like
        Acceleration in m/s², shape ``(n,)`` or ``(m, n)``.
    fs : float
        Sample rate in Hz (≥ 250 Hz for the ISO weightings).
    weighting : str
        ``"Wk"`` (vertical, ISO 2631-1), ``"Wd"`` (horizontal), ``"Wb"`` (vertical, rail
        vehicles, ISO 2631-4 / EN 12299), or ``"Bv"``/``"Bh"``.
    method : {"iir", "fft"}
        Filter realisation, see :func:`~flexride.analysis.weighting.apply_weighting`.

    Returns
    -------
    WeightedRms
        The value with the weighting and standard that produced it.
    """
    aw = apply_weighting(x, fs, weighting, method=method)
    r = np.sqrt(np.mean(aw * aw, axis=-1))
    return WeightedRms(value=float(r) if r.ndim == 0 else r, weighting=weighting,
                       standard=WEIGHTINGS[weighting].standard,
                       method=f"rms over the whole record of the {weighting}-weighted "
                              f"acceleration ({method} filter)")


def running_rms(
    x: np.ndarray, fs: float, tau: float = 1.0
) -> tuple[np.ndarray, np.ndarray]:
    """Running rms with linear integration over the last ``tau`` seconds (ISO 2631-1 eq. 4).

    Parameters
    ----------
    x : array_like
        Signal (normally the weighted acceleration, m/s²), shape ``(n,)`` or ``(m, n)``.
    fs : float
        Sample rate in Hz.
    tau : float
        Integration time in s (ISO 2631-1 recommends 1 s).

    Returns
    -------
    t : numpy.ndarray
        Time of the end of each window in s (sample index / fs), shape ``(n − N + 1,)``.
    values : numpy.ndarray
        Running rms at those times, shape ``(..., n − N + 1)``; N = round(tau·fs).
    """
    fs = check_rate(fs)
    x = check_signal(x, fs, name="signal", min_duration=tau, method=f"a {tau:g} s running rms")
    n_win = max(1, round(tau * fs))
    return _window_rms(x, fs, n_win, 1)


def _window_rms(x: np.ndarray, fs: float, n_win: int, step: int,
                sq: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Rms over windows of ``n_win`` samples ending at samples n_win−1, n_win−1+step, ...

    ``sq`` may pass x² when the caller has it already.
    """
    csum = np.zeros((*x.shape[:-1], x.shape[-1] + 1))
    np.cumsum(x * x if sq is None else sq, axis=-1, out=csum[..., 1:])
    hi = csum[..., n_win::step]
    m = hi.shape[-1]
    ms = hi - csum[..., : (m - 1) * step + 1 : step]
    ms *= 1.0 / n_win
    np.clip(ms, 0.0, None, out=ms)
    ends = n_win + step * np.arange(m)
    return (ends - 1) / fs, np.sqrt(ms, out=ms)


def mtvv(x_weighted: np.ndarray, fs: float, tau: float = 1.0) -> float | np.ndarray:
    """Maximum transient vibration value: the largest 1 s running rms (m/s²)."""
    _, r = running_rms(x_weighted, fs, tau)
    m = r.max(axis=-1)
    return float(m) if m.ndim == 0 else m


def vdv(x_weighted: np.ndarray, fs: float) -> float | np.ndarray:
    """Fourth-power vibration dose value (∫ a_w⁴ dt)^(1/4) in m/s^1.75."""
    fs = check_rate(fs)
    x = check_signal(x_weighted, fs, name="signal", min_samples=1, method="VDV")
    sq = x * x
    v = (np.sum(sq * sq, axis=-1) / fs) ** 0.25
    return float(v) if v.ndim == 0 else v


def crest_factor(x_weighted: np.ndarray) -> float | np.ndarray:
    """Crest factor max|a_w| / rms(a_w) (-); NaN for an all-zero record."""
    x = check_signal(x_weighted, name="signal", min_samples=1, method="the crest factor")
    r = np.sqrt(np.mean(x * x, axis=-1))
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(r > 0.0, np.max(np.abs(x), axis=-1) / np.where(r > 0, r, 1.0), np.nan)
    return float(c) if c.ndim == 0 else c


def comfort_band(a_w: float) -> str:
    """ISO 2631-1 Annex C.2.3 comfort reaction for an overall weighted rms (m/s²).

    The bands overlap; a value in an overlap returns both names joined by " / ", e.g.
    0.55 m/s² → ``"a little uncomfortable / fairly uncomfortable"``.
    """
    v = float(a_w)
    if not np.isfinite(v) or v < 0.0:
        raise AnalysisError(f"comfort band needs a finite non-negative rms, got {a_w!r}")
    names = []
    for lo, hi, name in ISO2631_BANDS:
        if name == "not uncomfortable":
            inside = v < hi
        elif name == "extremely uncomfortable":
            inside = v > lo
        else:
            inside = lo <= v <= hi
        if inside:
            names.append(name)
    return " / ".join(names)


def vibration_total_value(
    a_wx: float = 0.0, a_wy: float = 0.0, a_wz: float = 0.0,
    k: tuple[float, float, float] = (1.0, 1.0, 1.0),
) -> float:
    """Point vibration total value a_v (m/s²), ISO 2631-1 §8.2 (k = 1 for comfort on a floor)."""
    return float(np.sqrt((k[0] * a_wx) ** 2 + (k[1] * a_wy) ** 2 + (k[2] * a_wz) ** 2))


@dataclass
class Iso2631Result:
    """ISO 2631-1 evaluation of one acceleration record.

    Attributes
    ----------
    weighting : str
        Frequency weighting used (``"Wk"``, ``"Wd"`` or ``"Wb"``).
    a_w : float
        Overall frequency-weighted rms (m/s²).
    rms : float
        Unweighted rms of the record (m/s²).
    mtvv : float
        Maximum 1 s running rms (m/s²).
    vdv : float
        Vibration dose value (m/s^1.75).
    crest_factor : float
        max|a_w| / a_w (-).
    mtvv_ratio : float
        MTVV / a_w (-); above 1.5 the basic method may underestimate.
    vdv_ratio : float
        VDV / (a_w T^(1/4)) (-); above 1.75 the basic method may underestimate.
    basic_method_adequate : bool
        Crest factor ≤ 9 and both ratios below their limits.
    comfort : str
        ISO 2631-1 Annex C.2.3 comfort reaction for a_w.
    standard, method : str
        What produced the values.
    """

    weighting: str
    a_w: float
    rms: float
    mtvv: float
    vdv: float
    crest_factor: float
    mtvv_ratio: float
    vdv_ratio: float
    basic_method_adequate: bool
    comfort: str
    standard: str = _STANDARD
    method: str = ""
    parameters: dict = field(default_factory=dict)


def iso2631_comfort(
    x: np.ndarray,
    fs: float,
    weighting: str = "Wk",
    *,
    tau: float = 1.0,
    method: WeightingMethod = "iir",
) -> Iso2631Result:
    """Full ISO 2631-1 evaluation (a_w, MTVV, VDV, crest factor, comfort band) of one record.

    Parameters
    ----------
    x : array_like
        Acceleration in m/s², shape ``(n,)``; at least ``tau`` seconds long.
    fs : float
        Sample rate in Hz (≥ 250 Hz).
    weighting : str
        ``"Wk"`` or ``"Wb"`` (vertical), ``"Wd"`` (horizontal).
    tau : float
        Running-rms integration time in s.
    method : {"iir", "fft"}
        Filter realisation.
    """
    if weighting not in ("Wk", "Wd", "Wb"):
        raise AnalysisError(f"ISO 2631 weighting must be 'Wk', 'Wd' or 'Wb', got {weighting!r}")
    fs = check_rate(fs)
    x = check_signal(x, fs, name="acceleration", min_duration=tau, ndim=(1,),
                     method=f"ISO 2631-1 evaluation ({tau:g} s running rms)")
    aw_sig = apply_weighting(x, fs, weighting, method=method)
    return _iso_from_weighted(x, aw_sig, fs, weighting, tau, method)


def _iso_from_weighted(
    x: np.ndarray, aw_sig: np.ndarray, fs: float, weighting: str, tau: float, method: str
) -> Iso2631Result:
    sq = aw_sig * aw_sig
    a_w = float(np.sqrt(np.mean(sq)))
    raw = float(np.sqrt(np.mean(x * x)))  # no BLAS call: its threads stall on busy machines
    _, rr = _window_rms(aw_sig, fs, max(1, round(tau * fs)), 1, sq=sq)
    m = float(rr.max())
    v = float((np.sum(sq * sq) / fs) ** 0.25)
    duration = x.shape[-1] / fs
    if a_w > 0.0:
        cf = float(np.max(np.abs(aw_sig)) / a_w)
        mr = m / a_w
        vr = v / (a_w * duration**0.25)
    else:
        cf = mr = vr = float("nan")
    adequate = bool(a_w > 0.0 and cf <= 9.0 and mr <= 1.5 and vr <= 1.75)
    std = WEIGHTINGS[weighting].standard
    desc = (f"ISO 2631-1:1997 basic method: {weighting}-weighted rms ({std}, {method} filter), "
            f"MTVV with {tau:g} s linear running rms, VDV, crest factor; comfort per Annex C")
    return Iso2631Result(
        weighting=weighting, a_w=a_w, rms=raw, mtvv=m, vdv=v, crest_factor=cf, mtvv_ratio=mr,
        vdv_ratio=vr, basic_method_adequate=adequate, comfort=comfort_band(a_w),
        standard=_STANDARD if weighting != "Wb" else "ISO 2631-1:1997 with Wb of ISO 2631-4:2001",
        method=desc, parameters={"tau_s": tau, "filter": method, "duration_s": duration},
    )

"""Frequency weightings for human vibration: ISO 2631-1 Wk, Wd, ISO 2631-4 / EN 12299 Wb and
Sperling's B filters, defined by their analogue transfer functions and realised digitally.

Analogue definitions (DESIGN §6; ISO 2631-1:1997 Annex A, ISO 8041-1:2017, ISO 2631-4:2001,
EN 12299:2009), with s = j2πf, ω_i = 2πf_i, Q1 = Q2 = 1/√2::

    H_h = 1 / (1 + ω1/(Q1 s) + (ω1/s)²)                    band-limiting high pass
    H_l = 1 / (1 + s/(Q2 ω2) + (s/ω2)²)                    band-limiting low pass
    H_t = K (1 + s/ω3) / (1 + s/(Q4 ω4) + (s/ω4)²)         acceleration-velocity transition
    H_s = (1 + s/(Q5 ω5) + (s/ω5)²) / (1 + s/(Q6 ω6) + (s/ω6)²) · (ω5/ω6)²   upward step
    W   = H_h · H_l · H_t · H_s

Sperling's weighting (Wz / B filter) is the rational function whose magnitude is the B_v(f) of
DESIGN §6; with p = jf (f in Hz)::

    B_v(p) = 0.588 (√1.911 p + 0.25 p²) / (1 + 1.563 p + 0.2777 p² + 0.0368 p³),  B_h = 1.25 B_v

(the minimum-phase realisation of that magnitude; its denominator is Hurwitz).

Digital realisation (chosen: ``method="iir"``)
----------------------------------------------
Bilinear transform with *per-root prewarping*: every analogue pole and zero is scaled so that
its natural frequency |p| becomes 2 fs tan(|p| / (2 fs)) before the transform (its Q is kept),
so each corner frequency of the standard lands exactly where it belongs in the digital filter
(the classical approach for ISO 8041 weighting filters). The overall gain is then matched to the
analogue magnitude at 4 Hz. The result is a causal, stable IIR filter in second-order sections,
started from rest (as a measuring instrument is), cheap on long records and on 2-D arrays of
many channels. Its error grows only towards the Nyquist frequency (frequency warping between
the corners). Against the analogue definition, 0.5–40 Hz / 40–80 Hz:

=========  ======================  ======================
fs         ISO Wk, Wd, Wb          Sperling Bv, Bh
=========  ======================  ======================
2 kHz      0.1 % 0.25° / 0.4 % 0.3°   0.13 % / 0.5 %
1 kHz      0.4 % 1.0° / 1.4 % 1.3°    0.5 % / 2.1 %
500 Hz     1.6 % 4.2° / 5.8 % 5.3°    2.1 % / 8.6 %
=========  ======================  ======================

(tested at 1 and 2 kHz; ISO 8041 allows ±0.5 dB ≈ 6 % in the pass band). Below 1 kHz prefer
``method="fft"``, which multiplies the spectrum of the zero-padded record by the analogue
response itself: exact at every frequency, but acausal (each output sample sees the whole
record) and twice the record length in memory.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy import fft as sp_fft
from scipy import signal

from flexride.analysis._common import check_nyquist, check_rate, check_signal
from flexride.errors import AnalysisError

__all__ = [
    "WEIGHTINGS",
    "WeightingDef",
    "apply_weighting",
    "weighting_response",
    "weighting_sos",
    "weighting_zpk",
]

_Q1 = _Q2 = 1.0 / math.sqrt(2.0)
_F_REF = 4.0  # Hz, frequency at which the digital gain is matched to the analogue one

WeightingMethod = Literal["iir", "fft"]


@dataclass(frozen=True)
class WeightingDef:
    """Parameters of one frequency weighting.

    Attributes
    ----------
    name : str
        ``"Wk"``, ``"Wd"``, ``"Wb"``, ``"Bv"`` or ``"Bh"``.
    description : str
        What the weighting is for.
    standard : str
        The standard (edition) that defines it.
    f1, f2, f3, f4, q4, f5, q5, f6, q6, k : float
        ISO 2631 / ISO 8041 parameters (Hz, -); ``f5 = f6 = inf`` means no upward step.
        NaN for Sperling's B filters, which are not of this form.
    min_rate : float
        Lowest sample rate (Hz) the digital realisation accepts: 2.5 × the highest
        characteristic frequency (the band-limiting 100 Hz of ISO weightings, 40 Hz of the
        Sperling band for the B filters).
    """

    name: str
    description: str
    standard: str
    f1: float = math.nan
    f2: float = math.nan
    f3: float = math.nan
    f4: float = math.nan
    q4: float = math.nan
    f5: float = math.inf
    q5: float = math.nan
    f6: float = math.inf
    q6: float = math.nan
    k: float = 1.0
    min_rate: float = 250.0


WEIGHTINGS: dict[str, WeightingDef] = {
    "Wk": WeightingDef(
        "Wk", "vertical (z) whole-body vibration, seated/standing/recumbent",
        "ISO 2631-1:1997 / ISO 8041-1:2017",
        f1=0.4, f2=100.0, f3=12.5, f4=12.5, q4=0.63, f5=2.37, q5=0.91, f6=3.35, q6=0.91, k=1.0),
    "Wd": WeightingDef(
        "Wd", "horizontal (x, y) whole-body vibration", "ISO 2631-1:1997 / ISO 8041-1:2017",
        f1=0.4, f2=100.0, f3=2.0, f4=2.0, q4=0.63, k=1.0),
    "Wb": WeightingDef(
        "Wb", "vertical (z) vibration in rail vehicles", "ISO 2631-4:2001 / EN 12299:2009",
        f1=0.4, f2=100.0, f3=16.0, f4=16.0, q4=0.55, f5=2.5, q5=0.9, f6=4.0, q6=0.95, k=1.024),
    "Bv": WeightingDef(
        "Bv", "Sperling ride-index weighting, vertical (B_v)", "Sperling / UIC 513 (DESIGN §6)",
        min_rate=100.0),
    "Bh": WeightingDef(
        "Bh", "Sperling ride-index weighting, lateral (B_h = 1.25 B_v)",
        "Sperling / UIC 513 (DESIGN §6)", min_rate=100.0),
}

# Sperling B_v as a rational function of p = j f (f in Hz), DESIGN §6.
_B_NUM = (0.25, math.sqrt(1.911), 0.0)  # 0.25 p² + √1.911 p (highest power first)
_B_DEN = (0.0368, 0.2777, 1.563, 1.0)
_B_GAIN = {"Bv": 0.588, "Bh": 1.25 * 0.588}


def _get(name: str) -> WeightingDef:
    try:
        return WEIGHTINGS[name]
    except KeyError:
        raise AnalysisError(
            f"unknown weighting {name!r}; choose one of {', '.join(WEIGHTINGS)}"
        ) from None


def weighting_response(name: str, f: np.ndarray | float) -> np.ndarray:
    """Analogue frequency response of a weighting, evaluated from its standard definition.

    Parameters
    ----------
    name : str
        ``"Wk"``, ``"Wd"``, ``"Wb"``, ``"Bv"`` or ``"Bh"``.
    f : array_like
        Frequencies in Hz (≥ 0).

    Returns
    -------
    numpy.ndarray
        Complex response H(j2πf) (dimensionless: weighted acceleration per acceleration).
    """
    w = _get(name)
    f = np.asarray(f, dtype=np.float64)
    if name in _B_GAIN:
        p = 1j * f
        num = np.polyval(_B_NUM, p)
        den = np.polyval(_B_DEN, p)
        return _B_GAIN[name] * num / den
    s = 2j * np.pi * f
    w1, w2, w3, w4 = (2 * np.pi * fi for fi in (w.f1, w.f2, w.f3, w.f4))
    with np.errstate(divide="ignore", invalid="ignore"):
        hh = 1.0 / (1.0 + w1 / (_Q1 * s) + (w1 / s) ** 2)
    hh = np.where(f == 0.0, 0.0, hh)
    hl = 1.0 / (1.0 + s / (_Q2 * w2) + (s / w2) ** 2)
    ht = w.k * (1.0 + s / w3) / (1.0 + s / (w.q4 * w4) + (s / w4) ** 2)
    hs: float | NDArray[np.complex128]
    if math.isinf(w.f5):
        hs = 1.0
    else:
        w5, w6 = 2 * np.pi * w.f5, 2 * np.pi * w.f6
        hs = (1.0 + s / (w.q5 * w5) + (s / w5) ** 2) / (1.0 + s / (w.q6 * w6) + (s / w6) ** 2)
        hs = hs * (w5 / w6) ** 2
    return hh * hl * ht * hs


def _quad_roots(w: float, q: float) -> np.ndarray:
    """Roots of s² + (ω/Q) s + ω²."""
    return np.roots([1.0, w / q, w * w]).astype(complex)


def weighting_zpk(name: str) -> tuple[np.ndarray, np.ndarray, float]:
    """Analogue zeros, poles (rad/s) and gain of a weighting.

    Returns
    -------
    z, p : numpy.ndarray
        Complex zeros and poles in rad/s.
    k : float
        Gain, so that H(s) = k Π(s − z) / Π(s − p).
    """
    w = _get(name)
    if name in _B_GAIN:
        # p = s / (2π): rescale the polynomial coefficients to powers of s.
        c = 2.0 * np.pi
        num = np.array(_B_NUM) / c ** np.arange(len(_B_NUM) - 1, -1, -1)
        den = np.array(_B_DEN) / c ** np.arange(len(_B_DEN) - 1, -1, -1)
        z = np.roots(np.trim_zeros(num, "b")).astype(complex)
        z = np.concatenate([z, np.zeros(len(num) - len(np.trim_zeros(num, "b")), complex)])
        p = np.roots(den).astype(complex)
        k = _B_GAIN[name] * num[0] / den[0]
        return z, p, float(k)
    w1, w2, w3, w4 = (2 * np.pi * fi for fi in (w.f1, w.f2, w.f3, w.f4))
    zeros = [np.zeros(2, complex), np.array([-w3], complex)]
    poles = [_quad_roots(w1, _Q1), _quad_roots(w2, _Q2), _quad_roots(w4, w.q4)]
    k = w2 * w2 * w.k * w4 * w4 / w3
    if not math.isinf(w.f5):
        w5, w6 = 2 * np.pi * w.f5, 2 * np.pi * w.f6
        zeros.append(_quad_roots(w5, w.q5))
        poles.append(_quad_roots(w6, w.q6))
    return np.concatenate(zeros), np.concatenate(poles), float(k)


def _prewarp(roots: np.ndarray, fs: float) -> np.ndarray:
    """Scale each root so its natural frequency |r| maps exactly under the bilinear transform."""
    out = np.array(roots, dtype=complex)
    mag = np.abs(out)
    nz = mag > 0.0
    out[nz] *= 2.0 * fs * np.tan(mag[nz] / (2.0 * fs)) / mag[nz]
    return out


def weighting_sos(name: str, fs: float) -> np.ndarray:
    """Digital realisation of a weighting as second-order sections (bilinear, prewarped).

    Parameters
    ----------
    name : str
        ``"Wk"``, ``"Wd"``, ``"Wb"``, ``"Bv"`` or ``"Bh"``.
    fs : float
        Sample rate in Hz; at least :attr:`WeightingDef.min_rate`.

    Returns
    -------
    numpy.ndarray
        Second-order sections, shape ``(n_sections, 6)``, for :func:`scipy.signal.sosfilt`.

    Raises
    ------
    AnalysisError
        Unknown weighting or sample rate too low.
    """
    return _weighting_sos_cached(name, _check_weighting_rate(name, fs)).copy()


def _check_weighting_rate(name: str, fs: float) -> float:
    wdef = _get(name)
    fs = check_rate(fs)
    check_nyquist(fs, wdef.min_rate / 2.5, f"the {name} weighting", factor=2.5)
    return fs


_SOS_CACHE: dict[tuple[str, float], np.ndarray] = {}


def _weighting_sos_cached(name: str, fs: float) -> np.ndarray:
    key = (name, fs)
    sos = _SOS_CACHE.get(key)
    if sos is None:
        z, p, k = weighting_zpk(name)
        zd, pd, kd = signal.bilinear_zpk(_prewarp(z, fs), _prewarp(p, fs), k, fs)
        _, h_d = signal.freqz_zpk(zd, pd, kd, worN=[_F_REF], fs=fs)
        h_a = weighting_response(name, _F_REF)
        kd = kd * float(np.abs(h_a) / np.abs(h_d[0]))
        sos = signal.zpk2sos(zd, pd, kd)
        if len(_SOS_CACHE) > 64:
            _SOS_CACHE.clear()
        _SOS_CACHE[key] = sos
    return sos


def apply_weighting(
    x: np.ndarray, fs: float, name: str, method: WeightingMethod = "iir"
) -> np.ndarray:
    """Frequency-weight an acceleration record.

    Parameters
    ----------
    x : array_like
        Acceleration in m/s², shape ``(n,)`` or ``(m, n)`` (samples along the last axis).
    fs : float
        Sample rate in Hz.
    name : str
        ``"Wk"``, ``"Wd"``, ``"Wb"``, ``"Bv"`` or ``"Bh"``.
    method : {"iir", "fft"}
        ``"iir"`` (default): causal prewarped-bilinear filter started from rest.
        ``"fft"``: multiplication by the analogue response on the zero-padded record.

    Returns
    -------
    numpy.ndarray
        Weighted acceleration in m/s², same shape as ``x``.
    """
    fs = _check_weighting_rate(name, fs)
    x = check_signal(x, fs, name="acceleration", method=f"{name} weighting")
    if method == "iir":
        return signal.sosfilt(_weighting_sos_cached(name, fs), x, axis=-1)
    if method == "fft":
        n = x.shape[-1]
        nfft = sp_fft.next_fast_len(2 * n, real=True)
        spec = sp_fft.rfft(x, nfft, axis=-1)
        spec *= weighting_response(name, sp_fft.rfftfreq(nfft, 1.0 / fs))
        return sp_fft.irfft(spec, nfft, axis=-1)[..., :n]
    raise AnalysisError(f"unknown weighting method {method!r}; use 'iir' or 'fft'")

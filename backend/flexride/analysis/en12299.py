"""Passenger ride comfort per EN 12299:2009: continuous comfort C_c and mean comfort N_MV.

Weightings: Wd for the horizontal directions x, y and Wb for the vertical z, each including the
0.4–100 Hz band limitation (:mod:`flexride.analysis.weighting`), measured on the floor.

Continuous comfort
    C_Cx(t) = a_XP^Wd(t), C_Cy(t) = a_YP^Wd(t), C_Cz(t) = a_ZP^Wb(t): the rms of the weighted
    acceleration over the preceding 5 s, evaluated every second (``step_s``), in m/s².
    Scale: C_c < 0.20 very comfortable, 0.20–0.30 comfortable, 0.30–0.40 medium,
    ≥ 0.40 less comfortable.

Mean comfort, standard method (DESIGN §6)
    N_MV = 6 √((a_XP95^Wd)² + (a_YP95^Wd)² + (a_ZP95^Wb)²), each a_P95 the 95th percentile of the
    rms values of consecutive, non-overlapping 5 s blocks over a 5 min evaluation window
    (60 blocks). Scale: N_MV < 1.5 very comfortable, 1.5–2.5 comfortable, 2.5–3.5 medium,
    3.5–4.5 uncomfortable, ≥ 4.5 very uncomfortable.

    Percentile rule (pinned): nearest rank, the ⌈0.95 n⌉-th smallest of n block values
    (``numpy.percentile(..., method="inverted_cdf")``): the 57th of 60 in a full window.
    Blocks start at t = 0; a trailing part shorter than 5 s is not used.
    Runs of at least 5 min: one N_MV per complete 5 min window, the reported value is the
    largest; blocks after the last complete window are not used (their duration is reported).
    **Runs shorter than 5 min** (at least one 5 s block): one evaluation over all complete
    blocks with the same nearest-rank rule (with fewer than 20 blocks this is the largest block
    rms, a conservative estimate); the result is flagged ``short_run = True``.
    A missing direction (simulations often have no longitudinal channel) contributes 0 and is
    listed in ``directions_used``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.analysis._common import check_rate, check_signal
from flexride.analysis.iso2631 import _window_rms
from flexride.analysis.weighting import WeightingMethod, apply_weighting
from flexride.errors import AnalysisError

__all__ = [
    "CC_SCALE",
    "NMV_SCALE",
    "ContinuousComfort",
    "MeanComfort",
    "cc_scale",
    "continuous_comfort",
    "mean_comfort",
    "nmv_scale",
]

_STANDARD = "EN 12299:2009"

#: Continuous comfort scale: (upper limit m/s², label); the last applies above.
CC_SCALE: tuple[tuple[float, str], ...] = (
    (0.20, "very comfortable"),
    (0.30, "comfortable"),
    (0.40, "medium"),
    (math.inf, "less comfortable"),
)
#: Mean comfort scale: (upper limit, label).
NMV_SCALE: tuple[tuple[float, str], ...] = (
    (1.5, "very comfortable"),
    (2.5, "comfortable"),
    (3.5, "medium"),
    (4.5, "uncomfortable"),
    (math.inf, "very uncomfortable"),
)

PERCENTILE_RULE = ("nearest rank: the ceil(0.95 n)-th smallest of the n 5 s block rms values "
                   "(57th of 60)")


def _scale(value: float, scale: tuple[tuple[float, str], ...], what: str) -> str:
    v = float(value)
    if not math.isfinite(v) or v < 0.0:
        raise AnalysisError(f"{what} must be finite and non-negative, got {value!r}")
    for limit, label in scale:
        if v < limit:
            return label
    return scale[-1][1]


def cc_scale(value: float) -> str:
    """EN 12299 continuous-comfort label for C_c in m/s²."""
    return _scale(value, CC_SCALE, "continuous comfort")


def nmv_scale(value: float) -> str:
    """EN 12299 mean-comfort label for N_MV (-)."""
    return _scale(value, NMV_SCALE, "mean comfort")


def _weighting_for(direction: str) -> tuple[str, str]:
    d = str(direction).lower()
    if d in ("x", "longitudinal"):
        return "x", "Wd"
    if d in ("y", "lateral"):
        return "y", "Wd"
    if d in ("z", "vertical"):
        return "z", "Wb"
    raise AnalysisError(f"direction must be 'x', 'y' or 'z', got {direction!r}")


@dataclass
class ContinuousComfort:
    """EN 12299 continuous comfort of one direction.

    Attributes
    ----------
    direction : str
        ``"x"``, ``"y"`` or ``"z"``.
    weighting : str
        ``"Wd"`` or ``"Wb"``.
    times : numpy.ndarray
        End time of each 5 s window in s.
    values : numpy.ndarray
        C_c(t) in m/s².
    maximum : float
        Largest C_c (m/s²); ``time_of_maximum`` its time (s).
    scale : str
        EN 12299 label of the maximum.
    """

    direction: str
    weighting: str
    times: np.ndarray
    values: np.ndarray
    maximum: float
    time_of_maximum: float
    scale: str
    window_s: float = 5.0
    step_s: float = 1.0
    standard: str = _STANDARD
    method: str = ""


def continuous_comfort(
    x: np.ndarray,
    fs: float,
    direction: str,
    *,
    window_s: float = 5.0,
    step_s: float = 1.0,
    method: WeightingMethod = "iir",
    weighted: np.ndarray | None = None,
) -> ContinuousComfort:
    """EN 12299 continuous comfort C_c(t): 5 s rms of the weighted floor acceleration.

    Parameters
    ----------
    x : array_like
        Floor acceleration in m/s², shape ``(n,)``; at least ``window_s`` long.
    fs : float
        Sample rate in Hz (≥ 250 Hz).
    direction : {"x", "y", "z"}
        Direction, choosing Wd (x, y) or Wb (z).
    window_s, step_s : float
        Window length and update interval in s (EN 12299: 5 s, evaluated every 1 s).
    method : {"iir", "fft"}
        Filter realisation.
    weighted : array_like, optional
        Already-weighted acceleration (skips the filtering; used by :func:`analyze`).
    """
    d, wname = _weighting_for(direction)
    fs = check_rate(fs)
    x = check_signal(x, fs, name="acceleration", min_duration=window_s, ndim=(1,),
                     method=f"EN 12299 continuous comfort ({window_s:g} s windows)")
    aw = apply_weighting(x, fs, wname, method=method) if weighted is None else weighted
    t, v = _window_rms(aw, fs, max(1, round(window_s * fs)), max(1, round(step_s * fs)))
    t = t + 1.0 / fs  # end of the window (the last sample's interval ends 1/fs later)
    i = int(np.argmax(v))
    desc = (f"EN 12299:2009 continuous comfort: rms of the {wname}-weighted acceleration over "
            f"{window_s:g} s, every {step_s:g} s ({method} filter)")
    return ContinuousComfort(direction=d, weighting=wname, times=t, values=v,
                             maximum=float(v[i]), time_of_maximum=float(t[i]),
                             scale=cc_scale(float(v[i])), window_s=window_s, step_s=step_s,
                             method=desc)


@dataclass
class MeanComfort:
    """EN 12299 mean comfort N_MV (standard method).

    Attributes
    ----------
    value : float
        N_MV (-), the largest over the evaluation windows.
    scale : str
        EN 12299 label of ``value``.
    windows : list of dict
        Per evaluation window: ``start_s``, ``end_s``, ``n_blocks``, ``a_xp95``, ``a_yp95``,
        ``a_zp95`` (m/s²) and ``n_mv``.
    short_run : bool
        True if the run is shorter than one 5 min window (see module docs).
    directions_used : list of str
        Directions that had data; missing ones count as 0.
    unused_s : float
        Duration at the end of the run that no evaluation window covers (s).
    """

    value: float
    scale: str
    windows: list[dict[str, Any]]
    short_run: bool
    directions_used: list[str]
    unused_s: float
    percentile_rule: str = PERCENTILE_RULE
    block_s: float = 5.0
    window_s: float = 300.0
    standard: str = _STANDARD
    method: str = ""
    parameters: dict[str, Any] = field(default_factory=dict)


def _p95(values: np.ndarray) -> np.ndarray:
    return np.percentile(values, 95.0, axis=-1, method="inverted_cdf")


def mean_comfort(
    fs: float,
    *,
    x: np.ndarray | None = None,
    y: np.ndarray | None = None,
    z: np.ndarray | None = None,
    block_s: float = 5.0,
    window_s: float = 300.0,
    method: WeightingMethod = "iir",
    weighted: dict[str, np.ndarray] | None = None,
) -> MeanComfort:
    """EN 12299 mean comfort N_MV from floor accelerations (standard method).

    Parameters
    ----------
    fs : float
        Sample rate in Hz (≥ 250 Hz).
    x, y, z : array_like, optional
        Floor accelerations in m/s² (same length); at least one is needed.
    block_s : float
        Block length for the rms values (EN 12299: 5 s).
    window_s : float
        Evaluation window (EN 12299: 5 min).
    method : {"iir", "fft"}
        Filter realisation.
    weighted : dict, optional
        Already-weighted signals by direction (skips the filtering; used by :func:`analyze`).

    Returns
    -------
    MeanComfort

    Raises
    ------
    AnalysisError
        No direction given, different lengths, or a record shorter than one block.
    """
    fs = check_rate(fs)
    given = {d: a for d, a in (("x", x), ("y", y), ("z", z)) if a is not None}
    if not given:
        raise AnalysisError("mean comfort needs at least one of the x, y, z accelerations")
    sig, n = _comfort_weighted(given, fs, block_s, method, weighted)
    nb = max(1, round(block_s * fs))
    n_blocks = n // nb
    if n_blocks < 1:
        raise AnalysisError(f"mean comfort: record shorter than one {block_s:g} s block")
    block_rms = {d: np.sqrt(np.mean(s[: n_blocks * nb].reshape(n_blocks, nb) ** 2, axis=1))
                 for d, s in sig.items()}
    per_window = max(1, round(window_s / block_s))
    short = n_blocks < per_window
    if short:
        groups = [(0, n_blocks)]
    else:
        groups = [(i, i + per_window) for i in range(0, n_blocks - per_window + 1, per_window)]
    windows = [_nmv_window(block_rms, b0, b1, nb, fs) for b0, b1 in groups]
    value = max(w["n_mv"] for w in windows)
    unused = (n - groups[-1][1] * nb) / fs
    desc = _nmv_description(given, method, block_s, window_s, n_blocks, per_window, short)
    return MeanComfort(value=value, scale=nmv_scale(value), windows=windows, short_run=short,
                       directions_used=sorted(given), unused_s=unused, block_s=block_s,
                       window_s=window_s, method=desc,
                       parameters={"filter": method, "n_blocks": n_blocks})


def _comfort_weighted(given: dict[str, np.ndarray], fs: float, block_s: float,
                      method: WeightingMethod,
                      weighted: dict[str, np.ndarray] | None) -> tuple[dict[str, np.ndarray], int]:
    """The comfort-weighted floor accelerations (m/s²; Wd for x and y, Wb for z) by direction,
    and their common number of samples.

    Directions found in ``weighted`` are taken from there instead of being filtered.

    Raises
    ------
    AnalysisError
        A record shorter than one block of ``block_s`` s, or records of different lengths.
    """
    sig: dict[str, np.ndarray] = {}
    n = None
    for d, a in given.items():
        a = check_signal(a, fs, name=f"{d} acceleration", min_duration=block_s, ndim=(1,),
                         method=f"EN 12299 mean comfort ({block_s:g} s blocks)")
        if n is not None and a.shape[-1] != n:
            raise AnalysisError("mean comfort: x, y, z accelerations must have the same length")
        n = a.shape[-1]
        if weighted is not None and d in weighted:
            sig[d] = np.asarray(weighted[d], dtype=np.float64)
        else:
            sig[d] = apply_weighting(a, fs, _weighting_for(d)[1], method=method)
    assert n is not None
    return sig, n


def _nmv_window(block_rms: dict[str, np.ndarray], b0: int, b1: int, nb: int,
                fs: float) -> dict[str, Any]:
    """N_MV of one evaluation window, blocks ``b0`` to ``b1`` (exclusive) of ``nb`` samples:
    start and end (s), number of blocks, the 95th percentiles a_XP95, a_YP95, a_ZP95 of the
    block rms values (m/s²; 0 for a missing direction) and ``n_mv``.
    """
    p = {d: float(_p95(block_rms[d][b0:b1])) if d in block_rms else 0.0 for d in "xyz"}
    nmv = 6.0 * math.sqrt(p["x"] ** 2 + p["y"] ** 2 + p["z"] ** 2)
    return {"start_s": b0 * nb / fs, "end_s": b1 * nb / fs, "n_blocks": b1 - b0,
            "a_xp95": p["x"], "a_yp95": p["y"], "a_zp95": p["z"], "n_mv": nmv}


def _nmv_description(given: dict[str, np.ndarray], method: WeightingMethod, block_s: float,
                     window_s: float, n_blocks: int, per_window: int, short: bool) -> str:
    """The ``method`` text of a mean comfort: formula, filter, block (s) and window (min)
    lengths, and whether the run was short or directions were missing.
    """
    missing = [d for d in "xyz" if d not in given]
    desc = (f"EN 12299:2009 mean comfort, standard method: N_MV = 6·√(a_XP95² + a_YP95² + "
            f"a_ZP95²) (Wd x/y, Wb z, {method} filter), {block_s:g} s blocks, "
            f"{window_s / 60:g} min windows, P95 by nearest rank")
    if short:
        desc += (f"; SHORT RUN: {n_blocks} block(s) < {per_window}, one evaluation over the "
                 "whole run")
    if missing:
        desc += f"; missing direction(s) {', '.join(missing)} taken as 0"
    return desc

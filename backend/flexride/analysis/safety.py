"""Running safety from wheel–rail forces: derailment quotient Y/Q, wheel unloading ΔQ/Q and
the track-shifting force ΣY, with the limits of DESIGN §6.

Names follow EN 14363: **Q** is the vertical wheel force, **Y** the lateral wheel–rail force.
GB 5599 writes the vertical force P and the lateral force Q: its derailment coefficient Q/P is
the derailment quotient Y/Q here, its wheel unloading rate ΔP/P is ΔQ/Q (:data:`CONVENTION`).

Forces (flexride channels): ``wheelset<i>.<side>.force.z`` is the vertical wheel force Q (N,
positive in compression), ``wheelset<i>.<side>.force.y`` the lateral wheel–rail force Y (N, in
track y, left positive, exerted by the rail on the wheel).

Quantities and limits
---------------------
Derailment quotient Y/Q (GB 5599-1985 allowable limit 1.2 of its Q/P)
    Y is the lateral force *towards the track centre*: −F_y on the left wheel, +F_y on the right
    wheel (the flange-climbing sense: the rail pushes the climbing wheel's flange inwards);
    ``side=None`` uses |F_y|. Q is floored at 1 % of its mean to keep the ratio finite during
    wheel lift (counted in ``notes``).
Wheel unloading ΔQ/Q (GB 5599-1985 allowable limit 0.65 of its ΔP/P)
    ΔQ/Q = (Q0 − Q)/Q0 with Q0 the static wheel force; only unloading counts.
Track-shifting force ΣY (EN 14363 Prud'homme limit 10 + 2Q0/3 kN)
    ΣY = F_y,left + F_y,right (kN), |ΣY| compared with 10 + 2Q0/3, 2Q0 the static axle load in
    kN (Prud'homme's P0).

Processing (pinned, after the EN 14363 / UIC 518 table for (Y/Q)_2m and (ΣY)_2m)
    1. low pass at **20 Hz**: 4th-order Butterworth, forward–backward (zero phase);
    2. Y/Q and ΣY: **sliding mean over 2 m** of track, evaluated every **0.5 m** (window and
       step converted to samples with the running speed); ΔQ/Q: no sliding mean (EN 14363
       evaluates the vertical force Q after the 20 Hz low pass only);
    3. assessed value: the **maximum** of the processed signal (GB 5599 compares the maximum;
       the EN 14363 statistic, the 99.85th percentile, is reported as ``p99_85``), compared
       with the limit.
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Final, TypedDict

import numpy as np
from scipy import signal

from flexride.analysis._common import check_nyquist, check_rate, check_signal
from flexride.errors import AnalysisError
from flexride.results import Channel

if TYPE_CHECKING:
    from flexride.results import Results

__all__ = [
    "CONVENTION",
    "SAFETY_DEFAULTS",
    "SAFETY_LIMITS",
    "SAFETY_SYMBOLS",
    "RunningSafety",
    "SafetyIndex",
    "derailment_coefficient",
    "lateral_force_limit",
    "nadal_limit",
    "running_safety",
    "wheel_unloading",
    "wheelset_lateral_force",
]

#: Limits of DESIGN §6.
SAFETY_LIMITS = {"derailment_coefficient": 1.2, "wheel_unloading": 0.65}

#: Symbol and name of each index for people (EN 14363 names: Q vertical, Y lateral), the one
#: source of the CLI's tables and the dashboard (``symbol`` and ``title`` of every index).
SAFETY_SYMBOLS: Final[dict[str, tuple[str, str]]] = {
    "derailment_coefficient": ("Y/Q", "derailment quotient"),
    "wheel_unloading": ("ΔQ/Q", "wheel unloading"),
    "wheelset_lateral_force": ("ΣY", "track-shifting force"),
}

#: The force convention in one line, with GB 5599's names of the same quantities.
CONVENTION: Final = ("EN 14363 names: Q vertical wheel force, Y lateral wheel force, derailment "
                     "quotient Y/Q, wheel unloading ΔQ/Q, track-shifting force ΣY. GB 5599 writes "
                     "P for the vertical and Q for the lateral force: its derailment coefficient "
                     "Q/P is Y/Q, its wheel unloading rate ΔP/P is ΔQ/Q.")


def nadal_limit(flange_angle_rad: float, friction: float) -> float:
    """Nadal's limit of the derailment quotient Y/Q of a flanging wheel (-).

    Flange climbing starts when the lateral force Y over the vertical load Q exceeds
    (tan γ − μ)/(1 + μ·tan γ), γ the largest flange contact angle and μ the wheel–rail
    friction coefficient (Nadal 1908; EN 14363 derives its limit 0.8 from it with a margin).

    Parameters
    ----------
    flange_angle_rad : float
        Largest flange contact angle of the wheel on the rail (rad), 0 < γ < π/2.
    friction : float
        Friction coefficient μ ≥ 0 (-).
    """
    if not (0.0 < flange_angle_rad < 0.5 * math.pi) or not (friction >= 0.0):
        raise AnalysisError(f"Nadal's limit needs 0 < flange angle < 90° and μ ≥ 0, got "
                            f"{math.degrees(flange_angle_rad):.4g}° and {friction!r}")
    t = math.tan(flange_angle_rad)
    return (t - friction) / (1.0 + friction * t)


class SafetyDefaults(TypedDict):
    """Processing parameters of the running-safety indices."""

    lowpass_hz: float
    window_m: float
    step_m: float
    order: int


#: Pinned processing parameters.
SAFETY_DEFAULTS: Final[SafetyDefaults] = {
    "lowpass_hz": 20.0, "window_m": 2.0, "step_m": 0.5, "order": 4
}


@dataclass
class SafetyIndex:
    """One running-safety quantity at one wheel or wheelset.

    Attributes
    ----------
    name : str
        ``"derailment_coefficient"``, ``"wheel_unloading"`` or ``"wheelset_lateral_force"``.
    location : str
        ``"wheelset1.left"``, ``"wheelset2"``...
    value : float
        Assessed value (maximum of the processed signal) in ``unit``.
    limit : float
        Limit in ``unit``.
    utilisation : float
        value / limit (-).
    passed : bool
        value ≤ limit.
    p99_85 : float
        99.85th percentile of the processed signal.
    time_of_max : float
        Time of the maximum in s (centre of the sliding window where one is used).
    standard, processing : str
        Where the limit comes from and how the signal was processed.
    times, series : numpy.ndarray or None
        The processed signal (only kept when requested).
    symbol, title : str
        For people: ``"Y/Q"`` and ``"derailment quotient"`` etc. (:data:`SAFETY_SYMBOLS`;
        filled from ``name`` when not given).
    """

    name: str
    location: str
    value: float
    limit: float
    utilisation: float
    passed: bool
    p99_85: float
    time_of_max: float
    unit: str
    standard: str
    processing: str
    notes: list[str] = field(default_factory=list)
    times: np.ndarray | None = None
    series: np.ndarray | None = None
    symbol: str = ""
    title: str = ""

    def __post_init__(self) -> None:
        """Fill ``symbol`` and ``title`` from ``name`` when they are not given."""
        symbol, title = SAFETY_SYMBOLS.get(self.name, (self.name, self.name.replace("_", " ")))
        self.symbol = self.symbol or symbol
        self.title = self.title or title


@functools.lru_cache(maxsize=32)
def _butter_low(order: int, cutoff: float, fs: float) -> np.ndarray:
    return signal.butter(order, cutoff, btype="low", fs=fs, output="sos")


def _lowpass(x: np.ndarray, fs: float, cutoff: float, order: int) -> np.ndarray:
    """Zero-phase Butterworth low pass along the last axis."""
    check_nyquist(fs, cutoff, f"the {cutoff:g} Hz low pass of running-safety forces", factor=2.5)
    sos = _butter_low(int(order), float(cutoff), float(fs))
    padlen = min(x.shape[-1] - 1, 3 * (2 * len(sos) + 1) + int(3 * fs / cutoff))
    return signal.sosfiltfilt(sos, x, axis=-1, padlen=padlen)


def _sliding_mean(
    x: np.ndarray, fs: float, speed: float, window_m: float, step_m: float
) -> tuple[np.ndarray, np.ndarray]:
    """Sliding mean over ``window_m`` of track every ``step_m``; returns (centre times, means)."""
    if not (math.isfinite(speed) and speed > 0.0):
        raise AnalysisError(
            f"running speed must be positive (m/s) for a sliding window, got {speed!r}")
    nw = max(1, round(window_m / speed * fs))
    ns = max(1, round(step_m / speed * fs))
    if x.shape[-1] < nw:
        raise AnalysisError(
            f"record of {x.shape[-1] / fs:.3g} s is shorter than the {window_m:g} m sliding "
            f"window ({nw / fs:.3g} s at {speed:g} m/s)"
        )
    csum = np.concatenate([[0.0], np.cumsum(x)])
    ends = np.arange(nw, x.shape[-1] + 1, ns)
    return (ends - 0.5 * nw - 0.5) / fs, (csum[ends] - csum[ends - nw]) / nw


def _make_index(name: str, location: str, times: np.ndarray, series: np.ndarray, limit: float,
                unit: str, standard: str, processing: str, notes: list[str],
                keep_series: bool) -> SafetyIndex:
    i = int(np.argmax(series))
    value = float(series[i])
    return SafetyIndex(
        name=name, location=location, value=value, limit=float(limit),
        utilisation=value / limit if limit else float("nan"), passed=bool(value <= limit),
        p99_85=float(np.percentile(series, 99.85)), time_of_max=float(times[i]), unit=unit,
        standard=standard, processing=processing, notes=notes,
        times=times if keep_series else None, series=series if keep_series else None,
    )


def derailment_coefficient(
    lateral_force: np.ndarray,
    vertical_force: np.ndarray,
    fs: float,
    speed_mps: float,
    *,
    side: str | None = None,
    location: str = "",
    lowpass_hz: float = SAFETY_DEFAULTS["lowpass_hz"],
    window_m: float = SAFETY_DEFAULTS["window_m"],
    step_m: float = SAFETY_DEFAULTS["step_m"],
    keep_series: bool = False,
) -> SafetyIndex:
    """Derailment quotient Y/Q of one wheel (limit 1.2, GB 5599's Q/P).

    Parameters
    ----------
    lateral_force : array_like
        Lateral wheel–rail force Y = F_y on the wheel in N (track y, left positive).
    vertical_force : array_like
        Vertical wheel force Q in N (positive in compression).
    fs : float
        Sample rate in Hz.
    speed_mps : float
        Running speed in m/s (converts the 2 m window to samples).
    side : {"left", "right", None}
        Wheel side: Y = −F_y (left) or +F_y (right), the force towards the track centre;
        None uses |F_y|.
    location : str
        Label, e.g. ``"wheelset1.left"``.
    lowpass_hz, window_m, step_m : float
        Processing (module docs).
    keep_series : bool
        Keep the processed Y/Q signal in the result.
    """
    fs = check_rate(fs)
    q = check_signal(lateral_force, fs, name="lateral force", ndim=(1,), min_samples=8,
                     method="the derailment quotient Y/Q")
    p = check_signal(vertical_force, fs, name="vertical force", ndim=(1,), min_samples=8,
                     method="the derailment quotient Y/Q")
    if q.shape != p.shape:
        raise AnalysisError("lateral and vertical force records differ in length")
    if side not in ("left", "right", None):
        raise AnalysisError(f"side must be 'left', 'right' or None, got {side!r}")
    lp = _lowpass(np.vstack([q, p]), fs, lowpass_hz, SAFETY_DEFAULTS["order"])
    return _derailment_core(lp[0], lp[1], float(np.mean(p)), fs, speed_mps, side, location,
                            lowpass_hz, window_m, step_m, keep_series)


def _derailment_core(q_lp: np.ndarray, p_lp: np.ndarray, p_mean: float, fs: float,
                     speed_mps: float, side: str | None, location: str, lowpass_hz: float,
                     window_m: float, step_m: float, keep_series: bool) -> SafetyIndex:
    q_eff = -q_lp if side == "left" else q_lp if side == "right" else np.abs(q_lp)
    p_floor = 0.01 * abs(p_mean)
    if p_floor <= 0.0:
        raise AnalysisError("vertical wheel force Q is zero on average: no derailment quotient")
    lift = int(np.count_nonzero(p_lp < p_floor))
    ratio = q_eff / np.maximum(p_lp, p_floor)
    t, s = _sliding_mean(ratio, fs, speed_mps, window_m, step_m)
    notes = [f"wheel force Q below 1 % of its mean in {lift} sample(s) (floored)"] if lift else []
    sense = {"left": "Y = −F_y (towards track centre)", "right": "Y = +F_y (towards track centre)",
             None: "Y = |F_y|"}[side]
    proc = (f"{sense}; {lowpass_hz:g} Hz Butterworth low pass (order 4, zero phase) on Y and Q; "
            f"Y/Q sliding mean over {window_m:g} m every {step_m:g} m; maximum")
    return _make_index("derailment_coefficient", location, t, s,
                       SAFETY_LIMITS["derailment_coefficient"], "-",
                       "GB 5599-1985 allowable limit (DESIGN §6)", proc, notes, keep_series)


def wheel_unloading(
    vertical_force: np.ndarray,
    static_load: float,
    fs: float,
    *,
    location: str = "",
    lowpass_hz: float = SAFETY_DEFAULTS["lowpass_hz"],
    keep_series: bool = False,
    series_step_s: float | None = None,
) -> SafetyIndex:
    """Wheel unloading ΔQ/Q = (Q0 − Q)/Q0 of one wheel (limit 0.65, GB 5599's ΔP/P).

    Parameters
    ----------
    vertical_force : array_like
        Vertical wheel force Q in N.
    static_load : float
        Static wheel force Q0 in N (> 0).
    fs : float
        Sample rate in Hz.
    location : str
        Label.
    lowpass_hz : float
        Low-pass cut-off in Hz.
    keep_series : bool
        Keep the processed signal.
    series_step_s : float, optional
        Keep only the largest value of every block of this duration (s) in the series.
    """
    fs = check_rate(fs)
    p = check_signal(vertical_force, fs, name="vertical force", ndim=(1,), min_samples=8,
                     method="the wheel unloading ΔQ/Q")
    p0 = float(static_load)
    if not (math.isfinite(p0) and p0 > 0.0):
        raise AnalysisError(f"static wheel load must be positive (N), got {static_load!r}")
    p_lp = _lowpass(p, fs, lowpass_hz, SAFETY_DEFAULTS["order"])
    return _unloading_core(p_lp, p0, fs, location, lowpass_hz, keep_series, series_step_s)


def _unloading_core(p_lp: np.ndarray, p0: float, fs: float, location: str, lowpass_hz: float,
                    keep_series: bool, series_step_s: float | None) -> SafetyIndex:
    rate = (p0 - p_lp) / p0
    t = np.arange(p_lp.size) / fs
    proc = (f"ΔQ/Q = (Q0 − Q)/Q0, Q0 = {p0:.6g} N; {lowpass_hz:g} Hz Butterworth low pass "
            "(order 4, zero phase); maximum (unloading positive)")
    idx = _make_index("wheel_unloading", location, t, rate, SAFETY_LIMITS["wheel_unloading"],
                      "-", "GB 5599-1985 allowable limit (DESIGN §6)", proc, [], False)
    if keep_series:
        step = 1 if series_step_s is None else max(1, round(series_step_s * fs))
        nb = rate.size // step
        if step > 1 and nb >= 1:
            idx.series = rate[: nb * step].reshape(nb, step).max(axis=1)
            idx.times = (np.arange(nb) + 0.5) * step / fs
        else:
            idx.series, idx.times = rate, t
    return idx


def lateral_force_limit(static_axle_load: float) -> float:
    """EN 14363 (Prud'homme) track-shifting force limit 10 + 2Q0/3 in kN (2Q0 axle load in N)."""
    return 10.0 + float(static_axle_load) / 1000.0 / 3.0


def wheelset_lateral_force(
    lateral_force_left: np.ndarray,
    lateral_force_right: np.ndarray,
    static_axle_load: float,
    fs: float,
    speed_mps: float,
    *,
    location: str = "",
    lowpass_hz: float = SAFETY_DEFAULTS["lowpass_hz"],
    window_m: float = SAFETY_DEFAULTS["window_m"],
    step_m: float = SAFETY_DEFAULTS["step_m"],
    keep_series: bool = False,
) -> SafetyIndex:
    """Track-shifting force |ΣY| of a wheelset in kN against 10 + 2Q0/3 kN (EN 14363).

    Parameters
    ----------
    lateral_force_left, lateral_force_right : array_like
        Lateral wheel–rail forces on the two wheels in N (track y).
    static_axle_load : float
        Static axle load 2Q0 in N.
    fs : float
        Sample rate in Hz.
    speed_mps : float
        Running speed in m/s.
    location : str
        Label, e.g. ``"wheelset1"``.
    lowpass_hz, window_m, step_m : float
        Processing (module docs).
    keep_series : bool
        Keep the processed signal.
    """
    fs = check_rate(fs)
    yl = check_signal(lateral_force_left, fs, name="left lateral force", ndim=(1,),
                      min_samples=8, method="the track-shifting force ΣY")
    yr = check_signal(lateral_force_right, fs, name="right lateral force", ndim=(1,),
                      min_samples=8, method="the track-shifting force ΣY")
    if yl.shape != yr.shape:
        raise AnalysisError("left and right lateral force records differ in length")
    p0 = float(static_axle_load)
    if not (math.isfinite(p0) and p0 > 0.0):
        raise AnalysisError(f"static axle load must be positive (N), got {static_axle_load!r}")
    h = _lowpass(yl + yr, fs, lowpass_hz, SAFETY_DEFAULTS["order"]) / 1000.0
    return _lateral_core(h, p0, fs, speed_mps, location, lowpass_hz, window_m, step_m,
                         keep_series)


def _lateral_core(h: np.ndarray, p0: float, fs: float, speed_mps: float, location: str,
                  lowpass_hz: float, window_m: float, step_m: float,
                  keep_series: bool) -> SafetyIndex:
    t, s = _sliding_mean(h, fs, speed_mps, window_m, step_m)
    proc = (f"ΣY = F_y,left + F_y,right; {lowpass_hz:g} Hz Butterworth low pass (order 4, zero "
            f"phase); sliding mean over {window_m:g} m every {step_m:g} m; maximum of |ΣY|")
    return _make_index("wheelset_lateral_force", location, t, np.abs(s),
                       lateral_force_limit(p0), "kN",
                       f"EN 14363 limit 10 + 2Q0/3 kN, 2Q0 = {p0 / 1000:.4g} kN (DESIGN §6)",
                       proc, [], keep_series)


@dataclass
class RunningSafety:
    """Running-safety indices of a run.

    Attributes
    ----------
    indices : list of SafetyIndex
        Every quantity at every wheel / wheelset.
    passed : bool
        All indices within their limits.
    static_wheel_loads : dict
        Static wheel load per wheel (N) and where it came from.
    processing : dict
        Pinned processing parameters.
    notes : list of str
        What was skipped or floored.
    nadal : dict or None
        With real wheel profiles: the flange angle (``flange_angle_deg``), the friction
        coefficient, Nadal's limit of Y/Q for them and the largest Y/Q of the run against it
        (``worst``, ``utilisation``, ``location``); None for the conical tread (no flange
        angle).
    """

    indices: list[SafetyIndex]
    passed: bool
    static_wheel_loads: dict[str, Any]
    processing: dict[str, Any]
    notes: list[str] = field(default_factory=list)
    nadal: dict[str, Any] | None = None

    def worst(self, name: str) -> SafetyIndex | None:
        """The index of one kind with the highest utilisation, or None."""
        cands = [i for i in self.indices if i.name == name]
        return max(cands, key=lambda i: i.utilisation) if cands else None


_WHEELSET = re.compile(r"^wheelset(\d+)$")


def _static_loads(meta: dict[str, Any], n_ws: list[int], channels: dict[str, np.ndarray]
                  ) -> tuple[dict[str, float], str]:
    raw = meta.get("static_wheel_loads")
    loads: dict[str, float] = {}
    if raw is not None:
        arr = np.asarray(raw, dtype=np.float64)
        if arr.ndim == 1 and arr.size == 2 * len(n_ws):
            arr = arr.reshape(-1, 2)
        if arr.ndim == 2 and arr.shape == (len(n_ws), 2):
            for k, ws in enumerate(n_ws):
                loads[f"wheelset{ws}.left"] = float(arr[k, 0])
                loads[f"wheelset{ws}.right"] = float(arr[k, 1])
            return loads, "results.meta['static_wheel_loads']"
    for ws in n_ws:
        for side in ("left", "right"):
            loads[f"wheelset{ws}.{side}"] = float(np.mean(channels[f"wheelset{ws}.{side}.force.z"]))
    src = "mean of force.z over the run"
    if raw is not None:
        src += " (meta['static_wheel_loads'] has an unexpected shape)"
    return loads, src


def _speed_of(results: Results) -> float:
    v = results.running_speed()
    if v is None:
        raise AnalysisError("running speed unknown: no meta['speed_mps'] and no distance axis")
    return v


def running_safety(
    results: Results,
    *,
    lowpass_hz: float = SAFETY_DEFAULTS["lowpass_hz"],
    window_m: float = SAFETY_DEFAULTS["window_m"],
    step_m: float = SAFETY_DEFAULTS["step_m"],
    keep_series: bool = False,
) -> RunningSafety | None:
    """Running-safety indices of every wheelset in a run (None if it has no wheel forces).

    Uses ``wheelset<i>.<side>.force.z`` / ``.force.y``; static wheel loads from
    ``results.meta["static_wheel_loads"]`` (``[[left, right], ...]`` or flat per wheelset and
    side, N), else the mean of force.z over the run.
    """
    found: dict[int, set[str]] = {}
    for ch in results.parsed():
        m = _WHEELSET.match(ch.body)
        if m and ch.quantity == "force" and ch.point in ("left", "right") and (
                ch.direction in ("y", "z")):
            found.setdefault(int(m.group(1)), set()).add(f"{ch.point}.{ch.direction}")
    complete = sorted(ws for ws, parts in found.items()
                      if {"left.y", "left.z", "right.y", "right.z"} <= parts)
    if not complete:
        return None
    fs = check_rate(results.sample_rate)
    speed = _speed_of(results)
    parts = (("left", "y"), ("left", "z"), ("right", "y"), ("right", "z"))
    names = [Channel(f"wheelset{ws}", side, "force", d).name
             for ws in complete for side, d in parts]
    raw = check_signal(np.vstack([np.asarray(results.channels[c], dtype=np.float64)
                                  for c in names]), fs, name="wheel-rail forces", min_samples=8,
                       method="running safety")
    loads, src = _static_loads(results.meta, complete, results.channels)
    bad = [k for k, v in loads.items() if not (math.isfinite(v) and v > 0.0)]
    if bad:
        raise AnalysisError(f"static wheel load not positive at {', '.join(bad)} ({src})")
    lp = _lowpass(raw, fs, lowpass_hz, SAFETY_DEFAULTS["order"])
    indices: list[SafetyIndex] = []
    notes: list[str] = []
    for k, ws in enumerate(complete):
        rows = {f"{side}.force.{d}": 4 * k + j for j, (side, d) in enumerate(parts)}
        for side in ("left", "right"):
            loc = f"wheelset{ws}.{side}"
            iy, iz = rows[f"{side}.force.y"], rows[f"{side}.force.z"]
            indices.append(_derailment_core(lp[iy], lp[iz], float(np.mean(raw[iz])), fs, speed,
                                            side, loc, lowpass_hz, window_m, step_m,
                                            keep_series))
            indices.append(_unloading_core(lp[iz], loads[loc], fs, loc, lowpass_hz,
                                           keep_series, step_m / speed))
        axle = loads[f"wheelset{ws}.left"] + loads[f"wheelset{ws}.right"]
        h = (lp[rows["left.force.y"]] + lp[rows["right.force.y"]]) / 1000.0
        indices.append(_lateral_core(h, axle, fs, speed, f"wheelset{ws}", lowpass_hz, window_m,
                                     step_m, keep_series))
    incomplete = sorted(set(found) - set(complete))
    if incomplete:
        notes.append(f"wheelsets without all four force channels skipped: {incomplete}")
    return RunningSafety(
        indices=indices, passed=all(i.passed for i in indices),
        static_wheel_loads={"values_N": loads, "source": src},
        processing={"lowpass_hz": lowpass_hz, "window_m": window_m, "step_m": step_m,
                    "speed_mps": speed, "filter": "Butterworth order 4, zero phase"},
        notes=notes, nadal=_nadal_check(results.meta, indices),
    )


def _nadal_check(meta: dict[str, Any], indices: list[SafetyIndex]) -> dict[str, Any] | None:
    """The run's largest Y/Q against Nadal's limit for its wheel's flange angle and friction
    (``meta["flange_angle_rad"]``, ``meta["friction"]``: written for real profiles).
    """
    angle, mu = meta.get("flange_angle_rad"), meta.get("friction")
    qp = [i for i in indices if i.name == "derailment_coefficient"]
    if angle is None or mu is None or not qp:
        return None
    limit = nadal_limit(float(angle), float(mu))
    worst = max(qp, key=lambda i: i.value)
    return {"flange_angle_deg": math.degrees(float(angle)), "friction": float(mu),
            "limit": limit, "worst": worst.value, "location": worst.location,
            "utilisation": worst.value / limit, "passed": bool(worst.value <= limit)}

"""Equivalent conicity of a wheelset on its track (EN 15302).

Two methods, both from the rolling-radius difference Δr(y) = r_left − r_right against the
wheelset's lateral displacement y (a table, linearly interpolated between its points, or the
rigid contact-point search of a profile pair):

``integration`` (EN 15302, integration of the kinematic equation)
    Klingel's kinematic wheelset motion y'' = −Δr(y)/(2·e0·r0) (x the distance travelled) has
    the first integral y'² = (L − S(y))/(e0·r0) with S(y) = ∫Δr dy. For an amplitude ŷ the
    orbit lies between the turning points y1 < y2 with S(y1) = S(y2) = L and y2 − y1 = 2ŷ;
    the half wavelength is √(e0·r0)·∫ dy/√(L − S(y)) from y1 to y2, and
    tan γe = e0·r0·(2π/λ)², so tan γe = (π/I)² with I = ∫ dy/√(L − S(y)) (e0 and r0 cancel).
    With Δr linear between the table points S is piecewise quadratic and every piece of I is
    integrated in closed form (the inverse-square-root end singularities exactly), and the
    turning points are the exact roots of the quadratic pieces: the only approximation is the
    linear interpolation of the table. The orbit is centred where S is smallest; when Δr
    vanishes on an interval wider than 2ŷ there is no kinematic oscillation and tan γe = 0.
``harmonic`` (linearisation by the first harmonic, describing function)
    For y = y_c + ŷ·sin τ the first Fourier coefficient of Δr(y(τ)) divided by 2ŷ:
    tan γe = (1/(π ŷ))·∫ Δr(y_c + ŷ v)·v/√(1 − v²) dv over v ∈ [−1, 1], with the bias y_c
    chosen so that Δr has zero mean over the cycle; integrated exactly for piecewise-linear Δr.

Both give tan γe = λ at every amplitude for a cone of conicity λ (Δr = 2λy).
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np

from flexride.errors import ScenarioError

__all__ = [
    "DEFAULT_AMPLITUDES",
    "ConicityMethod",
    "equivalent_conicity",
    "read_delta_r_csv",
]

ConicityMethod = Literal["integration", "harmonic"]

#: Amplitudes ŷ in m: 1 … 7.5 mm in 0.5 mm steps.
DEFAULT_AMPLITUDES = np.round(np.arange(1.0, 7.51, 0.5), 6) * 1e-3

_LINEAR_TOL = 1e-8


def _check_table(y: np.ndarray, dr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    y = np.asarray(y, dtype=np.float64).reshape(-1)
    dr = np.asarray(dr, dtype=np.float64).reshape(-1)
    if y.shape != dr.shape or y.size < 3:
        raise ScenarioError("Δr table: y and Δr need the same length, at least 3 points")
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(dr))):
        raise ScenarioError("Δr table: values must be finite")
    if np.any(np.diff(y) <= 0.0):
        i = int(np.flatnonzero(np.diff(y) <= 0.0)[0]) + 1
        raise ScenarioError(f"Δr table: y must increase strictly (row {i + 1})")
    return y, dr


def _piece_integral(q0: float, q1: float, q2: float, ua: float, ub: float) -> float:
    """∫ du/√(q0 + q1 u + q2 u²) from ua to ub, the quadratic being ≥ 0 there (exact)."""
    if ub <= ua:
        return 0.0
    width = ub - ua
    qa = max(q0 + q1 * ua + q2 * ua * ua, 0.0)
    qb = max(q0 + q1 * ub + q2 * ub * ub, 0.0)
    scale = qa + qb + abs(q1) * width
    if abs(q2) * width * width <= _LINEAR_TOL * scale:
        den = math.sqrt(qa) + math.sqrt(qb)
        return math.inf if den == 0.0 else 2.0 * width / den
    pa = q1 + 2.0 * q2 * ua
    pb = q1 + 2.0 * q2 * ub
    disc = q1 * q1 - 4.0 * q0 * q2
    if q2 > 0.0:
        rq = math.sqrt(q2)

        def big_a(q: float, p: float) -> float:
            root = 2.0 * math.sqrt(q2 * q)
            return root + p if p >= 0.0 else -disc / (root - p)

        a_a, a_b = big_a(qa, pa), big_a(qb, pb)
        if a_a == 0.0 or a_b == 0.0 or a_a * a_b < 0.0:
            return math.inf
        return math.log(a_b / a_a) / rq
    c = -q2
    rc = math.sqrt(c)
    th_a = math.atan2(-pa, 2.0 * math.sqrt(c * qa))
    th_b = math.atan2(-pb, 2.0 * math.sqrt(c * qb))
    return (th_b - th_a) / rc


def _crossing(s0: float, b: float, m: float, level: float, h: float) -> float:
    """Smallest u in [0, h] with s0 + b·u + m·u²/2 = level (s0 < level)."""
    rise = level - s0
    disc = max(b * b + 2.0 * m * rise, 0.0)
    den = b + math.sqrt(disc)
    if den <= 0.0:
        return h
    return min(max(2.0 * rise / den, 0.0), h)


class _Orbit:
    """S(y) of a piecewise-linear Δr table and the orbits of the kinematic motion."""

    def __init__(self, y: np.ndarray, dr: np.ndarray) -> None:
        self.y = y
        self.dr = dr
        h = np.diff(y)
        self.h = h
        self.m = np.diff(dr) / h
        self.s = np.concatenate([[0.0], np.cumsum(0.5 * (dr[:-1] + dr[1:]) * h)])
        self.i0 = int(np.argmin(self.s))
        self.smin = float(self.s[self.i0])

    def right(self, level: float) -> float | None:
        """First y > y[i0] with S = level (None beyond the table)."""
        s = self.s
        up = np.flatnonzero(s[self.i0 + 1:] >= level)
        if up.size == 0:
            return None
        j = self.i0 + 1 + int(up[0])
        k = j - 1
        u = _crossing(float(s[k]), float(self.dr[k]), float(self.m[k]), level, float(self.h[k]))
        return float(self.y[k] + u)

    def left(self, level: float) -> float | None:
        """First y < y[i0] (going left) with S = level (None beyond the table)."""
        s = self.s
        up = np.flatnonzero(s[: self.i0][::-1] >= level)
        if up.size == 0:
            return None
        j = self.i0 - 1 - int(up[0])
        k = j  # piece [y_k, y_k+1], walked from y_k+1 leftward
        v = _crossing(float(s[k + 1]), -float(self.dr[k + 1]), float(self.m[k]), level,
                      float(self.h[k]))
        return float(self.y[k + 1] - v)

    def width(self, level: float) -> float:
        a, b = self.left(level), self.right(level)
        if a is None or b is None:
            return math.inf
        return b - a

    def period_integral(self, level: float, y1: float, y2: float) -> float:
        """I = ∫ dy/√(level − S(y)) from y1 to y2."""
        y, s, dr, m = self.y, self.s, self.dr, self.m
        k1 = int(np.clip(np.searchsorted(y, y1, side="right") - 1, 0, y.size - 2))
        k2 = int(np.clip(np.searchsorted(y, y2, side="left") - 1, 0, y.size - 2))
        total = 0.0
        for k in range(k1, k2 + 1):
            ua = max(y1 - y[k], 0.0)
            ub = min(y2, y[k + 1]) - y[k]
            total += _piece_integral(level - float(s[k]), -float(dr[k]), -0.5 * float(m[k]),
                                     ua, ub)
        return total


def _integration(y: np.ndarray, dr: np.ndarray, amplitudes: np.ndarray) -> np.ndarray:
    orbit = _Orbit(y, dr)
    out = np.full(amplitudes.shape, np.nan)
    span = float(min(orbit.s[0], orbit.s[-1])) - orbit.smin
    if not span > 0.0:
        return out  # S has its minimum at an end: no orbit inside the table
    lo_level = orbit.smin + 1e-12 * span
    hi_level = orbit.smin + (1.0 - 1e-12) * span
    w_lo, w_hi = orbit.width(lo_level), orbit.width(hi_level)
    for j, amp in enumerate(amplitudes):
        target = 2.0 * float(amp)
        if w_lo >= target:
            out[j] = 0.0  # Δr vanishes over more than the orbit: no kinematic oscillation
            continue
        if w_hi < target:
            continue  # the orbit leaves the table
        lo, hi = lo_level, hi_level
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if orbit.width(mid) >= target:
                hi = mid
            else:
                lo = mid
            if hi - lo <= 1e-15 * span:
                break
        y1, y2 = orbit.left(hi), orbit.right(hi)
        if y1 is None or y2 is None:
            continue
        integral = orbit.period_integral(hi, y1, y2)
        out[j] = 0.0 if not math.isfinite(integral) else (math.pi / integral) ** 2
    return out


def _harmonic_moments(y: np.ndarray, dr: np.ndarray, yc: float, amp: float) -> tuple[float, float]:
    """∫Δr(yc + a v)/√(1−v²) dv and ∫Δr(yc + a v)·v/√(1−v²) dv over [−1, 1] (exact)."""
    v_nodes = (y - yc) / amp
    inside = (v_nodes > -1.0) & (v_nodes < 1.0)
    breaks = np.concatenate([[-1.0], v_nodes[inside], [1.0]])
    d_at = np.interp(yc + amp * breaks, y, dr)
    asn = np.arcsin(np.clip(breaks, -1.0, 1.0))
    sq = np.sqrt(np.clip(1.0 - breaks * breaks, 0.0, None))
    m0 = 0.0
    m1 = 0.0
    for k in range(breaks.size - 1):
        va, vb = breaks[k], breaks[k + 1]
        if vb <= va:
            continue
        beta = (d_at[k + 1] - d_at[k]) / (vb - va)
        alpha = d_at[k] - beta * va
        # ∫(α + βv)/√(1−v²) = α·asin v − β·√(1−v²)
        m0 += alpha * (asn[k + 1] - asn[k]) - beta * (sq[k + 1] - sq[k])
        # ∫(α + βv)·v/√(1−v²) = −α·√(1−v²) + β·(asin v − v√(1−v²))/2
        m1 += (-alpha * (sq[k + 1] - sq[k])
               + 0.5 * beta * ((asn[k + 1] - vb * sq[k + 1]) - (asn[k] - va * sq[k])))
    return m0, m1


def _harmonic(y: np.ndarray, dr: np.ndarray, amplitudes: np.ndarray) -> np.ndarray:
    out = np.full(amplitudes.shape, np.nan)
    for j, amp in enumerate(amplitudes):
        a = float(amp)
        lo, hi = float(y[0]) + a, float(y[-1]) - a
        if not hi > lo:
            continue
        m_lo = _harmonic_moments(y, dr, lo, a)[0]
        m_hi = _harmonic_moments(y, dr, hi, a)[0]
        if m_lo > 0.0 or m_hi < 0.0:
            continue  # no bias point keeps the cycle inside the table
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if _harmonic_moments(y, dr, mid, a)[0] >= 0.0:
                hi = mid
            else:
                lo = mid
            if hi - lo < 1e-13 * a:
                break
        _, m1 = _harmonic_moments(y, dr, 0.5 * (lo + hi), a)
        out[j] = m1 / (math.pi * a)
    return out


def equivalent_conicity(
    y: np.ndarray,
    delta_r: np.ndarray,
    amplitudes: np.ndarray | None = None,
    method: ConicityMethod = "integration",
) -> np.ndarray:
    """Equivalent conicity tan γe from a rolling-radius-difference table.

    Parameters
    ----------
    y : array_like
        Lateral wheelset displacement in m, strictly increasing.
    delta_r : array_like
        Rolling-radius difference r_left − r_right in m at ``y`` (linear between the points).
    amplitudes : array_like, optional
        Amplitudes ŷ in m (half the peak-to-peak lateral motion); default
        :data:`DEFAULT_AMPLITUDES` (1 … 7.5 mm).
    method : {"integration", "harmonic"}
        EN 15302 integration of the kinematic equation, or first-harmonic linearisation.

    Returns
    -------
    numpy.ndarray
        tan γe (dimensionless) per amplitude; NaN where the orbit does not fit in the table.

    Raises
    ------
    ScenarioError
        For a malformed table, non-positive amplitudes or an unknown method.
    """
    yy, dr = _check_table(np.asarray(y), np.asarray(delta_r))
    amps = DEFAULT_AMPLITUDES if amplitudes is None else np.asarray(amplitudes, dtype=np.float64)
    amps = amps.reshape(-1)
    if amps.size == 0 or not np.all(np.isfinite(amps)) or np.any(amps <= 0.0):
        raise ScenarioError("conicity amplitudes must be finite and positive")
    if method == "integration":
        return _integration(yy, dr, amps)
    if method == "harmonic":
        return _harmonic(yy, dr, amps)
    raise ScenarioError(f"conicity method must be 'integration' or 'harmonic', got {method!r}")


def read_delta_r_csv(path_or_text: str, name: str = "Δr table") -> tuple[np.ndarray, np.ndarray]:
    """Read a Δr table in CSV with the header ``y_mm,delta_r_mm`` (mm, one row per point).

    Parameters
    ----------
    path_or_text : str
        The CSV text.
    name : str
        File name for messages.

    Returns
    -------
    y, delta_r : numpy.ndarray
        In m.

    Raises
    ------
    ScenarioError
        Naming the file and line for a wrong header, a malformed or non-finite row, or y not
        strictly increasing.
    """
    rows = [(no, ln.strip()) for no, ln in enumerate(path_or_text.splitlines(), start=1)]
    rows = [(no, ln) for no, ln in rows if ln and not ln.startswith("#")]
    if not rows:
        raise ScenarioError(f"{name}: empty file")
    head_no, head = rows[0]
    cols = [c.strip().lower() for c in head.split(",")]
    if cols != ["y_mm", "delta_r_mm"]:
        raise ScenarioError(f"{name}, line {head_no}: the header must be 'y_mm,delta_r_mm', "
                            f"got {head!r}")
    ys: list[float] = []
    ds: list[float] = []
    for no, ln in rows[1:]:
        parts = [p.strip() for p in ln.split(",")]
        if len(parts) != 2:
            raise ScenarioError(f"{name}, line {no}: expected 2 values, got {len(parts)}")
        try:
            a, b = float(parts[0]), float(parts[1])
        except ValueError as exc:
            raise ScenarioError(f"{name}, line {no}: not a number in {ln!r}") from exc
        if not (math.isfinite(a) and math.isfinite(b)):
            raise ScenarioError(f"{name}, line {no}: values must be finite")
        if ys and a <= ys[-1]:
            raise ScenarioError(f"{name}, line {no}: y_mm must increase strictly")
        ys.append(a)
        ds.append(b)
    if len(ys) < 3:
        raise ScenarioError(f"{name}: at least 3 rows are needed, got {len(ys)}")
    return np.array(ys) * 1e-3, np.array(ds) * 1e-3

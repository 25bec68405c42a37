"""The S1002 wheel profile of EN 13715 (UIC 510-2) from its analytic definition.

The standard defines the radius increase F(s) over the nominal rolling radius (mm) of the
lateral coordinate s (mm; s = 0 at the taping line, s > 0 toward the outer face, flange back at
s = −70) in eight sections A … H: a 1:15 outer tread (A), polynomials for the tread (B) and the
flange root (C), the R13 flange-root arc (D), the straight flange flank (E) and the R20, R12
(flange tip) and R20.5 (flange back) arcs (F, G, H). Coefficients: ``reference/
wheel-rail-profiles.md`` §1.1 (facts of the standard).

The published coefficients leave two small steps at section joins: C/B at s = −26
(3.65e-5 mm) and D/C at s = −35 (1.18e-4 mm, slopes −0.91761 / −0.91757). :func:`s1002_radius`
removes them with a local blend over ±0.5 mm around each join: F = (1 − w)·F_left + w·F_right
with the quintic smoothstep w (C², both section formulas continued analytically across the
join). Outside the two 1 mm windows nothing changes; inside, the change is at most
:data:`BLEND_MAX_CHANGE` (measured: 5.91e-5 mm at s = −35, 1.83e-5 mm at s = −26, i.e. half of
each step, since the blend meets both sections half way).
"""

from __future__ import annotations

import math

import numpy as np

from flexride.contact.profiles.profile import Profile

__all__ = [
    "BLEND_HALF_WIDTH",
    "BLEND_MAX_CHANGE",
    "S1002_JOINS",
    "S1002_RANGE",
    "s1002",
    "s1002_radius",
    "s1002_radius_raw",
]

#: Section boundaries of EN 13715 S1002 in mm, from the outer face to the flange back.
S1002_JOINS = (32.15796, -26.0, -35.0, -38.426669071, -39.764473993, -49.662510381,
               -62.764705882)
#: Range of the analytic definition in mm (flange back to outer tread).
S1002_RANGE = (-70.0, 60.0)
#: Half width of the blends at s = −26 and s = −35 in mm.
BLEND_HALF_WIDTH = 0.5
#: Bound on the change of F by the blends in mm (measured 5.91e-5 at s = −35, 1.83e-5 at −26).
BLEND_MAX_CHANGE = 6.0e-5

# Coefficients of EN 13715 / UIC 510-2 (mm)
_AA, _BA = 1.364323640, 0.066666667
_B = (0.0, 3.358537058e-02, 1.565681624e-03, 2.810427944e-05, 5.844240864e-08, 1.562379023e-08,
      5.309217349e-15, 5.957839843e-12, 2.646656573e-13)
_C = (4.320221063e03, 1.038384026e03, 1.065501873e02, 6.051367875, 2.054332446e-01,
      4.169739389e-03, 4.687195829e-05, 2.252755540e-07)
_AD, _BD, _CD = 16.446, 13.0, 26.210665
_AE, _BE = 93.576667419, 2.747477419
_AF, _BF, _CF = 8.834924130, 20.0, 58.558326413
_AG, _BG, _CG = 16.0, 12.0, 55.0
_AH, _BH, _CH = 9.519259302, 20.5, 49.5


def _sec_a(s: np.ndarray) -> np.ndarray:
    return _AA - _BA * s


def _sec_b(s: np.ndarray) -> np.ndarray:
    # F = AB − BB·s + CB·s² − DB·s³ + EB·s⁴ − FB·s⁵ + GB·s⁶ − HB·s⁷ + IB·s⁸
    out = np.zeros_like(s)
    for k in range(8, -1, -1):
        out = out * s + (_B[k] if k % 2 == 0 else -_B[k])
    return out


def _sec_c(s: np.ndarray) -> np.ndarray:
    # F = −AC − BC·s − CC·s² − … − HC·s⁷
    out = np.zeros_like(s)
    for k in range(7, -1, -1):
        out = out * s - _C[k]
    return out


def _arc(s: np.ndarray, a: float, r: float, c: float, sign: float) -> np.ndarray:
    return a + sign * np.sqrt(np.maximum(r * r - (s + c) ** 2, 0.0))


def _sec_d(s: np.ndarray) -> np.ndarray:
    return _arc(s, _AD, _BD, _CD, -1.0)


def _sec_e(s: np.ndarray) -> np.ndarray:
    return -_AE - _BE * s


def _sec_f(s: np.ndarray) -> np.ndarray:
    return _arc(s, _AF, _BF, _CF, 1.0)


def _sec_g(s: np.ndarray) -> np.ndarray:
    return _arc(s, _AG, _BG, _CG, 1.0)


def _sec_h(s: np.ndarray) -> np.ndarray:
    return _arc(s, _AH, _BH, _CH, 1.0)


_SECTIONS = (_sec_a, _sec_b, _sec_c, _sec_d, _sec_e, _sec_f, _sec_g, _sec_h)


def s1002_radius_raw(s: np.ndarray | float) -> np.ndarray:
    """Radius increase F(s) of S1002 exactly as the published sections define it (with the two
    small steps at s = −26 and −35).

    Parameters
    ----------
    s : array_like
        Lateral coordinate in mm (taping line 0, outer face positive), −70 ≤ s ≤ 60.

    Returns
    -------
    numpy.ndarray
        F in mm (positive toward the rail; flange tip F(−55) = 28).
    """
    s = np.asarray(s, dtype=np.float64)
    j = S1002_JOINS
    conds = [s >= j[0], s >= j[1], s >= j[2], s >= j[3], s >= j[4], s >= j[5], s >= j[6]]
    # evaluate each section only where it applies (the arcs are undefined far outside)
    out = np.empty_like(s)
    done = np.zeros(s.shape, dtype=bool)
    for cond, sec in zip(conds, _SECTIONS[:-1], strict=True):
        m = cond & ~done
        out[m] = sec(s[m])
        done |= m
    out[~done] = _sec_h(s[~done])
    return out


def _smoothstep(t: np.ndarray) -> np.ndarray:
    t = np.clip(t, 0.0, 1.0)
    return t * t * t * (10.0 - 15.0 * t + 6.0 * t * t)


def s1002_radius(s: np.ndarray | float) -> np.ndarray:
    """Radius increase F(s) of S1002 with the steps at s = −26 and −35 blended out.

    Parameters
    ----------
    s : array_like
        Lateral coordinate in mm, −70 ≤ s ≤ 60.

    Returns
    -------
    numpy.ndarray
        F in mm; equal to :func:`s1002_radius_raw` outside s ∈ [−26.5, −25.5] ∪
        [−35.5, −34.5], C² across both joins.
    """
    s = np.asarray(s, dtype=np.float64)
    out = s1002_radius_raw(s)
    w = BLEND_HALF_WIDTH
    for join, left, right in ((-26.0, _sec_c, _sec_b), (-35.0, _sec_d, _sec_c)):
        m = np.abs(s - join) < w
        if np.any(m):
            t = _smoothstep((s[m] - (join - w)) / (2.0 * w))
            out[m] = (1.0 - t) * left(s[m]) + t * right(s[m])
    return out


def s1002(step: float = 5.0e-5, name: str = "S1002 (EN 13715)") -> Profile:
    """The S1002 wheel profile in the convention of :class:`Profile` (y = s, z = −F, in m).

    Parameters
    ----------
    step : float
        Sampling step in m along the contour (default 0.05 mm, uniform in arc length); the
        sections are sampled from s = −70 to +60 mm, with every section join a point.
    name : str
        Source name of the profile.

    Returns
    -------
    Profile
        A wheel profile of about 3000 points (at the default step).
    """
    lo, hi = S1002_RANGE
    h_mm = float(step) * 1e3
    if not (math.isfinite(h_mm) and 1e-4 <= h_mm <= 1.0):
        from flexride.errors import ScenarioError

        raise ScenarioError(f"S1002 sampling step must lie in [1e-7, 1e-3] m, got {step!r}")
    # points uniform in arc length: cumulative chord length on a fine lateral grid, then the
    # lateral coordinate at multiples of the step (the flange flank and back are steep)
    fine = np.linspace(lo, hi, round((hi - lo) / min(h_mm / 20.0, 1e-3)) + 1)
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(fine),
                                                    np.diff(s1002_radius(fine))))])
    k = math.ceil(arc[-1] / h_mm)
    s = np.interp(np.linspace(0.0, arc[-1], k + 1), arc, fine)
    s = np.unique(np.concatenate([s, np.array(S1002_JOINS)]))
    keep = np.concatenate([[True], np.diff(s) > 1e-6])  # a join next to a grid point
    s = s[keep]
    return Profile("wheel", s * 1e-3, -s1002_radius(s) * 1e-3, name)

"""Damping of elastic modes: Rayleigh damping (paper Eqs. 2–4) or modal damping per mode."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from flexride.errors import FEModelError


@dataclass(frozen=True)
class RayleighDamping:
    """Rayleigh damping ``C = α M + β K`` fixed by two modes and their damping ratios.

    Attributes
    ----------
    f1, f2 : float
        Frequencies of the two modes (Hz), ``f1 != f2``.
    zeta1, zeta2 : float
        Damping ratios at ``f1`` and ``f2`` (-).
    """

    f1: float
    f2: float
    zeta1: float
    zeta2: float

    @property
    def coefficients(self) -> tuple[float, float]:
        """(α in 1/s, β in s) from paper Eqs. (3) and (4)."""
        w1, w2 = 2 * np.pi * self.f1, 2 * np.pi * self.f2
        if abs(w1 - w2) < 1e-12:
            raise ValueError("Rayleigh damping needs two different frequencies")
        alpha = 2.0 * w1 * w2 * (self.zeta2 * w1 - self.zeta1 * w2) / (w1**2 - w2**2)
        beta = 2.0 * (self.zeta1 * w1 - self.zeta2 * w2) / (w1**2 - w2**2)
        return float(alpha), float(beta)

    def ratios(self, frequencies: np.ndarray) -> np.ndarray:
        """Modal damping ratios ``ζ = α/(2ω) + βω/2`` at ``frequencies`` (Hz)."""
        alpha, beta = self.coefficients
        w = 2 * np.pi * np.asarray(frequencies, dtype=float)
        return alpha / (2.0 * np.maximum(w, 1e-12)) + beta * w / 2.0


@dataclass(frozen=True)
class RayleighThroughModes:
    """Rayleigh damping through two of the body's own elastic modes (paper Eqs. 2–4), whose
    frequencies are known only once the FE model is solved.

    Attributes
    ----------
    zeta1, zeta2 : float
        Damping ratios of the two modes (-).
    mode1, mode2 : int
        1-based indices of the two elastic modes (default: the first two).
    """

    zeta1: float
    zeta2: float
    mode1: int = 1
    mode2: int = 2

    def resolve(self, frequencies: np.ndarray) -> RayleighDamping:
        """The :class:`RayleighDamping` through the two modes of ``frequencies`` (Hz)."""
        f = np.asarray(frequencies, dtype=float)
        if min(self.mode1, self.mode2) < 1 or max(self.mode1, self.mode2) > f.size:
            raise FEModelError(f"Rayleigh damping through modes {self.mode1} and {self.mode2} "
                               f"needs that many elastic modes (the body has {f.size})")
        return RayleighDamping(float(f[self.mode1 - 1]), float(f[self.mode2 - 1]),
                               self.zeta1, self.zeta2)


DampingSpec = float | Sequence[float] | np.ndarray | RayleighDamping | RayleighThroughModes


def modal_damping_ratios(spec: DampingSpec, frequencies: np.ndarray) -> np.ndarray:
    """Damping ratio of each elastic mode.

    Parameters
    ----------
    spec : float, sequence of float, RayleighDamping or RayleighThroughModes
        One ratio for all modes, one per mode (the last one repeats for further modes), or
        Rayleigh damping (through given frequencies or through two of these modes).
    frequencies : numpy.ndarray
        Elastic natural frequencies (Hz).

    Returns
    -------
    numpy.ndarray
        ζ per mode (-).
    """
    f = np.asarray(frequencies, dtype=float)
    if isinstance(spec, RayleighThroughModes):
        spec = spec.resolve(f)
    if isinstance(spec, RayleighDamping):
        z = spec.ratios(f)
    elif isinstance(spec, (int, float, np.integer, np.floating)):
        z = np.full(f.size, float(spec))
    else:
        arr = np.asarray(spec, dtype=float).ravel()
        if arr.size == 0:
            raise ValueError("empty list of damping ratios")
        z = np.concatenate([arr, np.full(max(f.size - arr.size, 0), arr[-1])])[: f.size]
    if np.any(z < 0) or np.any(~np.isfinite(z)):
        raise ValueError("damping ratios must be finite and non-negative")
    return z

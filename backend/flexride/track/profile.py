"""Rail irregularity profile on a uniform grid along the line, and the rules of that grid.

Every kind of irregularity (:mod:`flexride.track.spectra`, :mod:`flexride.track.defects`,
measured data through :mod:`flexride.track.excitation`) ends as an :class:`IrregularityProfile`:
the vertical and lateral irregularity of the left and right rail (m) at s0 + i·ds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from flexride.errors import ScenarioError
from flexride.track.measured import RAIL_COLUMNS

__all__ = [
    "DEFAULT_DS",
    "POINTS_PER_WAVELENGTH",
    "RAIL_KEYS",
    "IrregularityProfile",
    "check_step",
    "n_points",
]

DEFAULT_DS = 0.05
"""Grid step used when no excitation needs a finer one (m)."""
POINTS_PER_WAVELENGTH = 20
"""Grid points per shortest wavelength (-): ds ≤ λ_min/20."""
RAIL_KEYS = RAIL_COLUMNS
"""Names of the four rail irregularities (the profile's arrays), in the kernel's row order."""


def n_points(length_m: float, ds: float) -> int:
    """Number of grid points covering [0, ``length_m``] (m) with step ``ds`` (m).

    The last point is at or just beyond ``length_m``.

    Raises
    ------
    ScenarioError
        A length that is not finite and ≥ 0 m, or a step that is not finite and > 0 m.
    """
    if not (math.isfinite(length_m) and length_m >= 0.0):
        raise ScenarioError(f"profile length must be a finite length >= 0 m, got {length_m}")
    if not (math.isfinite(ds) and ds > 0.0):
        raise ScenarioError(f"grid step ds must be > 0 m, got {ds}")
    return math.ceil(length_m / ds - 1e-9) + 1


def check_step(ds: float, wavelength_m: float, what: str) -> None:
    """Reject a grid step ``ds`` (m) that cannot represent ``wavelength_m`` (m): ds > λ/2.

    ``what`` names the wavelength in the message (e.g. ``"corrugation"``).

    Raises
    ------
    ScenarioError
        ``ds`` exceeds half the wavelength.
    """
    if ds > 0.5 * wavelength_m * (1.0 + 1e-12):
        raise ScenarioError(
            f"grid step ds = {ds} m is too coarse for the {what} wavelength {wavelength_m} m "
            f"(need ds <= wavelength/2, better /{POINTS_PER_WAVELENGTH})"
        )


@dataclass
class IrregularityProfile:
    """Rail irregularities on a uniform grid along the line.

    Attributes
    ----------
    s0 : float
        Distance of the first grid point along the line (m).
    ds : float
        Grid step (m), > 0.
    z_left, z_right : numpy.ndarray
        Vertical irregularity of the left / right rail (m), up positive.
    y_left, y_right : numpy.ndarray
        Lateral irregularity of the left / right rail (m), left (+y) positive; y_left − y_right
        is the gauge deviation (widening positive).

    Notes
    -----
    Grid point i is at s0 + i·ds. Between grid points the profile is linearly interpolated,
    outside the grid it is zero (:meth:`sample`). Profiles add with ``+`` (and ``sum``).
    """

    s0: float
    ds: float
    z_left: np.ndarray
    z_right: np.ndarray
    y_left: np.ndarray
    y_right: np.ndarray

    def __post_init__(self) -> None:
        """Check the grid step and that the four arrays have one length."""
        if not (math.isfinite(self.ds) and self.ds > 0.0):
            raise ValueError(f"ds must be a positive grid step in m, got {self.ds}")
        arrays = [np.ascontiguousarray(getattr(self, k), dtype=np.float64) for k in RAIL_KEYS]
        n = arrays[0].shape
        if len(n) != 1 or n[0] < 1 or any(a.shape != n for a in arrays):
            raise ValueError("z_left, z_right, y_left, y_right must be 1-D of equal length >= 1")
        for key, arr in zip(RAIL_KEYS, arrays, strict=True):
            setattr(self, key, arr)

    @classmethod
    def zeros(cls, length_m: float, ds: float, s0: float = 0.0) -> IrregularityProfile:
        """Flat track from ``s0`` to at least ``s0 + length_m`` (m) with step ``ds`` (m)."""
        n = n_points(length_m, ds)
        return cls(s0, ds, *(np.zeros(n) for _ in range(4)))

    @property
    def n(self) -> int:
        """Number of grid points."""
        return int(self.z_left.size)

    @property
    def s(self) -> np.ndarray:
        """Grid positions along the line (m)."""
        return self.s0 + self.ds * np.arange(self.n)

    @property
    def s_end(self) -> float:
        """Position of the last grid point (m)."""
        return self.s0 + self.ds * (self.n - 1)

    def rails(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The four rail irregularities (m) in :data:`RAIL_KEYS` order (the arrays, no copy)."""
        return self.z_left, self.z_right, self.y_left, self.y_right

    def sample(
        self, s: np.ndarray | float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Irregularities at arbitrary positions.

        Parameters
        ----------
        s : array_like
            Positions along the line (m).

        Returns
        -------
        z_left, z_right, y_left, y_right : numpy.ndarray
            Rail irregularities (m) at ``s``, linearly interpolated, zero outside the grid.
        """
        sq = np.asarray(s, dtype=float)
        grid = self.s
        zl, zr, yl, yr = (np.interp(sq, grid, r, left=0.0, right=0.0) for r in self.rails())
        return zl, zr, yl, yr

    def __add__(self, other: IrregularityProfile) -> IrregularityProfile:
        """Sum of two profiles on a common grid.

        The result spans both profiles with the finer of the two steps, starting at the smaller
        ``s0``; each profile is linearly interpolated onto it (exact where the grids coincide)
        and taken as zero outside its own extent.
        """
        if not isinstance(other, IrregularityProfile):
            return NotImplemented
        if self.ds == other.ds and self.s0 == other.s0 and self.n == other.n:
            return IrregularityProfile(
                self.s0,
                self.ds,
                *(a + b for a, b in zip(self.rails(), other.rails(), strict=True)),
            )
        ds = min(self.ds, other.ds)
        s0 = min(self.s0, other.s0)
        s_end = max(self.s_end, other.s_end)
        n = n_points(s_end - s0, ds)
        grid = s0 + ds * np.arange(n)
        a = self.sample(grid)
        b = other.sample(grid)
        return IrregularityProfile(s0, ds, *(x + y for x, y in zip(a, b, strict=True)))

    def __radd__(self, other: object) -> IrregularityProfile:
        """``0 + profile`` is the profile, so ``sum()`` of profiles works."""
        if isinstance(other, int | float) and other == 0:  # lets sum() start from 0
            return self
        return NotImplemented

"""Local vertical rail defects: corrugation and settlement, both cosine dips.

Both follow one shape (:func:`cosine_defect`): over a stretch starting at s0,

    z = −(depth/2)·(1 − cos(2π(s − s0)/λ)),    0 ≥ z ≥ −depth,

repeated over a whole number of wavelengths and zero elsewhere, so the rail enters and leaves
the stretch with zero height and slope. Corrugation repeats it along a stretch (short waves),
settlement is a single wavelength (one long dip). Lateral irregularities are zero.
"""

from __future__ import annotations

import math

import numpy as np

from flexride.errors import ScenarioError
from flexride.scenario.excitation import Rails
from flexride.track.profile import (
    DEFAULT_DS,
    POINTS_PER_WAVELENGTH,
    IrregularityProfile,
    check_step,
)

__all__ = ["corrugation_profile", "cosine_defect", "settlement_profile"]


def _rail_mask(rails: str) -> tuple[float, float]:
    """Factors (left, right) of a defect on ``rails`` (-)."""
    if rails == "both":
        return 1.0, 1.0
    if rails == "left":
        return 1.0, 0.0
    if rails == "right":
        return 0.0, 1.0
    raise ScenarioError(f"rails must be 'both', 'left' or 'right', got {rails!r}")


def cosine_defect(
    length_m: float,
    wavelength_m: float,
    depth_m: float,
    start_m: float,
    stretch_m: float,
    rails: Rails = "both",
    ds: float | None = None,
    what: str = "defect",
) -> IrregularityProfile:
    """Vertical cosine defect repeated over whole wavelengths of a stretch.

    Parameters
    ----------
    length_m : float
        Route length to cover (m); the grid runs from 0 to at least ``length_m``.
    wavelength_m : float
        Wavelength λ of one dip (m), > 0.
    depth_m : float
        Depth of each dip (m, peak to peak).
    start_m : float
        Start s0 of the stretch along the line (m).
    stretch_m : float
        Length of the stretch (m); rounded down to a whole number of wavelengths, at least one,
        so the stretch ends smoothly.
    rails : {"both", "left", "right"}
        Rail(s) with the defect.
    ds : float, optional
        Grid step (m); default min(0.05 m, λ/20). Must not exceed λ/2.
    what : str
        Name of the defect in error messages (e.g. ``"corrugation"``).

    Returns
    -------
    IrregularityProfile
        z = −(depth/2)·(1 − cos(2π(s − s0)/λ)) for s0 ≤ s ≤ s0 + n·λ (n whole wavelengths),
        zero elsewhere, on the chosen rails; lateral irregularities zero; s0 = 0 of the grid.

    Raises
    ------
    ScenarioError
        Non-positive wavelength, a grid too coarse for it, or unknown ``rails``.
    """
    if not wavelength_m > 0.0:
        raise ScenarioError(f"{what} wavelength must be > 0 m, got {wavelength_m}")
    if ds is None:
        ds = min(DEFAULT_DS, wavelength_m / POINTS_PER_WAVELENGTH)
    check_step(ds, wavelength_m, what)
    prof = IrregularityProfile.zeros(length_m, ds)
    cycles = max(1, math.floor(stretch_m / wavelength_m + 1e-9))
    end = start_m + cycles * wavelength_m
    s = prof.s
    inside = (s >= start_m) & (s <= end)
    z = np.where(
        inside, -0.5 * depth_m * (1.0 - np.cos(2.0 * math.pi * (s - start_m) / wavelength_m)), 0.0
    )
    ml, mr = _rail_mask(rails)
    prof.z_left += ml * z
    prof.z_right += mr * z
    return prof


def corrugation_profile(
    length_m: float,
    wavelength_m: float = 0.5,
    depth_m: float = 0.001,
    start_m: float = 0.0,
    corrugated_length_m: float | None = None,
    rails: Rails = "both",
    ds: float | None = None,
) -> IrregularityProfile:
    """Rail corrugation: continuous sinusoidal vertical irregularity.

    Parameters
    ----------
    length_m : float
        Route length to cover (m); the grid runs from 0 to at least ``length_m``.
    wavelength_m : float
        Corrugation wavelength λ (m).
    depth_m : float
        Peak-to-peak depth (m).
    start_m : float
        Start of the corrugated stretch along the line (m).
    corrugated_length_m : float, optional
        Length of the corrugated stretch (m); default to the end of the route. It is rounded
        down to a whole number of wavelengths (at least one), so the profile ends smoothly.
        (The schema field :attr:`~flexride.scenario.excitation.Corrugation.length_m`.)
    rails : {"both", "left", "right"}
        Corrugated rail(s).
    ds : float, optional
        Grid step (m); default min(0.05 m, λ/20).

    Returns
    -------
    IrregularityProfile
        z = −(depth/2)·(1 − cos(2π(s − start)/λ)) on the corrugated stretch (0 ≥ z ≥ −depth),
        zero elsewhere; lateral irregularities zero (:func:`cosine_defect`).
    """
    stretch = length_m - start_m if corrugated_length_m is None else corrugated_length_m
    return cosine_defect(length_m, wavelength_m, depth_m, start_m, stretch, rails, ds,
                         "corrugation")


def settlement_profile(
    length_m: float,
    wavelength_m: float = 20.0,
    depth_m: float = 0.1,
    position_m: float = 50.0,
    rails: Rails = "both",
    ds: float | None = None,
) -> IrregularityProfile:
    """Track settlement: a single cosine dip.

    Parameters
    ----------
    length_m : float
        Route length to cover (m); the grid runs from 0 to at least ``length_m``.
    wavelength_m : float
        Length λ of the dip (m).
    depth_m : float
        Depth of the dip (m); the deepest point is at ``position_m + λ/2``.
    position_m : float
        Start s0 of the dip along the line (m).
    rails : {"both", "left", "right"}
        Settled rail(s).
    ds : float, optional
        Grid step (m); default min(0.05 m, λ/20).

    Returns
    -------
    IrregularityProfile
        z = −(depth/2)·(1 − cos(2π(s − s0)/λ)) for s0 ≤ s ≤ s0 + λ, zero elsewhere; lateral
        irregularities zero (:func:`cosine_defect` over one wavelength).
    """
    return cosine_defect(length_m, wavelength_m, depth_m, position_m, wavelength_m, rails, ds,
                         "settlement")

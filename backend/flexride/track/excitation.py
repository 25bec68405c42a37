"""The track excitation of a scenario as one rail irregularity profile.

:func:`build_profile` turns the excitation schema objects (:mod:`flexride.scenario.excitation`)
into an :class:`~flexride.track.profile.IrregularityProfile` on one grid and sums them: random
irregularity (:mod:`flexride.track.spectra`, with its fade-in), corrugation and settlement
(:mod:`flexride.track.defects`) and measured data (:mod:`flexride.track.measured` reads and
checks them; here they are mapped to the rails and resampled). :func:`measured_profile` does the
last for a CSV file alone, on the data's own grid.

Measured data map to the rails as z_left = vertical + cross_level/2 + z_left,
z_right = vertical − cross_level/2 + z_right, y_left = alignment + gauge/2 + y_left,
y_right = alignment − gauge/2 + y_right (cross_level the rail height difference, gauge the
gauge deviation, all in m; absent columns count as zero).
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from flexride.errors import ScenarioError
from flexride.scenario.excitation import (
    Corrugation,
    MeasuredIrregularity,
    RandomIrregularity,
    Settlement,
)
from flexride.track.defects import corrugation_profile, settlement_profile
from flexride.track.measured import (
    COMPONENT_COLUMNS,
    LIBRARY,
    MeasuredSources,
    MeasuredTable,
    load_measured,
)
from flexride.track.profile import (
    DEFAULT_DS,
    POINTS_PER_WAVELENGTH,
    IrregularityProfile,
    n_points,
)
from flexride.track.spectra import GERMAN_HALF_GAUGE, random_profile

if TYPE_CHECKING:
    from flexride.scenario.excitation import Excitation

__all__ = ["build_profile", "measured_profile"]


def measured_profile(
    path: str | Path,
    distance_column: str = "distance_m",
    scale: float = 1.0,
    ds: float | None = None,
) -> IrregularityProfile:
    """Irregularity profile from a measured CSV file.

    Parameters
    ----------
    path : str or pathlib.Path
        CSV file; format in :class:`flexride.scenario.excitation.MeasuredIrregularity`: a header
        row, a distance column (m, strictly increasing) and any of ``vertical``,
        ``alignment``, ``cross_level`` (rail height difference z_left − z_right),
        ``gauge`` (y_left − y_right, widening positive), ``z_left``, ``z_right``, ``y_left``,
        ``y_right`` (all m). Blank lines and ``#`` comment lines are skipped; other columns
        are ignored.
    distance_column : str
        Name of the distance column.
    scale : float
        Amplitude factor (-).
    ds : float, optional
        Grid step (m); default the median spacing of the data.

    Returns
    -------
    IrregularityProfile
        From the first to (at least) the last measured distance, linearly resampled and
        mapped to the rails (module docstring).

    Raises
    ------
    ScenarioError
        Unreadable or empty file, missing distance or irregularity columns, wrong number of
        cells, non-numeric or non-finite cells, distance not strictly increasing; the message
        names the file, the line and the column.
    """
    table = load_measured(MeasuredIrregularity(path=str(path), distance_column=distance_column))
    dist = table.distance
    if ds is None:
        ds = table.median_spacing
    n = n_points(float(dist[-1] - dist[0]), ds)
    grid = float(dist[0]) + ds * np.arange(n)
    return IrregularityProfile(float(dist[0]), ds, *_measured_rails(table, scale, grid))


def _measured_rails(table: MeasuredTable, scale: float, grid: np.ndarray) -> list[np.ndarray]:
    """Rail irregularities (m) of checked measured data, interpolated at ``grid`` (m)."""

    def col(key: str) -> np.ndarray:
        if key not in table.columns:
            return np.zeros(grid.size)
        return np.interp(grid, table.distance, table.columns[key], left=0.0, right=0.0)

    zv, ya, cl, g = (col(k) for k in COMPONENT_COLUMNS)
    return [
        scale * (zv + 0.5 * cl + col("z_left")),
        scale * (zv - 0.5 * cl + col("z_right")),
        scale * (ya + 0.5 * g + col("y_left")),
        scale * (ya - 0.5 * g + col("y_right")),
    ]


def _required_ds(exc: Excitation) -> float:
    """Grid step an excitation needs (m); inf when it has no requirement."""
    if isinstance(exc, RandomIrregularity):
        return exc.wavelength_min_m / POINTS_PER_WAVELENGTH
    if isinstance(exc, Corrugation | Settlement):
        return exc.wavelength_m / POINTS_PER_WAVELENGTH
    return math.inf


def build_profile(
    excitations: Iterable[Excitation],
    length_m: float,
    ds: float | None = None,
    half_gauge: float = GERMAN_HALF_GAUGE,
    sources: MeasuredSources = LIBRARY,
) -> IrregularityProfile:
    """Sum all excitations of a scenario into one rail irregularity profile.

    Parameters
    ----------
    excitations : iterable of Excitation
        Schema objects (:mod:`flexride.scenario.excitation`); an empty list gives a flat track.
    length_m : float
        Route length (m); the grid runs from 0 to at least ``length_m``. Measured data beyond
        it are cut off.
    ds : float, optional
        Grid step (m). Default: min(0.05 m, λ/20 for every wavelength present — the random
        λ_min, the corrugation and settlement wavelengths — and the spacing of measured data).
        A given ``ds`` is used as is; it must not exceed half of any of those wavelengths.
    half_gauge : float
        b, half distance between rail centres (m), for the random cross level.
    sources : MeasuredSources
        Where measured data may be read from (files by path in the library; the service's
        uploads only in the service).

    Returns
    -------
    IrregularityProfile
        The sum, with s0 = 0 and step ``ds``. A random irregularity fades in over its first
        :data:`~flexride.track.spectra.RANDOM_FADE_IN_M` (20 m).

    Raises
    ------
    ScenarioError
        Unusable measured data, located at its source field (``path``, ``upload``, ``rows``).
    """
    excs = list(excitations)
    measured = {i: load_measured(exc, sources) for i, exc in enumerate(excs)
                if isinstance(exc, MeasuredIrregularity)}
    if ds is None:
        ds = DEFAULT_DS
        for i, exc in enumerate(excs):
            ds = min(ds, _required_ds(exc))
            if i in measured:
                ds = min(ds, measured[i].median_spacing)
    total = IrregularityProfile.zeros(length_m, ds)
    n = total.n
    for i, exc in enumerate(excs):
        if isinstance(exc, RandomIrregularity):
            part = random_profile(
                length_m,
                exc.spectrum,
                exc.components,
                exc.wavelength_min_m,
                exc.wavelength_max_m,
                exc.seed,
                ds=ds,
                half_gauge=half_gauge,
                scale=exc.scale,
                table=exc.table,
            )
        elif isinstance(exc, Corrugation):
            part = corrugation_profile(
                length_m, exc.wavelength_m, exc.depth_m, exc.start_m, exc.length_m, exc.rails, ds
            )
        elif isinstance(exc, Settlement):
            part = settlement_profile(
                length_m, exc.wavelength_m, exc.depth_m, exc.position_m, exc.rails, ds
            )
        elif isinstance(exc, MeasuredIrregularity):
            part = IrregularityProfile(0.0, ds, *_measured_rails(measured[i], exc.scale, total.s))
        else:  # pragma: no cover - the union is closed
            raise ScenarioError(f"unknown excitation {type(exc).__name__}")
        for acc, add in zip(total.rails(), part.rails(), strict=True):
            acc += add[:n]
    return total

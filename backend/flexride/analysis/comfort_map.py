"""Comfort maps: one comfort measure at every node of a grid (e.g. the whole car-body floor).

The accelerations of all nodes come as one 2-D array ``[n_points, n_samples]``; every measure is
evaluated along the sample axis for a block of rows at a time (the filters, FFTs and running
sums are vectorised over rows), so thousands of nodes take about as long as the same number of
samples in one channel. Rows are processed in blocks of about ``block_samples`` values to bound
the memory of the intermediate arrays.

Measures
--------
``"sperling"``        Sperling index (form from ``form``, default spectral, see
                      :mod:`~flexride.analysis.sperling`); grades per GB 5599.
``"weighted_rms"``    ISO 2631 weighted rms a_w (m/s²); weighting default Wb for z
                      (ISO 2631-4 / EN 12299, rail), Wd for x and y.
``"cc_max"``          Largest EN 12299 continuous comfort C_c (5 s, every 1 s), m/s².
``"mtvv"``            ISO 2631-1 maximum 1 s running rms of the weighted acceleration, m/s².
``"vdv"``             ISO 2631-1 vibration dose value, m/s^1.75.
``"rms"``             Unweighted rms, m/s².
``"peak"``            Largest |a|, m/s².
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.analysis._common import check_rate, check_signal
from flexride.analysis.iso2631 import _window_rms
from flexride.analysis.sperling import (
    DEFAULT_SPERLING_FORM,
    SperlingForm,
    sperling,
    sperling_grade,
)
from flexride.analysis.weighting import apply_weighting
from flexride.errors import AnalysisError

__all__ = ["MEASURES", "ComfortMap", "comfort_map"]

MEASURES = ("sperling", "weighted_rms", "cc_max", "mtvv", "vdv", "rms", "peak")


@dataclass
class ComfortMap:
    """A comfort measure at every node.

    Attributes
    ----------
    values : numpy.ndarray
        Measure per node, shape ``(n_points,)``, in ``unit``.
    measure : str
        One of :data:`MEASURES`.
    direction : str
        ``"x"``, ``"y"`` or ``"z"``.
    unit : str
        Unit of ``values``.
    method : str
        Method (form, weighting, standard) that produced the values.
    grades : list of str or None
        GB 5599 grade per node (Sperling only).
    coordinates : numpy.ndarray or None
        Node coordinates as given (m).
    max_value : float
        Largest value; ``argmax`` the node index where it occurs.
    """

    values: np.ndarray
    measure: str
    direction: str
    unit: str
    method: str
    grades: list[str] | None = None
    coordinates: np.ndarray | None = None
    max_value: float = float("nan")
    argmax: int = -1
    parameters: dict[str, Any] = field(default_factory=dict)


def _direction(direction: str) -> str:
    d = str(direction).lower()
    aliases = {"z": "z", "vertical": "z", "y": "y", "lateral": "y", "x": "x",
               "longitudinal": "x"}
    if d not in aliases:
        raise AnalysisError(f"direction must be 'x', 'y' or 'z', got {direction!r}")
    return aliases[d]


def comfort_map(
    acc: np.ndarray,
    fs: float,
    *,
    measure: str = "sperling",
    direction: str = "z",
    form: SperlingForm = DEFAULT_SPERLING_FORM,
    weighting: str | None = None,
    coordinates: np.ndarray | None = None,
    block_samples: int = 4_000_000,
    **kwargs: Any,
) -> ComfortMap:
    """Evaluate a comfort measure at every node of a grid.

    Parameters
    ----------
    acc : array_like
        Accelerations in m/s², shape ``(n_points, n_samples)``.
    fs : float
        Sample rate in Hz.
    measure : str
        One of :data:`MEASURES` (default ``"sperling"``).
    direction : {"x", "y", "z"}
        Direction of the accelerations.
    form : {"spectral", "filter"}
        Sperling form (Sperling only).
    weighting : str, optional
        ISO weighting for ``weighted_rms``/``mtvv``/``vdv`` (default Wb for z, Wd for x, y).
    coordinates : array_like, optional
        Node coordinates, shape ``(n_points, 2 or 3)`` (m); stored with the map.
    block_samples : int
        Approximate number of values processed at once (memory bound).
    **kwargs
        Passed to the Sperling function (segment length, band...).

    Returns
    -------
    ComfortMap
    """
    if measure not in MEASURES:
        raise AnalysisError(f"unknown comfort measure {measure!r}; choose from {MEASURES}")
    d = _direction(direction)
    fs = check_rate(fs)
    a = check_signal(acc, fs, name="node accelerations", ndim=(2,), method="a comfort map")
    n_pts, n = a.shape
    coords = _coordinates(coordinates, n_pts)
    if measure == "sperling" and d == "x":
        raise AnalysisError("the Sperling index is defined for the vertical and lateral directions")
    wname = weighting or ("Wb" if d == "z" else "Wd")
    rows = max(1, int(block_samples // n))
    values = np.empty(n_pts)
    method = ""
    params: dict[str, Any] = {}
    for r0 in range(0, n_pts, rows):
        values[r0:r0 + rows], method, params = _block_values(
            a[r0:r0 + rows], fs, measure, d, form, wname, params, kwargs)
    unit = {"sperling": "-", "vdv": "m/s^1.75"}.get(measure, "m/s^2")
    i = int(np.argmax(values))
    grades = [sperling_grade(v) for v in values] if measure == "sperling" else None
    return ComfortMap(values=values, measure=measure, direction=d, unit=unit, method=method,
                      grades=grades, coordinates=coords, max_value=float(values[i]), argmax=i,
                      parameters=params)


def _coordinates(coordinates: np.ndarray | None, n_pts: int) -> np.ndarray | None:
    """Node coordinates (m) as a float array of ``n_pts`` rows, or None when not given.

    Raises
    ------
    AnalysisError
        If the array is not two-dimensional with one row per node.
    """
    if coordinates is None:
        return None
    coords = np.asarray(coordinates, dtype=np.float64)
    if coords.ndim != 2 or coords.shape[0] != n_pts:
        raise AnalysisError(
            f"coordinates must have shape (n_points={n_pts}, 2 or 3), got {coords.shape}"
        )
    return coords


def _block_values(
    blk: np.ndarray,
    fs: float,
    measure: str,
    d: str,
    form: SperlingForm,
    wname: str,
    params: dict[str, Any],
    kwargs: dict[str, Any],
) -> tuple[np.ndarray, str, dict[str, Any]]:
    """The measure at each node of one block of rows.

    Parameters
    ----------
    blk : numpy.ndarray
        Accelerations (m/s²) of the block's nodes, ``(rows, n_samples)``.
    fs : float
        Sample rate (Hz).
    measure, d, form : str
        Measure, direction (``x``, ``y``, ``z``) and Sperling form, as for :func:`comfort_map`.
    wname : str
        ISO weighting of ``weighted_rms``, ``mtvv`` and ``vdv``.
    params : dict
        Parameters so far (returned unchanged by measures without parameters).
    kwargs : dict
        Passed to the Sperling function.

    Returns
    -------
    values : numpy.ndarray
        One value per node (unit of the measure, see :func:`comfort_map`).
    method : str
        What produced the values.
    params : dict
        Parameters of the method.
    """
    n = blk.shape[-1]
    if measure == "sperling":
        res = sperling(blk, fs, "vertical" if d == "z" else "lateral", form=form, **kwargs)
        return np.asarray(res.value), res.method, res.parameters
    if measure == "rms":
        return np.sqrt(np.mean(blk * blk, axis=-1)), "unweighted rms", params
    if measure == "peak":
        return np.max(np.abs(blk), axis=-1), "largest absolute acceleration", params
    ww = "Wb" if measure == "cc_max" and d == "z" else ("Wd" if measure == "cc_max" else wname)
    aw = apply_weighting(blk, fs, ww)
    if measure == "weighted_rms":
        values = np.sqrt(np.mean(aw * aw, axis=-1))
        method = f"ISO 2631 {ww}-weighted rms (iir filter)"
    elif measure == "vdv":
        values = (np.sum(aw**4, axis=-1) / fs) ** 0.25
        method = f"ISO 2631-1 VDV of the {ww}-weighted acceleration"
    elif measure == "mtvv":
        if n < round(fs):
            raise AnalysisError("MTVV needs a record of at least 1 s")
        _, rr = _window_rms(aw, fs, round(fs), 1)
        values = rr.max(axis=-1)
        method = f"ISO 2631-1 MTVV (1 s linear running rms) of the {ww}-weighted acceleration"
    else:  # cc_max
        if n < round(5 * fs):
            raise AnalysisError("EN 12299 continuous comfort needs a record of at least 5 s")
        _, cc = _window_rms(aw, fs, round(5 * fs), round(fs))
        values = cc.max(axis=-1)
        method = f"EN 12299:2009 maximum continuous comfort C_c ({ww}, 5 s every 1 s)"
    return values, method, {"weighting": ww}

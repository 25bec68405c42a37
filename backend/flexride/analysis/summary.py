"""The summary of an analysed run: what :func:`~flexride.analysis.pipeline.analyze` returns.

:class:`Summary` holds, per car-body output point (:class:`PointSummary`) and direction
(:class:`DirectionSummary`), every measure of the run, plus the cross-correlations
(:class:`CorrelationSummary`), running safety and the peaks of the other acceleration channels.
:class:`SuspensionForceSummary` holds the statistics of each recorded suspension force
(the air springs: ``summary.suspension["secondary.1L"]["z"]``).
:meth:`Summary.to_dict` / :meth:`Summary.to_json` give its JSON form (the one the CLI, the
service and the dashboard read); :meth:`Summary.value` picks one scalar for tables and
regressions.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.analysis._common import jsonable
from flexride.analysis.correlation import CrossCorrelation
from flexride.analysis.en12299 import ContinuousComfort, MeanComfort
from flexride.analysis.iso2631 import Iso2631Result
from flexride.analysis.safety import RunningSafety
from flexride.analysis.spectra import SpectralPeak, Spectrum
from flexride.analysis.sperling import SperlingResult
from flexride.analysis.statistics import PeakStats
from flexride.analysis.timefreq import Spectrogram
from flexride.errors import AnalysisError

__all__ = [
    "ISO_WEIGHTINGS",
    "CorrelationSummary",
    "DirectionSummary",
    "PointSummary",
    "Summary",
    "SuspensionForceSummary",
]

ISO_WEIGHTINGS: dict[str, tuple[str, ...]] = {"z": ("Wb", "Wk"), "y": ("Wd",), "x": ("Wd",)}
"""ISO 2631 weightings evaluated per direction; the first is the comfort weighting (a_w, C_c,
N_MV)."""


@dataclass
class DirectionSummary:
    """Everything computed for one car-body channel.

    Attributes
    ----------
    channel : str
        Channel name, e.g. ``carbody.PR.acc.z``.
    direction : str
        ``"x"``, ``"y"`` or ``"z"``.
    peaks : PeakStats
        Statistics of the raw record (m/s²).
    dynamic_peaks : PeakStats or None
        Statistics of the dynamic part (quasi-static part removed).
    quasi_static_max_abs : float or None
        Largest |quasi-static part| (m/s²).
    sperling : SperlingResult or None
        Sperling index in the default form (y, z only).
    sperling_alternative : SperlingResult or None
        Sperling index in the other form.
    iso2631 : dict of str to Iso2631Result
        ISO 2631-1 evaluation per weighting (z: Wb, Wk; x, y: Wd).
    continuous_comfort : ContinuousComfort or None
        EN 12299 C_c(t) (Wb for z, Wd for x, y).
    dominant_peaks : list of SpectralPeak
        Dominant peaks of the Welch PSD of the dynamic part ((m/s²)²/Hz).
    psd, spectrogram : optional
        Arrays for the dashboard (``analyze(arrays=True)``).
    errors : dict of str to str
        Measures that could not be computed and why.
    """

    channel: str
    direction: str
    peaks: PeakStats
    dynamic_peaks: PeakStats | None = None
    quasi_static_max_abs: float | None = None
    sperling: SperlingResult | None = None
    sperling_alternative: SperlingResult | None = None
    iso2631: dict[str, Iso2631Result] = field(default_factory=dict)
    continuous_comfort: ContinuousComfort | None = None
    dominant_peaks: list[SpectralPeak] = field(default_factory=list)
    psd: Spectrum | None = None
    spectrogram: Spectrogram | None = None
    errors: dict[str, str] = field(default_factory=dict)


@dataclass
class PointSummary:
    """One car-body output point: its directions and its EN 12299 mean comfort.

    Attributes
    ----------
    name : str
        Point name (``PR``, ``PFB``...).
    on_floor : bool or None
        Whether the point is on the floor (EN 12299 is defined there); None if unknown.
    directions : dict of str to DirectionSummary
        By direction ``"z"``, ``"y"``, ``"x"``.
    mean_comfort : MeanComfort or None
        EN 12299 N_MV from the point's directions.
    """

    name: str
    on_floor: bool | None
    directions: dict[str, DirectionSummary] = field(default_factory=dict)
    mean_comfort: MeanComfort | None = None
    notes: list[str] = field(default_factory=list)
    errors: dict[str, str] = field(default_factory=dict)


@dataclass
class CorrelationSummary:
    """Cross-correlation of a reference point with another point in one direction.

    ``result`` follows :mod:`~flexride.analysis.correlation` (a = reference, b = other;
    a maximum at τ > 0 means the other point lags the reference). ``curve`` holds lags (s) and
    the normalised correlation when arrays are requested.
    """

    reference: str
    other: str
    direction: str
    result: CrossCorrelation
    curve: dict[str, np.ndarray] | None = None


@dataclass
class SuspensionForceSummary:
    """Statistics of one suspension force channel over the evaluated record (N).

    The channel ``<stage>.<element>.force.<direction>`` (e.g. ``secondary.1L.force.z``) is the
    force the element exerts on the car body, in its track frame, vertical positive up
    (:class:`~flexride.results.Channel`).

    Attributes
    ----------
    mean : float
        Mean of the record f (N): the static part (an air spring's share of the car body's
        weight, vertically).
    rms_dynamic : float
        Root mean square of f − mean (N).
    peak_dynamic : float
        Largest |f − mean| (N).
    max_abs : float
        Largest |f| (N).
    """

    mean: float
    rms_dynamic: float
    peak_dynamic: float
    max_abs: float

    @classmethod
    def of(cls, f: np.ndarray) -> SuspensionForceSummary:
        """The statistics of the force record ``f`` (N, at least one sample)."""
        f = np.asarray(f, dtype=np.float64)
        mean = float(np.mean(f))
        dyn = f - mean
        return cls(mean=mean, rms_dynamic=float(np.sqrt(np.mean(dyn * dyn))),
                   peak_dynamic=float(np.max(np.abs(dyn))), max_abs=float(np.max(np.abs(f))))


@dataclass
class Summary:
    """Analysis of one run.

    Attributes
    ----------
    run : dict
        Duration (s), sample rate (Hz), samples, speed (m/s, km/h), scenario name.
    settings : dict
        Every pinned default and the standard editions followed.
    points : dict of str to PointSummary
        Car-body output points in table order.
    correlations : list of CorrelationSummary
        Reference point against every other point, z and y.
    safety : RunningSafety or None
        Running-safety indices, if the run recorded wheel–rail forces.
    other_channels : dict of str to PeakStats
        Peak statistics of non-car-body acceleration channels.
    suspension : dict of str to dict of str to SuspensionForceSummary
        Recorded suspension forces by element (``secondary.1L`` …) and direction (``x``,
        ``y``, ``z``), in N.
    notes : list of str
        Remarks about the analysis (skipped channels...).
    """

    run: dict[str, Any]
    settings: dict[str, Any]
    points: dict[str, PointSummary]
    correlations: list[CorrelationSummary] = field(default_factory=list)
    safety: RunningSafety | None = None
    other_channels: dict[str, PeakStats] = field(default_factory=dict)
    suspension: dict[str, dict[str, SuspensionForceSummary]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-compatible dictionary (NaN and inf become None, arrays become lists)."""
        return jsonable(self)

    def to_json(self, **kwargs: Any) -> str:
        """JSON text of :meth:`to_dict` (keyword arguments go to :func:`json.dumps`)."""
        kwargs.setdefault("ensure_ascii", False)
        return json.dumps(self.to_dict(), **kwargs)

    def value(self, point: str, direction: str, quantity: str) -> float:
        """One scalar of the summary, for tables and regressions.

        Parameters
        ----------
        point : str
            Point name.
        direction : str
            ``"z"``, ``"y"`` or ``"x"``.
        quantity : str
            ``"peak"`` (largest |a| of the raw record, m/s²), ``"dynamic_peak"``,
            ``"sperling"`` (default form), ``"sperling_alternative"``, ``"a_w"`` (first ISO
            weighting: Wb for z, Wd for y), ``"a_wk"`` (Wk, z only), ``"cc_max"``, ``"rms"``
            or ``"n_mv"`` (direction ignored).
        """
        p = self.points.get(point)
        if p is None:
            raise AnalysisError(f"no point {point!r} in the summary; points: {list(self.points)}")
        if quantity == "n_mv":
            if p.mean_comfort is None:
                return math.nan
            return p.mean_comfort.value
        d = p.directions.get(direction)
        if d is None:
            raise AnalysisError(f"point {point} has no direction {direction!r}")
        if quantity == "peak":
            return float(d.peaks.max_abs)
        if quantity == "rms":
            return float(d.peaks.rms)
        if quantity == "dynamic_peak":
            return float(d.dynamic_peaks.max_abs) if d.dynamic_peaks else math.nan
        if quantity in ("sperling", "sperling_alternative"):
            s = getattr(d, quantity)
            return float(s.value) if s is not None else math.nan
        if quantity == "a_w":
            first = ISO_WEIGHTINGS[d.direction][0]
            return d.iso2631[first].a_w if first in d.iso2631 else math.nan
        if quantity == "a_wk":
            return d.iso2631["Wk"].a_w if "Wk" in d.iso2631 else math.nan
        if quantity == "cc_max":
            return d.continuous_comfort.maximum if d.continuous_comfort else math.nan
        raise AnalysisError(f"unknown summary quantity {quantity!r}")

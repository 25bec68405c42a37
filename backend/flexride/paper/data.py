"""The study's results as the claims read them: run records by condition, speed, body model
and seed, and estimates (mean ± 95 % CI over seeds) of any quantity of a record.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.paper import measures
from flexride.paper.measures import Estimate, mean_ci
from flexride.paper.reference import EXAMPLE_SPEED_KMH
from flexride.study.summary_values import summary_value

__all__ = ["NotComparable", "StudyData", "record_psd", "record_value"]


class NotComparable(Exception):
    """flexride has no value for a claim in this study (a condition, speed or array missing);
    the message says what is missing.
    """


def record_psd(record: dict[str, Any], point: str, direction: str
               ) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies (Hz) and Welch PSD ((m/s²)²/Hz) of the dynamic part at a point.

    Raises
    ------
    NotComparable
        If the record has no such PSD.
    """
    psd = record.get("psd") or {}
    key = f"{point}.{direction}"
    if "f" not in psd or key not in psd:
        raise NotComparable(f"no PSD of {key} in run {record['spec']}")
    return (np.asarray(psd["f"], dtype=float),
            np.asarray([np.nan if v is None else v for v in psd[key]], dtype=float))


def record_value(record: dict[str, Any], point: str, direction: str,
                 quantity: str) -> float | None:
    """One number of a run record.

    ``quantity`` is ``sperling`` (spectral form), ``sperling_filter``, ``peak`` (largest |a|
    of the raw record, m/s²), ``rms`` (m/s²), ``a_w`` (ISO 2631 weighted rms, m/s²) or
    ``band:LO:HI`` (rms of the dynamic part between LO and HI Hz, from the PSD, m/s²).
    """
    if quantity.startswith("band:"):
        _, lo, hi = quantity.split(":")
        try:
            f, p = record_psd(record, point, direction)
        except NotComparable:
            return None
        return measures.band_rms(f, p, float(lo), float(hi))
    if quantity == "sperling_filter":
        try:
            d = record["summary"]["points"][point]["directions"][direction]
            v = d["sperling_alternative"]["value"]
        except (KeyError, TypeError):
            return None
        return float(v) if v is not None and math.isfinite(v) else None
    return summary_value(record.get("summary"), point, direction, quantity)


@dataclass
class StudyData:
    """Run records of the study and the modal analysis, with look-ups for the claims.

    Attributes
    ----------
    records : list of dict
        Run records (:mod:`flexride.paper.record`).
    modal : dict or None
        Table 1's modal analysis (:func:`flexride.paper.modal.car_body_modes`).
    """

    records: list[dict[str, Any]]
    modal: dict[str, Any] | None = None
    _index: dict[tuple[str, float, str], list[dict[str, Any]]] = field(
        default_factory=dict, init=False, repr=False)
    mesh_records: list[dict[str, Any]] = field(default_factory=list, init=False, repr=False)
    """Records of the element-size pre-calculation (a ``spec.element_size_m``), plan order."""

    def __post_init__(self) -> None:
        """Index the records by (condition, speed, body), seeds ascending; the element-size
        pre-calculation's records apart (:attr:`mesh_records`).
        """
        for rec in self.records:
            s = rec["spec"]
            if s.get("element_size_m") is not None:
                self.mesh_records.append(rec)
                continue
            key = (s["condition"], float(s["speed_kmh"]), s["body"])
            self._index.setdefault(key, []).append(rec)
        for runs in self._index.values():
            runs.sort(key=lambda r: r["spec"].get("seed") or 0)

    def runs(self, condition: str, speed: float, body: str) -> list[dict[str, Any]]:
        """Records of one condition, speed (km/h) and body model, by seed; NotComparable if
        none.
        """
        runs = self._index.get((condition, float(speed), body))
        if not runs:
            raise NotComparable(f"no {body} run of {condition} at {speed:g} km/h in this study")
        return runs

    def first(self, condition: str, speed: float, body: str) -> dict[str, Any]:
        """The record of the first seed (the presets' track) of a condition, speed, body."""
        return self.runs(condition, speed, body)[0]

    def speeds(self, condition: str, body: str = "flexible") -> list[float]:
        """Speeds (km/h) with runs of a condition and body model, ascending."""
        return sorted(v for (c, v, b) in self._index if c == condition and b == body)

    def example_speed(self, condition: str) -> float:
        """The paper's example speed (80 km/h) if run, else the highest speed run."""
        speeds = self.speeds(condition)
        if not speeds:
            raise NotComparable(f"condition {condition} is not in this study")
        return EXAMPLE_SPEED_KMH if EXAMPLE_SPEED_KMH in speeds else speeds[-1]

    def need_speeds(self, condition: str, n: int) -> list[float]:
        """Speeds of a condition, NotComparable when fewer than ``n``."""
        speeds = self.speeds(condition)
        if len(speeds) < n:
            raise NotComparable(f"needs at least {n} speeds of {condition}; this study has "
                                f"{len(speeds)}")
        return speeds

    def estimate(self, condition: str, speed: float, body: str,
                 fn: Callable[[dict[str, Any]], float | None]) -> Estimate:
        """Mean ± CI over seeds of ``fn(record)``; NotComparable when no seed gives a value."""
        vals = [v for v in (fn(r) for r in self.runs(condition, speed, body))
                if v is not None and math.isfinite(v)]
        if not vals:
            raise NotComparable(f"no value for {condition} at {speed:g} km/h ({body})")
        return mean_ci(vals)

    def value(self, condition: str, speed: float, body: str, point: str, direction: str,
              quantity: str) -> Estimate:
        """Mean ± CI over seeds of :func:`record_value`."""
        def fn(rec: dict[str, Any]) -> float | None:
            return record_value(rec, point, direction, quantity)

        try:
            return self.estimate(condition, speed, body, fn)
        except NotComparable as exc:
            raise NotComparable(f"{exc}: {quantity} at {point} {direction}") from None

    def mean(self, condition: str, speed: float, body: str, point: str, direction: str,
             quantity: str) -> float:
        """The mean of :meth:`value`."""
        return self.value(condition, speed, body, point, direction, quantity).mean

    def mean_psd(self, condition: str, speed: float, body: str, point: str,
                 direction: str) -> tuple[np.ndarray, np.ndarray]:
        """Frequencies (Hz) and the PSD averaged over seeds ((m/s²)²/Hz)."""
        spectra = [record_psd(r, point, direction) for r in self.runs(condition, speed, body)]
        f = spectra[0][0]
        same = [p for fr, p in spectra if fr.shape == f.shape]
        return f, np.nanmean(np.vstack(same), axis=0)

    def correlations(self, condition: str, speed: float, body: str, other: str,
                     direction: str = "z") -> list[dict[str, Any]]:
        """The correlation entries (reference PRB) with ``other``, one per seed."""
        out = []
        for rec in self.runs(condition, speed, body):
            hit = [c for c in rec.get("correlations", [])
                   if c["other"] == other and c["direction"] == direction]
            out += hit[:1]
        if not out:
            raise NotComparable(f"no cross-correlation (PRB, {other}) {direction} in "
                                f"{condition} at {speed:g} km/h")
        return out

    def paired_ratio(self, condition: str, speed: float, point: str, direction: str,
                     quantity: str) -> Estimate:
        """Flexible/rigid ratio of a quantity, seed by seed (same track), mean ± CI."""
        flex = self.runs(condition, speed, "flexible")
        rigid = {r["spec"].get("seed"): r for r in self.runs(condition, speed, "rigid")}
        ratios = []
        for rf in flex:
            rr = rigid.get(rf["spec"].get("seed"))
            a = record_value(rf, point, direction, quantity)
            b = record_value(rr, point, direction, quantity) if rr is not None else None
            if a is not None and b:
                ratios.append(a / b)
        if not ratios:
            raise NotComparable(f"no rigid/flexible pair of {condition} at {speed:g} km/h")
        return mean_ci(ratios)


def speed_series(data: StudyData, condition: str, body: str, point: str, direction: str,
                 quantity: str, speeds: Sequence[float] | None = None) -> list[float]:
    """Means of a quantity at each speed (km/h) of ``speeds`` (default all of the condition)."""
    speeds = list(speeds) if speeds is not None else data.speeds(condition, body)
    return [data.mean(condition, v, body, point, direction, quantity) for v in speeds]

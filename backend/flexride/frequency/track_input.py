"""Track irregularity spectra as inputs of the linear model, in time at the running speed.

The German spectra of :mod:`flexride.track.spectra` are one-sided, S(Ω) in m²/(rad/m) against
the spatial angular frequency Ω (rad/m), and the random synthesis of the time-domain solver
uses them between 2π/λ_max and 2π/λ_min with hard band edges, scaled by ``scale²``. A wheel
running at V sees the profile r(V t): a spatial angular frequency Ω becomes the temporal
frequency f = VΩ/2π (Hz). Equating the variance in corresponding bands,
S(Ω) dΩ = G(f) df with dΩ = 2π df / V, gives the one-sided temporal spectrum

    G(f) = (2π / V) · S(2π f / V)          (m²/Hz, or rad²/Hz for the cross-level angle)

inside the band V/λ_max ≤ f ≤ V/λ_min and zero outside it. Every wheelset sees the same
profile later by its distance behind the leading one.

Components map to the rails as in the synthesis (z_left = z_v + b·c, z_right = z_v − b·c,
y_left = y_a + g/2, y_right = y_a − g/2): :data:`RAIL_MAP` gives, per component, the rail
irregularities per unit component.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from flexride.frequency.errors import LinearisationError
from flexride.frequency.measured_input import MeasuredInput, measured_input
from flexride.scenario.excitation import (
    IRREGULARITY_COMPONENTS,
    MeasuredIrregularity,
    RandomIrregularity,
    SpectrumTable,
)
from flexride.scenario.scenario import Scenario
from flexride.track.measured import LIBRARY, MeasuredSources
from flexride.track.spectra import component_psd

__all__ = ["STATIONARY_KINDS", "RandomInput", "TrackSpectra", "rail_map", "track_spectra"]

STATIONARY_KINDS = ("random", "measured")
"""Excitation kinds the estimate takes as stationary random inputs (their spectra)."""


def rail_map(component: str, half_gauge: float) -> np.ndarray:
    """Rail irregularities (z left, z right, y left, y right) per unit of ``component``.

    Parameters
    ----------
    component : {"vertical", "alignment", "cross_level", "gauge"}
        Irregularity component (cross level as an angle in rad, the others in m).
    half_gauge : float
        b, half distance between the rail centres (m).

    Returns
    -------
    numpy.ndarray
        (4,) m per m (or m per rad for cross level).
    """
    b = half_gauge
    maps = {"vertical": (1.0, 1.0, 0.0, 0.0), "cross_level": (b, -b, 0.0, 0.0),
            "alignment": (0.0, 0.0, 1.0, 1.0), "gauge": (0.0, 0.0, 0.5, -0.5)}
    return np.array(maps[component])


@dataclass(frozen=True)
class RandomInput:
    """One random irregularity: German spectra or the user's table.

    Attributes
    ----------
    level : str
        ``"german-high"``, ``"german-low"`` or ``"table"``.
    components : tuple of str
        Components present.
    wavelength_min_m, wavelength_max_m : float
        Band (m), hard edges.
    scale : float
        Amplitude factor (-); the spectrum scales by its square.
    table : SpectrumTable or None
        The user's spectra (``level`` ``"table"``).
    """

    level: str
    components: tuple[str, ...]
    wavelength_min_m: float
    wavelength_max_m: float
    scale: float = 1.0
    table: SpectrumTable | None = None

    def temporal_psd(self, component: str, f: np.ndarray, speed: float,
                     half_gauge: float) -> np.ndarray:
        """One-sided temporal PSD G(f) of ``component`` at speed ``speed`` (m/s).

        Parameters
        ----------
        component : str
            Irregularity component.
        f : numpy.ndarray
            Frequencies (Hz), ≥ 0.
        speed : float
            Running speed V (m/s).
        half_gauge : float
            b of the cross-level spectrum (m).

        Returns
        -------
        numpy.ndarray
            G(f) in m²/Hz (rad²/Hz for cross level); zero outside the band and for absent
            components.
        """
        f = np.asarray(f, dtype=float)
        if component not in self.components:
            return np.zeros_like(f)
        omega = 2.0 * np.pi * f / speed
        band = (omega >= 2.0 * np.pi / self.wavelength_max_m) & (
            omega <= 2.0 * np.pi / self.wavelength_min_m)
        s = component_psd(self.level, component, half_gauge, self.table)(omega) * self.scale**2
        return np.where(band, 2.0 * np.pi / speed * s, 0.0)

    def to_dict(self) -> dict:
        """JSON form."""
        return {"kind": "random", "spectrum": self.level, "components": list(self.components),
                "wavelength_min_m": self.wavelength_min_m,
                "wavelength_max_m": self.wavelength_max_m, "scale": self.scale,
                "table": None if self.table is None else self.table.model_dump(mode="json")}


@dataclass(frozen=True)
class TrackSpectra:
    """Independent random irregularities (their spectra add) and the b of the rail mapping.

    Attributes
    ----------
    inputs : tuple of RandomInput or MeasuredInput
        The random irregularities: German spectra and measured records' spectra.
    half_gauge : float
        b, half distance between rail centres (m).
    """

    inputs: tuple[RandomInput | MeasuredInput, ...]
    half_gauge: float = 0.75
    components: tuple[str, ...] = field(default=IRREGULARITY_COMPONENTS)

    def psd(self, f: np.ndarray, speed: float) -> np.ndarray:
        """(n_components, n_f) one-sided temporal PSD of each component (m²/Hz, rad²/Hz)."""
        out = np.zeros((len(self.components), np.size(f)))
        for inp in self.inputs:
            for i, c in enumerate(self.components):
                out[i] += inp.temporal_psd(c, f, speed, self.half_gauge)
        return out

    def rail_maps(self) -> np.ndarray:
        """(n_components, 4) rail irregularities per unit component (see :func:`rail_map`)."""
        return np.array([rail_map(c, self.half_gauge) for c in self.components])

    def to_dict(self) -> dict:
        """JSON form."""
        return {"inputs": [i.to_dict() for i in self.inputs], "half_gauge_m": self.half_gauge,
                "components": list(self.components),
                "convention": "one-sided temporal PSD G(f) = (2π/V)·S(2πf/V) in the band "
                              "V/λ_max…V/λ_min"}


def track_spectra(scenario: Scenario, components: Sequence[str] | None = None,
                  sources: MeasuredSources = LIBRARY) -> TrackSpectra:
    """The random irregularities of a scenario as :class:`TrackSpectra`: the German spectra
    of its random excitations and the Welch spectra of its measured ones
    (:mod:`flexride.frequency.measured_input`; ``sources`` says where uploads are read from).

    Raises
    ------
    LinearisationError
        An excitation that is not a stationary random process (corrugation, settlement), a
        measured record too short for a spectrum, or no random excitation at all.
    ScenarioError
        A measured record that cannot be read.
    """
    half_gauge = scenario.track.rail_centre_half_distance
    inputs: list[RandomInput | MeasuredInput] = []
    for i, exc in enumerate(scenario.excitation):
        if isinstance(exc, MeasuredIrregularity):
            inputs.append(measured_input(exc, half_gauge, sources, f"excitation[{i}]"))
            continue
        if not isinstance(exc, RandomIrregularity):
            raise LinearisationError(
                f"excitation[{i}] is a {exc.kind} excitation: a transient or deterministic "
                "defect, not a stationary random irregularity; the frequency-domain estimate "
                "covers random irregularities only (use the time-domain solver)", "excitation")
        comps = tuple(c for c in exc.components if components is None or c in components)
        inputs.append(RandomInput(exc.spectrum, comps, exc.wavelength_min_m,
                                  exc.wavelength_max_m, exc.scale, exc.table))
    if not inputs:
        raise LinearisationError("the scenario has no random irregularity to estimate the "
                                 "response to", "excitation")
    return TrackSpectra(tuple(inputs), half_gauge)

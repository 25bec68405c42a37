"""A measured track irregularity as an input of the frequency-domain estimate: its one-sided
spatial spectra, estimated from the record.

The time-domain solver runs a measured profile as it is; the linear model needs its spectrum.
Each component of the generator's convention is formed from the measured rails (z_left =
z_v + b·c, z_right = z_v − b·c, y_left = y_a + g/2, y_right = y_a − g/2, so z_v and y_a are the
rails' means, c = (z_left − z_right)/(2b) the cross-level angle and g = y_left − y_right the
gauge deviation), resampled linearly onto a uniform grid at the record's median spacing, and its
spectrum is the Welch estimate of :func:`flexride.track.spectra.spatial_psd` (Hann segments,
50 % overlap, mean removed per segment). The components are taken as independent, as in the
random generator: a measured record's correlation between, e.g., vertical profile and cross
level is not carried into the estimate (it would need the cross-spectra).

The spectrum holds between the segment's longest wavelength and twice the sampling step
(Nyquist); outside it the input is zero, and the record should be long against the wavelengths
that matter (a few segments at least; the estimate says how many it averaged).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexride.frequency.errors import LinearisationError
from flexride.scenario.excitation import IRREGULARITY_COMPONENTS, MeasuredIrregularity
from flexride.track.measured import LIBRARY, MeasuredSources, MeasuredTable, load_measured
from flexride.track.spectra import spatial_psd

__all__ = ["MeasuredInput", "measured_input"]

MIN_SEGMENTS = 4
"""Fewest Welch segments (with 50 % overlap) a record must give for its spectrum (-)."""
SEGMENT_M = 200.0
"""Shortest Welch segment (m; a power of two of samples at or above it): wavelengths up to
this are resolved, the German spectra's band (1–80 m, up to 120 m) included."""


@dataclass(frozen=True)
class MeasuredInput:
    """The spatial spectra of a measured irregularity.

    Attributes
    ----------
    source : str
        What was measured (the excitation's source, for messages).
    omega : numpy.ndarray
        Spatial angular frequencies Ω of the spectrum lines (rad/m), ascending.
    spectra : dict of str to numpy.ndarray
        S(Ω) per component present, m²/(rad/m) (rad²/(rad/m) for cross level).
    spacing_m, length_m : float
        Sampling step and length of the record (m).
    segments : int
        Welch segments averaged.
    """

    source: str
    omega: np.ndarray
    spectra: dict[str, np.ndarray]
    spacing_m: float
    length_m: float
    segments: int

    @property
    def components(self) -> tuple[str, ...]:
        """Components present (nonzero in the record)."""
        return tuple(c for c in IRREGULARITY_COMPONENTS if c in self.spectra)

    def temporal_psd(self, component: str, f: np.ndarray, speed: float,
                     half_gauge: float) -> np.ndarray:
        """One-sided temporal PSD G(f) = (2π/V)·S(2πf/V) of ``component`` (m²/Hz, rad²/Hz for
        cross level) at speed ``speed`` (m/s); zero outside the record's resolved band and for
        absent components. ``half_gauge`` is not used (the cross level is measured).
        """
        f = np.asarray(f, dtype=float)
        s = self.spectra.get(component)
        if s is None:
            return np.zeros_like(f)
        omega = 2.0 * np.pi * f / speed
        inside = (omega >= self.omega[1]) & (omega <= self.omega[-1])
        return np.where(inside, 2.0 * np.pi / speed * np.interp(omega, self.omega, s), 0.0)

    def to_dict(self) -> dict:
        """JSON form."""
        return {"kind": "measured", "source": self.source, "components": list(self.components),
                "wavelength_min_m": 2.0 * np.pi / float(self.omega[-1]),
                "wavelength_max_m": 2.0 * np.pi / float(self.omega[1]),
                "spacing_m": self.spacing_m, "length_m": self.length_m,
                "welch_segments": self.segments,
                "convention": "Welch estimate of the record, components independent"}


def _rails(table: MeasuredTable, s: np.ndarray) -> dict[str, np.ndarray]:
    """z_left, z_right, y_left, y_right (m) of the table on the grid ``s`` (as the solver
    combines the columns: track.measured).
    """
    def col(name: str) -> np.ndarray:
        v = table.columns.get(name)
        return np.zeros_like(s) if v is None else np.interp(s, table.distance, v)

    zv, c, ya, g = col("vertical"), col("cross_level"), col("alignment"), col("gauge")
    return {"z_left": zv + 0.5 * c + col("z_left"), "z_right": zv - 0.5 * c + col("z_right"),
            "y_left": ya + 0.5 * g + col("y_left"), "y_right": ya - 0.5 * g + col("y_right")}


def _components(rails: dict[str, np.ndarray], half_gauge: float) -> dict[str, np.ndarray]:
    """The generator's components of the rails (m; cross level in rad)."""
    return {"vertical": 0.5 * (rails["z_left"] + rails["z_right"]),
            "alignment": 0.5 * (rails["y_left"] + rails["y_right"]),
            "cross_level": (rails["z_left"] - rails["z_right"]) / (2.0 * half_gauge),
            "gauge": rails["y_left"] - rails["y_right"]}


def measured_input(exc: MeasuredIrregularity, half_gauge: float,
                   sources: MeasuredSources = LIBRARY, where: str = "excitation") -> MeasuredInput:
    """The spectra of a measured-irregularity excitation.

    Parameters
    ----------
    exc : MeasuredIrregularity
        The excitation.
    half_gauge : float
        b, half the distance between the rail centres (m), for the cross-level angle.
    sources : MeasuredSources
        Where uploads are read from and whether paths may be.
    where : str
        The excitation's place in the scenario, for messages.

    Raises
    ------
    ScenarioError
        The data cannot be read (located at the excitation's source field).
    LinearisationError
        The record is too short for :data:`MIN_SEGMENTS` Welch segments.
    """
    table = load_measured(exc, sources)
    ds = table.median_spacing
    s = np.arange(table.distance[0], table.distance[-1], ds)
    nperseg = 2 ** int(np.ceil(np.log2(max(SEGMENT_M / ds, 16.0))))
    segments = (s.size - nperseg) // (nperseg // 2) + 1
    if segments < MIN_SEGMENTS:
        need = (MIN_SEGMENTS + 1) * nperseg * ds / 2.0
        raise LinearisationError(
            f"{where}: the measured record ({s[-1] - s[0]:.0f} m) is too short for its "
            f"spectrum: {MIN_SEGMENTS} Welch segments of {nperseg * ds:.0f} m (wavelengths up "
            f"to {SEGMENT_M:.0f} m) need {need:.0f} m (use the time-domain solver)",
            "excitation")
    spectra, omega = {}, np.empty(0)
    for name, values in _components(_rails(table, s), half_gauge).items():
        if np.any(values != 0.0):
            omega, spectra[name] = spatial_psd(values, ds, nperseg)
    if not spectra:
        raise LinearisationError(f"{where}: the measured record is zero everywhere",
                                 "excitation")
    label = (exc.upload and f"upload {exc.upload[:12]}") or exc.path or "inline rows"
    return MeasuredInput(str(label), omega, spectra, ds, float(s[-1] - s[0]), int(segments))

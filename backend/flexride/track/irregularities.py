"""Track irregularities: German spectra, random synthesis, local defects, measured data.

All spectra here are **one-sided**, against the spatial angular frequency Ω in rad/m
(DESIGN §4): the variance of a component in a band is ∫ S(Ω) dΩ over that band.

Components and rail mapping
---------------------------
The German spectra (DESIGN §6) describe four components:

vertical z_v (m)
    Mean vertical position of the two rails, up positive. S_v in m²/(rad/m).
alignment y_a (m)
    Mean lateral position of the two rails, left positive. S_a in m²/(rad/m).
cross level c (rad)
    Cross-level **angle**. S_c = (A_v/b²)·Ω_c²Ω²/((Ω²+Ω_r²)(Ω²+Ω_c²)(Ω²+Ω_s²)) has units of
    rad²/(rad/m) (A_v in m²·rad/m divided by b² in m²), so it is the spectrum of the angle, not
    of a height. The rail height difference is Δz = z_left − z_right = 2b·c, whose spectrum is
    4b²·S_c = 4·A_v·Ω_c²Ω²/(…): at short wavelengths (Ω ≫ Ω_s) that is exactly four times S_v,
    which is what two independent rails give (the mean has half, the difference twice the
    single-rail spectrum), and at long wavelengths the rails are correlated and Δz is small.
    This reading is therefore the physically consistent one.
gauge g (m)
    Gauge deviation y_left − y_right, widening positive. S_g in m²/(rad/m).

With b the half distance between the rail centres (``half_gauge``, 0.75 m by default, the b of
the spectrum definition) the rail irregularities are::

    z_left  = z_v + b·c        y_left  = y_a + g/2
    z_right = z_v − b·c        y_right = y_a − g/2

(left rail at y = +b, right rail at y = −b, z up; DESIGN §4). When a different ``half_gauge``
is used, the same b enters S_c, so the rail height difference statistics do not change.

Random synthesis
----------------
:func:`random_profile` draws a stationary zero-mean Gaussian realisation by inverse FFT: on a
periodic grid of length L_p ≥ max(route length, 8·λ_max) every Fourier line k (Ω_k = 2πk/L_p)
gets independent Gaussian cosine and sine coefficients of variance E_k, where E_k is the exact
integral of the target spectrum over the line's bin [Ω_k − ΔΩ/2, Ω_k + ΔΩ/2] clipped to the
band [2π/λ_max, 2π/λ_min] (5-point Gauss–Legendre per bin). The band edges are **hard**
(rectangular, no taper): the expected variance of the periodic realisation equals the band
integral, i.e. :func:`band_rms` squared. The route profile is the first part of the period.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Literal

import numpy as np
from scipy import fft as sp_fft
from scipy import integrate, signal

from flexride.errors import ScenarioError
from flexride.model.excitation import (
    IRREGULARITY_COMPONENTS,
    Corrugation,
    MeasuredIrregularity,
    RandomIrregularity,
    Settlement,
)
from flexride.track.measured import (
    COMPONENT_COLUMNS,
    LIBRARY,
    RAIL_COLUMNS,
    MeasuredSources,
    MeasuredTable,
    load_measured,
)

if TYPE_CHECKING:
    from flexride.model.excitation import Excitation

__all__ = [
    "GERMAN_HALF_GAUGE",
    "GERMAN_SPECTRA",
    "OMEGA_C",
    "OMEGA_R",
    "OMEGA_S",
    "IrregularityProfile",
    "band_rms",
    "build_profile",
    "corrugation_profile",
    "german_psd",
    "measured_profile",
    "random_profile",
    "settlement_profile",
    "spatial_psd",
]

OMEGA_C = 0.8246
"""Cut-off frequency Ω_c of the German spectra (rad/m)."""
OMEGA_R = 0.0206
"""Cut-off frequency Ω_r of the German spectra (rad/m)."""
OMEGA_S = 0.4380
"""Cut-off frequency Ω_s of the German spectra (rad/m)."""
GERMAN_HALF_GAUGE = 0.75
"""b of the German cross-level spectrum: half distance between the rail centres (m)."""

GERMAN_SPECTRA: dict[str, dict[str, float]] = {
    "low": {"A_v": 4.032e-7, "A_a": 2.119e-7, "A_g": 5.32e-8},
    "high": {"A_v": 1.080e-6, "A_a": 6.125e-7, "A_g": 1.032e-7},
}
"""Roughness constants A_v, A_a, A_g (m²·rad/m) per disturbance level (DESIGN §6)."""

DEFAULT_DS = 0.05
"""Grid step used when no excitation needs a finer one (m)."""
POINTS_PER_WAVELENGTH = 20
"""Grid points per shortest wavelength (-): ds ≤ λ_min/20."""
_MIN_PERIODS = 8  # synthesis period ≥ 8·λ_max: ≥ 8 Fourier lines per Ω_min
_RAIL_KEYS = RAIL_COLUMNS
_GL_X, _GL_W = np.polynomial.legendre.leggauss(5)


def _level_key(level: str) -> str:
    key = level.removeprefix("german-")
    if key not in GERMAN_SPECTRA:
        raise ScenarioError(
            f"unknown spectrum level {level!r}; expected 'high', 'low', "
            "'german-high' or 'german-low'"
        )
    return key


def german_psd(
    omega: np.ndarray | float,
    component: str,
    level: str = "high",
    half_gauge: float = GERMAN_HALF_GAUGE,
) -> np.ndarray:
    """German track-irregularity spectrum (one-sided).

    Parameters
    ----------
    omega : array_like
        Spatial angular frequency Ω ≥ 0 (rad/m).
    component : {"vertical", "alignment", "cross_level", "gauge"}
        Irregularity component (see the module docstring for their definitions).
    level : {"high", "low", "german-high", "german-low"}
        Disturbance level.
    half_gauge : float
        b of the cross-level formula, half distance between rail centres (m); 0.75 m in the
        standard definition.

    Returns
    -------
    numpy.ndarray
        S(Ω): for vertical, alignment and gauge in m²/(rad/m); for cross level the spectrum of
        the cross-level **angle** in rad²/(rad/m) (rail height difference Δz = 2b·angle has the
        spectrum 4b²·S).

    Raises
    ------
    ScenarioError
        Unknown component or level, or negative Ω.
    """
    om = np.asarray(omega, dtype=float)
    if np.any(om < 0.0):
        raise ScenarioError("spatial frequency omega must be >= 0 rad/m (one-sided spectrum)")
    consts = GERMAN_SPECTRA[_level_key(level)]
    o2 = om * om
    base = OMEGA_C**2 / ((o2 + OMEGA_R**2) * (o2 + OMEGA_C**2))
    if component == "vertical":
        return consts["A_v"] * base
    if component == "alignment":
        return consts["A_a"] * base
    if component == "cross_level":
        return consts["A_v"] / half_gauge**2 * base * o2 / (o2 + OMEGA_S**2)
    if component == "gauge":
        return consts["A_g"] * base * o2 / (o2 + OMEGA_S**2)
    raise ScenarioError(
        f"unknown irregularity component {component!r}; expected one of "
        f"{', '.join(IRREGULARITY_COMPONENTS)}"
    )


def band_rms(
    level: str,
    component: str,
    wavelength_min: float,
    wavelength_max: float,
    half_gauge: float = GERMAN_HALF_GAUGE,
) -> float:
    """Root mean square of a German-spectrum component within a wavelength band.

    Parameters
    ----------
    level : {"high", "low", "german-high", "german-low"}
        Disturbance level.
    component : {"vertical", "alignment", "cross_level", "gauge"}
        Irregularity component.
    wavelength_min, wavelength_max : float
        Band limits (m), 0 < wavelength_min < wavelength_max.
    half_gauge : float
        b of the cross-level formula (m).

    Returns
    -------
    float
        sqrt(∫ S(Ω) dΩ) over Ω from 2π/wavelength_max to 2π/wavelength_min (numerical
        integration with :func:`scipy.integrate.quad`); in m, for cross level in rad.
    """
    if not 0.0 < wavelength_min < wavelength_max:
        raise ScenarioError(
            f"need 0 < wavelength_min < wavelength_max, got {wavelength_min} m, {wavelength_max} m"
        )
    value, _ = integrate.quad(
        lambda om: float(german_psd(om, component, level, half_gauge)),
        2.0 * math.pi / wavelength_max,
        2.0 * math.pi / wavelength_min,
        limit=200,
        epsabs=0.0,
        epsrel=1e-10,
    )
    return math.sqrt(value)


def spatial_psd(
    profile_values: np.ndarray, ds: float, nperseg: int | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Welch estimate of the one-sided spectrum of a uniformly sampled profile.

    Parameters
    ----------
    profile_values : numpy.ndarray
        Profile samples (m, or rad for an angle), uniformly spaced by ``ds``.
    ds : float
        Sample spacing (m).
    nperseg : int, optional
        Welch segment length (samples); default the largest power of two not above a quarter
        of the record (at least 16, at most the record length). Hann window, 50 % overlap,
        mean removed per segment.

    Returns
    -------
    omega : numpy.ndarray
        Spatial angular frequency Ω (rad/m).
    psd : numpy.ndarray
        One-sided spectrum S(Ω) in m²/(rad/m) (rad²/(rad/m) for an angle); ∫ S dΩ is the
        variance.
    """
    x = np.asarray(profile_values, dtype=float)
    if x.ndim != 1 or x.size < 16:
        raise ScenarioError("spatial_psd needs a 1-D profile of at least 16 samples")
    if not ds > 0.0:
        raise ScenarioError(f"sample spacing ds must be > 0 m, got {ds}")
    if nperseg is None:
        nperseg = max(16, 2 ** math.floor(math.log2(max(x.size // 4, 1))))
    nperseg = min(int(nperseg), x.size)
    f, g = signal.welch(x, fs=1.0 / ds, nperseg=nperseg, detrend="constant")
    # G(f) df = S(Ω) dΩ with Ω = 2πf
    return 2.0 * math.pi * f, g / (2.0 * math.pi)


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
        if not (math.isfinite(self.ds) and self.ds > 0.0):
            raise ValueError(f"ds must be a positive grid step in m, got {self.ds}")
        arrays = [np.ascontiguousarray(getattr(self, k), dtype=np.float64) for k in _RAIL_KEYS]
        n = arrays[0].shape
        if len(n) != 1 or n[0] < 1 or any(a.shape != n for a in arrays):
            raise ValueError("z_left, z_right, y_left, y_right must be 1-D of equal length >= 1")
        for key, arr in zip(_RAIL_KEYS, arrays, strict=True):
            setattr(self, key, arr)

    @classmethod
    def zeros(cls, length_m: float, ds: float, s0: float = 0.0) -> IrregularityProfile:
        """Flat track from ``s0`` to at least ``s0 + length_m`` (m) with step ``ds`` (m)."""
        n = _n_points(length_m, ds)
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
        return tuple(  # type: ignore[return-value]
            np.interp(sq, grid, getattr(self, k), left=0.0, right=0.0) for k in _RAIL_KEYS
        )

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
                *(getattr(self, k) + getattr(other, k) for k in _RAIL_KEYS),
            )
        ds = min(self.ds, other.ds)
        s0 = min(self.s0, other.s0)
        s_end = max(self.s_end, other.s_end)
        n = _n_points(s_end - s0, ds)
        grid = s0 + ds * np.arange(n)
        a = self.sample(grid)
        b = other.sample(grid)
        return IrregularityProfile(s0, ds, *(x + y for x, y in zip(a, b, strict=True)))

    def __radd__(self, other: object) -> IrregularityProfile:
        if isinstance(other, int | float) and other == 0:  # lets sum() start from 0
            return self
        return NotImplemented


def _n_points(length_m: float, ds: float) -> int:
    """Grid points covering [0, length_m] with step ds (last point at or just beyond)."""
    if not (math.isfinite(length_m) and length_m >= 0.0):
        raise ScenarioError(f"profile length must be a finite length >= 0 m, got {length_m}")
    if not (math.isfinite(ds) and ds > 0.0):
        raise ScenarioError(f"grid step ds must be > 0 m, got {ds}")
    return math.ceil(length_m / ds - 1e-9) + 1


def _check_step(ds: float, wavelength_m: float, what: str) -> None:
    """Reject a grid step that cannot represent the wavelength (ds > λ/2)."""
    if ds > 0.5 * wavelength_m * (1.0 + 1e-12):
        raise ScenarioError(
            f"grid step ds = {ds} m is too coarse for the {what} wavelength {wavelength_m} m "
            f"(need ds <= wavelength/2, better /{POINTS_PER_WAVELENGTH})"
        )


def _rail_mask(rails: str) -> tuple[float, float]:
    if rails == "both":
        return 1.0, 1.0
    if rails == "left":
        return 1.0, 0.0
    if rails == "right":
        return 0.0, 1.0
    raise ScenarioError(f"rails must be 'both', 'left' or 'right', got {rails!r}")


def _bin_energies(
    omega_k: np.ndarray,
    d_omega: float,
    om_lo: float,
    om_hi: float,
    psd: Callable[[np.ndarray], np.ndarray],
) -> np.ndarray:
    """∫ psd over [Ω_k − ΔΩ/2, Ω_k + ΔΩ/2] ∩ [om_lo, om_hi] per line (5-point Gauss–Legendre)."""
    a = np.maximum(omega_k - 0.5 * d_omega, om_lo)
    b = np.minimum(omega_k + 0.5 * d_omega, om_hi)
    width = np.clip(b - a, 0.0, None)
    mid = 0.5 * (a + b)
    half = 0.5 * width
    energy = np.zeros_like(omega_k)
    for x, w in zip(_GL_X, _GL_W, strict=True):
        energy += w * psd(np.maximum(mid + half * x, 0.0))
    return energy * half


def random_profile(
    length_m: float,
    spectrum_level: str = "high",
    components: Sequence[str] = IRREGULARITY_COMPONENTS,
    wavelength_min_m: float = 1.0,
    wavelength_max_m: float = 120.0,
    seed: int = 1,
    ds: float | None = None,
    half_gauge: float = GERMAN_HALF_GAUGE,
    scale: float = 1.0,
) -> IrregularityProfile:
    """Random track irregularity from the German spectra (stationary Gaussian synthesis).

    Parameters
    ----------
    length_m : float
        Route length to cover (m); the grid runs from 0 to at least ``length_m``.
    spectrum_level : {"high", "low", "german-high", "german-low"}
        Disturbance level of the German spectra.
    components : sequence of {"vertical", "alignment", "cross_level", "gauge"}
        Components to generate; the others are zero.
    wavelength_min_m, wavelength_max_m : float
        Wavelength band (m); the spectrum is used for 2π/λ_max ≤ Ω ≤ 2π/λ_min with hard edges.
    seed : int
        Seed (≥ 0). Each component uses its own child stream of ``SeedSequence(seed)`` (in the
        fixed order vertical, alignment, cross_level, gauge), so components are independent and
        selecting a subset does not change the others. The realisation also depends on the
        synthesis length (hence on ``length_m`` when it exceeds 8·λ_max) and on ``ds``.
    ds : float, optional
        Grid step (m); default λ_min/20. Must not exceed λ_min/2 (Nyquist).
    half_gauge : float
        b, half distance between rail centres (m): z_left/right = z_v ± b·c.
    scale : float
        Amplitude factor (-); the spectrum is scaled by ``scale**2``.

    Returns
    -------
    IrregularityProfile
        Rail irregularities (m) with s0 = 0. Rail mapping: z_left = z_v + b·c,
        z_right = z_v − b·c, y_left = y_a + g/2, y_right = y_a − g/2 (see module docstring).

    Notes
    -----
    Cost is one real inverse FFT of the synthesis length per component: a 5 km profile at a
    0.025 m step takes a few tens of milliseconds.
    """
    key = _level_key(spectrum_level)
    comps = list(components)
    for c in comps:
        if c not in IRREGULARITY_COMPONENTS:
            raise ScenarioError(
                f"unknown irregularity component {c!r}; expected one of "
                f"{', '.join(IRREGULARITY_COMPONENTS)}"
            )
    if not 0.0 < wavelength_min_m < wavelength_max_m:
        raise ScenarioError(
            f"need 0 < wavelength_min_m < wavelength_max_m, got {wavelength_min_m} m, "
            f"{wavelength_max_m} m"
        )
    if seed < 0:
        raise ScenarioError(f"seed must be >= 0, got {seed}")
    if not half_gauge > 0.0:
        raise ScenarioError(f"half_gauge must be > 0 m, got {half_gauge}")
    if ds is None:
        ds = wavelength_min_m / POINTS_PER_WAVELENGTH
    _check_step(ds, wavelength_min_m, "shortest random")
    n = _n_points(length_m, ds)
    n_syn = sp_fft.next_fast_len(max(n, math.ceil(_MIN_PERIODS * wavelength_max_m / ds)), real=True)
    period = n_syn * ds
    d_omega = 2.0 * math.pi / period
    k = np.arange(n_syn // 2 + 1)
    omega_k = d_omega * k
    om_lo = 2.0 * math.pi / wavelength_max_m
    om_hi = min(2.0 * math.pi / wavelength_min_m, math.pi / ds)
    k_lo = max(1, math.floor(om_lo / d_omega - 0.5))
    k_hi = min(n_syn // 2, math.ceil(om_hi / d_omega + 0.5))
    band = slice(k_lo, k_hi + 1)
    nyquist = n_syn % 2 == 0

    children = np.random.SeedSequence(seed).spawn(len(IRREGULARITY_COMPONENTS))
    series: dict[str, np.ndarray] = {}
    for idx, comp in enumerate(IRREGULARITY_COMPONENTS):
        if comp not in comps:
            series[comp] = np.zeros(n)
            continue
        rng = np.random.default_rng(children[idx])
        energy = _bin_energies(
            omega_k[band],
            d_omega,
            om_lo,
            om_hi,
            lambda om, c=comp: german_psd(om, c, key, half_gauge),
        )
        std = np.sqrt(energy) * scale
        m = std.size
        coeff = np.zeros(n_syn // 2 + 1, dtype=complex)
        # x[j] = Σ_k a_k cos(Ω_k s_j) + b_k sin(Ω_k s_j), a_k, b_k ~ N(0, E_k):
        # irfft gives (2/N)·Re(c_k e^{iΩ_k s}) per line, so c_k = (N/2)(a_k − i b_k).
        gauss = rng.standard_normal((2, m))
        coeff[band] = 0.5 * n_syn * std * (gauss[0] - 1j * gauss[1])
        if nyquist and k_hi == n_syn // 2:
            # the Nyquist line is real and enters once: c = N·a, a ~ N(0, E)
            coeff[-1] = n_syn * std[-1] * gauss[0, -1]
        series[comp] = sp_fft.irfft(coeff, n=n_syn)[:n]

    b = half_gauge
    zv, ya = series["vertical"], series["alignment"]
    c, g = series["cross_level"], series["gauge"]
    return IrregularityProfile(0.0, ds, zv + b * c, zv - b * c, ya + 0.5 * g, ya - 0.5 * g)


def corrugation_profile(
    length_m: float,
    wavelength_m: float = 0.5,
    depth_m: float = 0.001,
    start_m: float = 0.0,
    corrugated_length_m: float | None = None,
    rails: Literal["both", "left", "right"] = "both",
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
        (The schema field :attr:`~flexride.model.excitation.Corrugation.length_m`.)
    rails : {"both", "left", "right"}
        Corrugated rail(s).
    ds : float, optional
        Grid step (m); default min(0.05 m, λ/20).

    Returns
    -------
    IrregularityProfile
        z = −(depth/2)·(1 − cos(2π(s − start)/λ)) on the corrugated stretch (0 ≥ z ≥ −depth),
        zero elsewhere; lateral irregularities zero.
    """
    if not wavelength_m > 0.0:
        raise ScenarioError(f"corrugation wavelength must be > 0 m, got {wavelength_m}")
    if ds is None:
        ds = min(DEFAULT_DS, wavelength_m / POINTS_PER_WAVELENGTH)
    _check_step(ds, wavelength_m, "corrugation")
    prof = IrregularityProfile.zeros(length_m, ds)
    span = length_m - start_m if corrugated_length_m is None else corrugated_length_m
    cycles = max(1, math.floor(span / wavelength_m + 1e-9))
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


def settlement_profile(
    length_m: float,
    wavelength_m: float = 20.0,
    depth_m: float = 0.1,
    position_m: float = 50.0,
    rails: Literal["both", "left", "right"] = "both",
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
        irregularities zero.
    """
    if not wavelength_m > 0.0:
        raise ScenarioError(f"settlement wavelength must be > 0 m, got {wavelength_m}")
    if ds is None:
        ds = min(DEFAULT_DS, wavelength_m / POINTS_PER_WAVELENGTH)
    _check_step(ds, wavelength_m, "settlement")
    prof = IrregularityProfile.zeros(length_m, ds)
    s = prof.s
    inside = (s >= position_m) & (s <= position_m + wavelength_m)
    z = np.where(
        inside,
        -0.5 * depth_m * (1.0 - np.cos(2.0 * math.pi * (s - position_m) / wavelength_m)),
        0.0,
    )
    ml, mr = _rail_mask(rails)
    prof.z_left += ml * z
    prof.z_right += mr * z
    return prof


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
        CSV file; format in :class:`flexride.model.excitation.MeasuredIrregularity`: a header
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
        From the first to (at least) the last measured distance, linearly resampled;
        z_left = vertical + cross_level/2 + z_left, z_right = vertical − cross_level/2 + z_right,
        y_left = alignment + gauge/2 + y_left, y_right = alignment − gauge/2 + y_right.

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
    n = _n_points(float(dist[-1] - dist[0]), ds)
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
        Schema objects (:mod:`flexride.model.excitation`); an empty list gives a flat track.
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
        The sum, with s0 = 0 and step ``ds``.

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
        for key in _RAIL_KEYS:
            getattr(total, key)[:] += getattr(part, key)[:n]
    return total

"""German track spectra and random irregularity synthesis from them.

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

Fade-in
-------
A route starts at s = 0 on level track: the realisation is multiplied by a raised-cosine ramp
w(s) = ½ − ½·cos(π·min(s/L_f, 1)) with L_f = :data:`RANDOM_FADE_IN_M` (20 m), so the run does
not begin with a step (:func:`fade_in_weight`). Beyond L_f the profile is the stationary
realisation.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from functools import partial
from typing import NamedTuple

import numpy as np

from flexride.errors import ScenarioError
from flexride.scenario.excitation import IRREGULARITY_COMPONENTS, SpectrumTable
from flexride.track.profile import (
    POINTS_PER_WAVELENGTH,
    IrregularityProfile,
    check_step,
    n_points,
)

__all__ = [
    "GERMAN_HALF_GAUGE",
    "GERMAN_SPECTRA",
    "OMEGA_C",
    "OMEGA_R",
    "OMEGA_S",
    "RANDOM_FADE_IN_M",
    "band_rms",
    "fade_in_weight",
    "german_psd",
    "random_profile",
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

RANDOM_FADE_IN_M = 20.0
"""Distance over which a random irregularity fades in from the start of the route (m), so a run
does not begin with a step."""
_MIN_PERIODS = 8  # synthesis period ≥ 8·λ_max: ≥ 8 Fourier lines per Ω_min
_GL_X, _GL_W = np.polynomial.legendre.leggauss(5)
_TINY_PSD = 1e-300  # a table's zero, on the log scale of its interpolation


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


def table_psd(omega: np.ndarray | float, table: SpectrumTable, component: str) -> np.ndarray:
    """A user's tabulated spectrum (:class:`~flexride.scenario.excitation.SpectrumTable`) at Ω.

    Parameters
    ----------
    omega : array_like
        Spatial angular frequency Ω ≥ 0 (rad/m).
    table : SpectrumTable
        The table.
    component : str
        Irregularity component.

    Returns
    -------
    numpy.ndarray
        S(Ω), log–log interpolated between the table's points, zero outside them and for a
        component the table does not give; units as :func:`german_psd`.
    """
    om = np.asarray(omega, dtype=float)
    values = getattr(table, component, None)
    if values is None:
        return np.zeros_like(om)
    knots = np.asarray(table.omega_rad_per_m, dtype=float)
    logs = np.log(np.maximum(np.asarray(values, dtype=float), _TINY_PSD))
    inside = (om >= knots[0]) & (om <= knots[-1])
    log_om = np.log(np.clip(om, knots[0], knots[-1]))
    out = np.exp(np.interp(log_om, np.log(knots), logs))
    return np.where(inside & (out > _TINY_PSD), out, 0.0)


def component_psd(spectrum: str, component: str, half_gauge: float = GERMAN_HALF_GAUGE,
                  table: SpectrumTable | None = None) -> Callable[[np.ndarray], np.ndarray]:
    """S(Ω) of one component of a random irregularity's spectrum, as a function of Ω:
    the German spectra by level, or the user's ``table`` when ``spectrum`` is ``"table"``.
    The one place the generator and the frequency-domain estimate take spectra from.
    """
    if spectrum == "table":
        if table is None:
            raise ScenarioError("spectrum 'table' needs its table")
        return partial(table_psd, table=table, component=component)
    return partial(german_psd, component=component, level=_level_key(spectrum),
                   half_gauge=half_gauge)


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
    from scipy import integrate  # on use: a run's import stays light (docs/architecture.md)

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
    from scipy import signal  # on use: scipy.signal imports scipy.stats (≈ 250 ms, memory)

    f, g = signal.welch(x, fs=1.0 / ds, nperseg=nperseg, detrend="constant")
    # G(f) df = S(Ω) dΩ with Ω = 2πf
    return 2.0 * math.pi * f, g / (2.0 * math.pi)


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
    fade_in_m: float = RANDOM_FADE_IN_M,
    table: SpectrumTable | None = None,
) -> IrregularityProfile:
    """Random track irregularity from the German spectra or a user's table (stationary
    Gaussian synthesis).

    Parameters
    ----------
    length_m : float
        Route length to cover (m); the grid runs from 0 to at least ``length_m``.
    spectrum_level : {"high", "low", "german-high", "german-low", "table"}
        Disturbance level of the German spectra, or ``"table"`` for ``table``.
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
    fade_in_m : float
        Length of the raised-cosine fade-in from s = 0 (m), :func:`fade_in_weight`; 0 gives the
        stationary realisation from the first point on.
    table : SpectrumTable, optional
        The user's spectra (:func:`table_psd`) when ``spectrum_level`` is ``"table"``.

    Returns
    -------
    IrregularityProfile
        Rail irregularities (m) with s0 = 0. Rail mapping: z_left = z_v + b·c,
        z_right = z_v − b·c, y_left = y_a + g/2, y_right = y_a − g/2 (see module docstring),
        each multiplied by the fade-in weight.

    Notes
    -----
    Cost is one real inverse FFT of the synthesis length per component: a 5 km profile at a
    0.025 m step takes a few tens of milliseconds.
    """
    psd_of = partial(component_psd, spectrum_level, half_gauge=half_gauge, table=table)
    comps = list(components)
    _check_random_args(comps, wavelength_min_m, wavelength_max_m, seed, half_gauge, fade_in_m)
    if ds is None:
        ds = wavelength_min_m / POINTS_PER_WAVELENGTH
    check_step(ds, wavelength_min_m, "shortest random")
    n = n_points(length_m, ds)
    grid = _synthesis_grid(n, ds, wavelength_min_m, wavelength_max_m)

    children = np.random.SeedSequence(seed).spawn(len(IRREGULARITY_COMPONENTS))
    series: dict[str, np.ndarray] = {}
    for idx, comp in enumerate(IRREGULARITY_COMPONENTS):
        if comp not in comps:
            series[comp] = np.zeros(n)
            continue
        series[comp] = _component_series(grid, n, psd_of(comp), scale,
                                         np.random.default_rng(children[idx]))

    b = half_gauge
    zv, ya = series["vertical"], series["alignment"]
    cl, g = series["cross_level"], series["gauge"]
    prof = IrregularityProfile(0.0, ds, zv + b * cl, zv - b * cl, ya + 0.5 * g, ya - 0.5 * g)
    if fade_in_m > 0.0:
        w = fade_in_weight(prof.s, fade_in_m)
        for rail in prof.rails():
            rail *= w
    return prof


def _check_random_args(comps: list[str], wavelength_min_m: float, wavelength_max_m: float,
                       seed: int, half_gauge: float, fade_in_m: float) -> None:
    """Reject the arguments of :func:`random_profile` that make no realisation.

    Parameters
    ----------
    comps : list of str
        Requested components.
    wavelength_min_m, wavelength_max_m : float
        Wavelength band (m).
    seed : int
        Seed (≥ 0).
    half_gauge : float
        Half distance between rail centres (m).
    fade_in_m : float
        Fade-in length (m).
    """
    for name in comps:
        if name not in IRREGULARITY_COMPONENTS:
            raise ScenarioError(
                f"unknown irregularity component {name!r}; expected one of "
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
    if not (math.isfinite(fade_in_m) and fade_in_m >= 0.0):
        raise ScenarioError(f"fade_in_m must be a finite length >= 0 m, got {fade_in_m}")


class _SynthesisGrid(NamedTuple):
    """Frequency grid of the random synthesis (see :func:`_synthesis_grid`)."""

    n_syn: int
    d_omega: float
    omega_k: np.ndarray
    om_lo: float
    om_hi: float
    band: slice
    k_hi: int


def _synthesis_grid(n: int, ds: float, wavelength_min_m: float,
                    wavelength_max_m: float) -> _SynthesisGrid:
    """Spectral lines of an inverse FFT covering ``n`` points and ``_MIN_PERIODS`` λ_max.

    Parameters
    ----------
    n : int
        Number of output points.
    ds : float
        Grid step (m).
    wavelength_min_m, wavelength_max_m : float
        Wavelength band (m).

    Returns
    -------
    _SynthesisGrid
        ``n_syn`` (FFT length), ``d_omega`` (line spacing, rad/m), ``omega_k`` (all lines,
        rad/m), ``om_lo``/``om_hi`` (band edges, rad/m), ``band`` (slice of the lines in the
        band) and ``k_hi`` (its last line).
    """
    n_syn = next_fast_len(max(n, math.ceil(_MIN_PERIODS * wavelength_max_m / ds)))
    period = n_syn * ds
    d_omega = 2.0 * math.pi / period
    k = np.arange(n_syn // 2 + 1)
    omega_k = d_omega * k
    om_lo = 2.0 * math.pi / wavelength_max_m
    om_hi = min(2.0 * math.pi / wavelength_min_m, math.pi / ds)
    k_lo = max(1, math.floor(om_lo / d_omega - 0.5))
    k_hi = min(n_syn // 2, math.ceil(om_hi / d_omega + 0.5))
    return _SynthesisGrid(n_syn, d_omega, omega_k, om_lo, om_hi, slice(k_lo, k_hi + 1), k_hi)


def _component_series(grid: _SynthesisGrid, n: int, psd: Callable[[np.ndarray], np.ndarray],
                      scale: float, rng: np.random.Generator) -> np.ndarray:
    """One stationary Gaussian component by inverse FFT of random spectral lines.

    Parameters
    ----------
    grid : _SynthesisGrid
        Frequency grid.
    n : int
        Number of output points.
    psd : callable(Ω) -> PSD
        One-sided PSD (m²/(rad/m) or rad²/(rad/m)) of the angular wavenumber Ω (rad/m).
    scale : float
        Amplitude factor (-).
    rng : numpy.random.Generator
        The component's own random stream.

    Returns
    -------
    numpy.ndarray
        The first ``n`` samples (m, or rad for cross level).
    """
    n_syn, band = grid.n_syn, grid.band
    energy = _bin_energies(grid.omega_k[band], grid.d_omega, grid.om_lo, grid.om_hi, psd)
    std = np.sqrt(energy) * scale
    m = std.size
    coeff = np.zeros(n_syn // 2 + 1, dtype=complex)
    # x[j] = Σ_k a_k cos(Ω_k s_j) + b_k sin(Ω_k s_j), a_k, b_k ~ N(0, E_k):
    # irfft gives (2/N)·Re(c_k e^{iΩ_k s}) per line, so c_k = (N/2)(a_k − i b_k).
    gauss = rng.standard_normal((2, m))
    coeff[band] = 0.5 * n_syn * std * (gauss[0] - 1j * gauss[1])
    if n_syn % 2 == 0 and grid.k_hi == n_syn // 2:
        # the Nyquist line is real and enters once: c = N·a, a ~ N(0, E)
        coeff[-1] = n_syn * std[-1] * gauss[0, -1]
    return np.fft.irfft(coeff, n=n_syn)[:n]


def next_fast_len(n: int) -> int:
    """The smallest 2^a·3^b·5^c ≥ ``n``: the lengths pocketfft transforms fastest for real
    data, what ``scipy.fft.next_fast_len(n, real=True)`` returns (tested against it). Kept
    here with NumPy's FFT because importing ``scipy.fft`` costs a run 16 MB of memory.
    """
    best = 2 * max(n, 1)
    p5 = 1
    while p5 < best:
        p35 = p5
        while p35 < best:
            m = p35
            while m < n:
                m *= 2
            best = min(best, m)
            p35 *= 3
        p5 *= 5
    return best


def fade_in_weight(s: np.ndarray, fade_in_m: float = RANDOM_FADE_IN_M) -> np.ndarray:
    """Raised-cosine fade-in weight of a random irregularity.

    Parameters
    ----------
    s : numpy.ndarray
        Positions along the line (m).
    fade_in_m : float
        Fade-in length L_f (m), > 0.

    Returns
    -------
    numpy.ndarray
        w = ½ − ½·cos(π·u), u = s/L_f clipped to [0, 1] (-): 0 at and before s = 0, 1 from
        s = L_f on, with zero slope at both ends.
    """
    u = np.clip(np.asarray(s, dtype=float) / fade_in_m, 0.0, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * u)



"""Wheel–rail contact geometry tables (DESIGN §3.4): computed once, interpolated in the kernel.

A :class:`ContactTable` holds, for the left (row 0) and right (row 1) wheel of a wheelset, the
contact quantities on a uniform grid of the wheelset's lateral displacement Δy relative to the
track centre line (ISO 8855: y to the left, left rail at +y): rolling radius, contact angle,
vertical rise and lateral shift of the contact point, Hertz ellipse factors and Kalker's
coefficients. The compiled helpers :func:`interp_uniform` and :func:`flange_force` are what the
solver kernel calls per step.

:func:`conical_table` fills the table analytically for a conical tread on a rail with a round
head (constant contact angle, no flange geometry; flange contact is a dead-band spring).
Real profile pairs — the S1002 wheel on the 60E1 rail (EN 13715 / EN 13674-1; the test data
are described in ``/work/shared/profiles/README.md``) — will fill the same :class:`ContactTable`
later from a contact-point search over Δy, so the kernel does not change. The conical table has
no roll dependence: the wheelset roll of a cone is second order in Δy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from flexride._numba_env import FASTMATH
from flexride.contact.hertz import hertz_ellipse
from flexride.contact.kalker import kalker_from_axes
from flexride.errors import ScenarioError

__all__ = [
    "TABLE_FIELDS",
    "TABLE_PARAMS",
    "ContactTable",
    "conical_table",
    "flange_force",
    "interp_uniform",
]

#: Order of the [2, n] fields in the data block returned by :meth:`ContactTable.as_arrays`.
TABLE_FIELDS = ("r", "gamma", "dz", "yc", "ca", "cb", "c11", "c22", "c23", "c33")
#: Order of the scalars in the parameter vector returned by :meth:`ContactTable.as_arrays`.
TABLE_PARAMS = ("y0", "dy", "r0", "b0", "flange_clearance", "flange_stiffness")


@dataclass(frozen=True, eq=False)
class ContactTable:
    """Contact geometry of one wheelset (both wheels) against its lateral displacement.

    Grid: Δy_i = y0 + i·dy, i = 0 … n − 1, where Δy is the lateral displacement of the wheelset
    relative to the track centre line in m (positive to the left). Every array is [2, n]:
    row 0 the left wheel, row 1 the right wheel. Arrays are stored as read-only contiguous
    float64.

    Attributes
    ----------
    y0 : float
        First grid value of Δy in m.
    dy : float
        Grid step in m (> 0).
    r : numpy.ndarray
        Rolling radius in m.
    gamma : numpy.ndarray
        Contact angle in rad: angle of the contact normal from the track-plane normal, positive
        when the normal force on the wheel points toward the track centre (lateral component
        of the force on the left wheel −N·sin γ, on the right wheel +N·sin γ).
    dz : numpy.ndarray
        Vertical rise of the contact point relative to its nominal position in m; enters the
        normal compression (for a cone dz = r − r0).
    yc : numpy.ndarray
        Lateral offset of the contact point from its nominal position on the wheel, in the
        wheelset frame (m, positive to the left).
    ca, cb : numpy.ndarray
        Hertz ellipse factors in m/N^(1/3): a = ca·N^(1/3) (rolling), b = cb·N^(1/3) (lateral).
    c11, c22, c23, c33 : numpy.ndarray
        Kalker's linear creep coefficients (dimensionless).
    r0 : float
        Nominal rolling radius in m.
    b0 : float
        Half distance between the nominal contact points (rolling circles) in m.
    flange_clearance : float
        Lateral displacement at which flange contact starts in m (≥ 0).
    flange_stiffness : float
        Lateral stiffness of the flange contact beyond the clearance in N/m (≥ 0).
    """

    y0: float
    dy: float
    r: np.ndarray
    gamma: np.ndarray
    dz: np.ndarray
    yc: np.ndarray
    ca: np.ndarray
    cb: np.ndarray
    c11: np.ndarray
    c22: np.ndarray
    c23: np.ndarray
    c33: np.ndarray
    r0: float
    b0: float
    flange_clearance: float
    flange_stiffness: float

    def __post_init__(self) -> None:
        """Check the table fields (finite, one length) and the grid."""
        shape = None
        for name in TABLE_FIELDS:
            arr = np.ascontiguousarray(getattr(self, name), dtype=np.float64)
            if arr.ndim != 2 or arr.shape[0] != 2 or arr.shape[1] < 2:
                raise ScenarioError(
                    f"contact table field {name!r} must have shape [2, n] with n >= 2, "
                    f"got {arr.shape}"
                )
            if shape is not None and arr.shape != shape:
                raise ScenarioError(
                    f"contact table field {name!r} has shape {arr.shape}, expected {shape}"
                )
            if not np.all(np.isfinite(arr)):
                raise ScenarioError(f"contact table field {name!r} contains NaN or inf")
            shape = arr.shape
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)
        for name in TABLE_PARAMS:
            value = float(getattr(self, name))
            if not math.isfinite(value):
                raise ScenarioError(f"contact table parameter {name!r} must be finite")
            object.__setattr__(self, name, value)
        if self.dy <= 0.0:
            raise ScenarioError(f"contact table step dy (m) must be positive, got {self.dy}")
        for name in ("r0", "b0"):
            if getattr(self, name) <= 0.0:
                raise ScenarioError(f"contact table {name} (m) must be positive")
        for name in ("flange_clearance", "flange_stiffness"):
            if getattr(self, name) < 0.0:
                raise ScenarioError(f"contact table {name} must not be negative")
        if np.any(self.r <= 0.0):
            raise ScenarioError("contact table rolling radii r (m) must be positive")

    @property
    def n(self) -> int:
        """Number of grid points."""
        return int(self.r.shape[1])

    @property
    def y_grid(self) -> np.ndarray:
        """Grid of wheelset lateral displacements Δy in m, shape [n]."""
        return self.y0 + self.dy * np.arange(self.n)

    def as_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """Flat float64 arrays for the numba kernel.

        Returns
        -------
        params : numpy.ndarray
            Shape [6], the scalars in the order of :data:`TABLE_PARAMS`
            (y0 m, dy m, r0 m, b0 m, flange_clearance m, flange_stiffness N/m).
        data : numpy.ndarray
            Shape [10, 2, n], C-contiguous, the fields in the order of :data:`TABLE_FIELDS`;
            ``data[k, side]`` is a contiguous row for :func:`interp_uniform`.
        """
        params = np.array([float(getattr(self, name)) for name in TABLE_PARAMS])
        data = np.ascontiguousarray(np.stack([getattr(self, name) for name in TABLE_FIELDS]))
        return params, data


def _positive(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise ScenarioError(f"{name} must be a finite positive number, got {value!r}")
    return value


def _non_negative(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and value >= 0.0):
        raise ScenarioError(f"{name} must be a finite number >= 0, got {value!r}")
    return value


def conical_table(
    r0: float = 0.42,
    conicity: float = 0.05,
    b0: float = 0.7465,
    flange_clearance: float = 0.008,
    flange_stiffness: float = 1.5e8,
    rail_head_radius: float = 0.3,
    E: float = 2.1e11,
    nu: float = 0.28,
    y_max: float = 0.02,
    n: int = 401,
) -> ContactTable:
    """Contact table of a conical tread (effective conicity λ) on rails with a round head.

    Parameters
    ----------
    r0 : float
        Nominal rolling radius in m.
    conicity : float
        Tread conicity λ = tan γ (dimensionless, in [0, 1)); the flange is on the inner side
        of each wheel, so the radius grows toward the track centre.
    b0 : float
        Half distance between the nominal rolling circles in m.
    flange_clearance : float
        Lateral wheelset displacement at which the flange touches the rail in m.
    flange_stiffness : float
        Lateral flange-contact stiffness in N/m. The default 1.5e8 N/m is of the order of the
        local lateral stiffness of the rail at the flange contact (rail-head and web bending
        plus fastening, about 1e8–2e8 N/m), which in series dominates the linearised Hertz
        flange stiffness (≈ 1e9 N/m at 20 kN, from dP/dδ = 1.5·P^(1/3)/G). Softer values
        (e.g. 1.8e7 N/m in True's Cooperrider bogie) are used when the rail is not modelled.
    rail_head_radius : float
        Transverse radius of the rail head crown in m (lateral curvature of the contact).
    E : float
        Young's modulus of wheel and rail in Pa.
    nu : float
        Poisson's ratio of wheel and rail, in [0, 0.5].
    y_max : float
        Grid half-range of the lateral displacement in m; the grid is [−y_max, y_max].
    n : int
        Number of grid points (≥ 2; odd puts Δy = 0 on the grid).

    Returns
    -------
    ContactTable
        With, for Δy the wheelset displacement (positive to the left):
        r_L = r0 + λΔy, r_R = r0 − λΔy (a wheelset moved left rolls on a larger radius on the
        left wheel); γ = arctan λ on both wheels; dz = r − r0; yc = −Δy on both wheels (the
        contact point stays on the rail crown, so it moves across the wheel by −Δy); Hertz
        factors from A = cos γ/(2r) (normal curvature of the wheel in the rolling direction,
        straight rail) and B = 1/(2·rail_head_radius) (straight cone generatrix); Kalker's
        coefficients for the axis ratio ca/cb.

    Raises
    ------
    ScenarioError
        For non-physical inputs (non-positive radii, ν outside [0, 0.5], λ·y_max ≥ r0, …).
    """
    r0, lam, b0, clearance, stiffness, rail_radius, modulus, nu, y_max, n = _conical_inputs(
        r0, conicity, b0, flange_clearance, flange_stiffness, rail_head_radius, E, nu, y_max, n
    )
    dy_grid = np.linspace(-y_max, y_max, n)
    r = np.stack([r0 + lam * dy_grid, r0 - lam * dy_grid])
    gam = math.atan(lam)
    gamma = np.full((2, n), gam)
    dz = r - r0
    yc = np.stack([-dy_grid, -dy_grid])
    ca, cb, coeffs = _conical_contact_grid(r, gam, rail_radius, modulus, nu)

    return ContactTable(
        y0=-y_max, dy=2.0 * y_max / (n - 1), r=r, gamma=gamma, dz=dz, yc=yc, ca=ca, cb=cb,
        c11=coeffs[0], c22=coeffs[1], c23=coeffs[2], c33=coeffs[3], r0=r0, b0=b0,
        flange_clearance=clearance, flange_stiffness=stiffness,
    )


def _conical_inputs(
    r0: float,
    conicity: float,
    b0: float,
    flange_clearance: float,
    flange_stiffness: float,
    rail_head_radius: float,
    E: float,
    nu: float,
    y_max: float,
    n: int,
) -> tuple[float, float, float, float, float, float, float, float, float, int]:
    """Check and convert the arguments of :func:`conical_table` (same names and units).

    Parameters
    ----------
    r0, conicity, b0, flange_clearance, flange_stiffness, rail_head_radius, E, nu, y_max, n
        As for :func:`conical_table` (m, -, m, m, N/m, m, Pa, -, m, -).

    Returns
    -------
    tuple
        (r0, λ, b0, clearance, stiffness, rail_head_radius, E, ν, y_max) as floats and n as int.

    Raises
    ------
    ScenarioError
        For non-physical inputs.
    """
    r0 = _positive("nominal rolling radius r0 (m)", r0)
    lam = _non_negative("conicity (tan γ)", conicity)
    if lam >= 1.0:
        raise ScenarioError(f"conicity (tan γ) must be below 1, got {lam!r}")
    b0 = _positive("half distance between rolling circles b0 (m)", b0)
    clearance = _non_negative("flange_clearance (m)", flange_clearance)
    stiffness = _non_negative("flange_stiffness (N/m)", flange_stiffness)
    rail_radius = _positive("rail_head_radius (m)", rail_head_radius)
    modulus = _positive("Young's modulus E (Pa)", E)
    nu = float(nu)
    if not (math.isfinite(nu) and 0.0 <= nu <= 0.5):
        raise ScenarioError(f"Poisson's ratio nu must lie in [0, 0.5], got {nu!r}")
    y_max = _positive("y_max (m)", y_max)
    if int(n) != n or n < 2:
        raise ScenarioError(f"number of grid points n must be an integer >= 2, got {n!r}")
    n = int(n)
    if lam * y_max >= r0:
        raise ScenarioError("conicity·y_max must be smaller than r0 (radius would vanish)")
    return r0, lam, b0, clearance, stiffness, rail_radius, modulus, nu, y_max, n


def _conical_contact_grid(r: np.ndarray, gam: float, rail_radius: float, modulus: float,
                          nu: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hertz semi-axes and Kalker coefficients of a conical tread on a round rail head.

    Parameters
    ----------
    r : numpy.ndarray
        (2, n) rolling radii (m), left and right.
    gam : float
        Contact angle (rad), the same on both wheels.
    rail_radius : float
        Transverse radius of the rail head crown (m).
    modulus : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).

    Returns
    -------
    ca, cb : numpy.ndarray
        (2, n) Hertz semi-axis factors, rolling and lateral (m/N^(1/3)).
    coeffs : numpy.ndarray
        (4, 2, n) Kalker coefficients c11, c22, c23, c33 (-).
    """
    n = r.shape[1]
    curv_y = 0.5 / rail_radius
    ca = np.empty((2, n))
    cb = np.empty((2, n))
    coeffs = np.empty((4, 2, n))
    for side in range(2):
        for i in range(n):
            ca_i, cb_i = hertz_ellipse(0.5 * math.cos(gam) / r[side, i], curv_y, modulus, nu)
            ca[side, i], cb[side, i] = ca_i, cb_i
            coeffs[:, side, i] = kalker_from_axes(ca_i, cb_i, nu)
    return ca, cb, coeffs


@numba.njit(cache=True, fastmath=set(FASTMATH))
def interp_uniform(table_row: np.ndarray, y0: float, dy: float, y: float) -> float:
    """Linear interpolation on a uniform grid, clamped to the end values (compiled).

    Parameters
    ----------
    table_row : numpy.ndarray
        Values at y0 + i·dy, i = 0 … n − 1 (n ≥ 2), any unit.
    y0 : float
        First grid point in m.
    dy : float
        Grid step in m (> 0).
    y : float
        Query point in m.

    Returns
    -------
    float
        Interpolated value (unit of ``table_row``); the first / last value outside the grid,
        NaN for a NaN query.
    """
    n = table_row.shape[0]
    t = (y - y0) / dy
    if t != t:
        return math.nan
    if t <= 0.0:
        return table_row[0]
    if t >= n - 1:
        return table_row[n - 1]
    i = int(t)
    frac = t - i
    return table_row[i] + frac * (table_row[i + 1] - table_row[i])


@numba.njit(cache=True, fastmath=set(FASTMATH))
def flange_force(dy_rel: float, clearance: float, stiffness: float) -> float:
    """Lateral flange-contact force on the wheelset: a linear spring with a dead band (compiled).

    Parameters
    ----------
    dy_rel : float
        Lateral displacement of the wheelset relative to the rails in m (positive to the left).
    clearance : float
        Flange clearance c in m (≥ 0).
    stiffness : float
        Flange-contact stiffness k in N/m.

    Returns
    -------
    float
        Force on the wheelset in N (positive to the left): 0 for |Δy| ≤ c, −k·(Δy − c) for
        Δy > c, −k·(Δy + c) for Δy < −c.
    """
    if dy_rel > clearance:
        return -stiffness * (dy_rel - clearance)
    if dy_rel < -clearance:
        return -stiffness * (dy_rel + clearance)
    return 0.0

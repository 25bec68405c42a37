"""How the track enters the linear model: the frozen rail window condensed onto the vehicle
(default), kept with all its modes, or replaced by rigid rails.

``condensed``
    Guyan reduction of the rail onto its interface with the vehicle. The contact touches the
    rail modes only through the rail-head displacements under the wheels (vertical and lateral
    at each wheel: sine values of every mode there); those directions are found as the row
    space of the coupling blocks of K, C and B (an SVD) and kept as master coordinates, the
    rest of the rail's modal space follows them statically (Petrov–Galerkin projection,
    because creep makes K unsymmetric). Exact at zero frequency; the creep forces keep acting
    between the wheel and a rail head that has the rail's stiffness, damping and Guyan mass.
    (Condensing the rail heads too would put the creep "damper" against a massless rail
    spring, which moves the bogie's lateral modes from 7 to 10 Hz: the rail head must stay a
    coordinate.) The rail resonances above ≈ 70 Hz are approximated by one Guyan mode per
    rail head.
``modal``
    Every rail mode of the frozen window, as in the stability check: exact for the frozen
    window, about 10× more states.
``rigid``
    Rail coordinates held at equilibrium: the wheels roll on rigid rails through the Hertz
    contact.

All work in force form (matrices multiplied by the diagonal mass) and return the
mass-normalised system of the kept coordinates.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
import scipy.linalg as sla

from flexride.frequency.lti import OutputMap, SecondOrderSystem

TrackModel = Literal["condensed", "modal", "rigid"]
TRACK_MODELS: tuple[TrackModel, ...] = ("condensed", "modal", "rigid")
#: Singular values of the coupling blocks below this fraction of the largest are not coupling:
#: the coupling has rank two per wheel (the rail head's vertical and lateral displacement),
#: those singular values are above 1e-2 of the largest, the rest is rounding of the
#: finite-difference Jacobians (below 1e-9; it was 1e-8 with plain 1e-7 differences, which a
#: threshold of 1e-9 counted as eight more rail-head coordinates).
INTERFACE_RTOL = 1e-6

__all__ = ["TRACK_MODELS", "Condensation", "Reduced", "TrackModel", "condensation",
           "reduce_track"]


@dataclass
class Condensation:
    """What the condensed track model takes from the rail: the rail's interface basis, the
    static modes and the rail parts of the reduced matrices.

    The static modes depend only on the rail's interior (its blocks outside the interface),
    the rail masses and the interface directions; the parts also on the couplings. A system
    whose vehicle block alone differs reuses all of it; one whose rail rows and columns differ
    only in and through the interface (another linearisation of the contact: the forces it
    adds act on the rail heads and depend on their motion) reuses the static modes with new
    parts (:meth:`adapt`).

    Attributes
    ----------
    n_veh : int
        Number of vehicle coordinates.
    Qi : numpy.ndarray
        (n_rail, n_i) orthonormal basis of the interface directions.
    Tr : numpy.ndarray
        (n_rail, n_i) rail coordinates per interface coordinate (static modes).
    Lr : numpy.ndarray
        (n_i, n_rail) the left (test) basis of the Petrov–Galerkin projection.
    m_inv : numpy.ndarray
        (n_i, n_i) inverse of the interface mass matrix Lr·diag(m_r)·Tr (1/kg).
    mass : numpy.ndarray
        (n_veh + n_i,) diagonal masses of the kept coordinates (kg, kg·m²).
    parts : dict of str to numpy.ndarray
        Mass-normalised reduced blocks that do not involve the vehicle block: ``K_vi``,
        ``K_iv``, ``K_ii`` (1/s²), the same of ``C`` (1/s), ``B0_i``, ``B1_i``.
    rail_rows, rail_cols : dict of str to numpy.ndarray
        The full system's rail rows (K, C, B0, B1) and rail columns (K, C) it was made from.
    rail_mass : numpy.ndarray
        The rail coordinates' masses it was made from (kg, kg·m²).
    """

    n_veh: int
    Qi: np.ndarray
    Tr: np.ndarray
    Lr: np.ndarray
    m_inv: np.ndarray
    mass: np.ndarray
    parts: dict[str, np.ndarray]
    rail_rows: dict[str, np.ndarray]
    rail_cols: dict[str, np.ndarray]
    rail_mass: np.ndarray

    @functools.cached_property
    def rail_scale(self) -> dict[str, float]:
        """Largest entry of the rail block of K and C in force form (N/m, N·s/m)."""
        r = slice(self.n_veh, None)
        return {name: float(np.abs(self.rail_mass[:, None] * self.rail_rows[name][:, r]).max())
                for name in ("K", "C")}

    def fits(self, full: SecondOrderSystem, mass: np.ndarray) -> bool:
        """Whether ``full`` has exactly the rail rows and columns this was made from."""
        r = slice(self.n_veh, None)
        if not np.array_equal(mass[r], self.rail_mass):
            return False
        for name in ("K", "C", "B0", "B1"):
            a = getattr(full, name)
            if not np.array_equal(a[r], self.rail_rows[name]):
                return False
            if name in ("K", "C") and not np.array_equal(a[:, r], self.rail_cols[name]):
                return False
        return True

    def interface_only(self, full: SecondOrderSystem, mass: np.ndarray) -> bool:
        """Whether ``full`` differs from the system this was made from only in and through
        the interface: the same rail masses, couplings whose rail parts lie in the interface
        directions, and rail blocks whose change is Qi·X·Qiᵀ (within :data:`ADAPT_RTOL` of the
        blocks' size). The static modes a fresh condensation would make are then these.
        """
        r = slice(self.n_veh, None)
        if full.n != self.n_veh + self.Tr.shape[0] or not np.array_equal(mass[r],
                                                                           self.rail_mass):
            return False
        m_r = self.rail_mass[:, None]
        for name in ("K", "C"):
            a = getattr(full, name)
            couplings = (a[:self.n_veh, r], (m_r * a[r, :self.n_veh]).T)
            if not all(_in_span(b, self.Qi) for b in couplings):
                return False
            if not _interface_change(a[r, r] - self.rail_rows[name][:, r], self.rail_mass,
                                     self.rail_scale[name], self.Qi):
                return False
        return all(_in_span((m_r * getattr(full, name)[r]).T, self.Qi) for name in ("B0", "B1"))

    def adapt(self, full: SecondOrderSystem, mass: np.ndarray) -> Condensation | None:
        """The condensation for ``full``: itself if it fits exactly, one with its static modes
        and new parts if ``full`` differs only in and through the interface, else None.
        """
        if self.fits(full, mass):
            return self
        if not self.interface_only(full, mass):
            return None
        v, r = slice(0, self.n_veh), slice(self.n_veh, full.n)
        # the rail blocks as views: an adapted condensation serves one system (a quasi-linear
        # iteration's), whose matrices are not changed afterwards
        return Condensation(self.n_veh, self.Qi, self.Tr, self.Lr, self.m_inv, self.mass,
                            _parts(full, mass, v, r, self.Tr, self.Lr, self.m_inv),
                            *_rail_blocks(full, r, copy=False), self.rail_mass)


#: A change of the rail blocks counts as "in the interface" when what lies outside it is below
#: this fraction of the blocks' largest entry: the finite-difference Jacobians' rounding (the
#: coupling singular values below 1e-9 of the largest, :data:`INTERFACE_RTOL`), far below what
#: a physical change of the rail's interior (a fastener, a rail mode) gives.
ADAPT_RTOL = 1e-8


def _in_span(rows: np.ndarray, Q: np.ndarray) -> bool:
    """Whether every row of ``rows`` lies in the column span of the orthonormal ``Q``."""
    scale = np.abs(rows).max()
    return bool(scale == 0.0 or np.abs(rows - (rows @ Q) @ Q.T).max() <= ADAPT_RTOL * scale)


def _interface_change(change: np.ndarray, mass: np.ndarray, scale: float, Q: np.ndarray
                      ) -> bool:
    """Whether the change ``mass[:, None]·change`` of a rail block (force form) is Q·X·Qᵀ
    (Q orthonormal) within :data:`ADAPT_RTOL` of the block's largest entry ``scale``: whether
    it and its transpose map the orthogonal complement of Q's span to zero. Tested on
    :data:`N_PROBES` fixed random vectors of that complement (a product with them instead of
    two with Q): a component outside the interface would have to be orthogonal to all of them.
    """
    p = _probes(change.shape[0])
    p = p - Q @ (Q.T @ p)
    p /= np.linalg.norm(p, axis=0)
    tol = ADAPT_RTOL * scale * math.sqrt(change.shape[0])
    return bool(np.abs(mass[:, None] * (change @ p)).max() <= tol
                and np.abs(change.T @ (mass[:, None] * p)).max() <= tol)


#: Probe vectors of :func:`_interface_change`.
N_PROBES = 4


@functools.lru_cache(maxsize=4)
def _probes(n: int) -> np.ndarray:
    """(n, :data:`N_PROBES`) fixed standard normal vectors (read-only)."""
    z = np.random.default_rng(n).standard_normal((n, N_PROBES))
    z.setflags(write=False)
    return z


@dataclass
class Reduced:
    """A reduced system and the map back to the full coordinates.

    Attributes
    ----------
    system : SecondOrderSystem
        Mass-normalised system of the kept coordinates.
    keep : numpy.ndarray
        Indices of the kept coordinates in the full vector; −1 − k for the k-th rail-head
        (interface) coordinate of the condensed track.
    T : numpy.ndarray
        (n, n_kept) full coordinates per kept coordinate.
    U : numpy.ndarray
        (n, m) full coordinates per unit input (static rail deflection under the input).
    mass : numpy.ndarray
        (n_kept,) diagonal masses of the kept coordinates (kg, kg·m²), for energy shares.
    condensation : Condensation, optional
        The rail's part of a condensed track model (reusable, see :func:`reduce_track`).
    """

    system: SecondOrderSystem
    keep: np.ndarray
    T: np.ndarray
    U: np.ndarray
    mass: np.ndarray
    condensation: Condensation | None = None

    def outputs(self, out: OutputMap) -> OutputMap:
        """Outputs of the full coordinates expressed in the kept ones (rail rows through T, U;
        the ω² P U term is dropped: acceleration outputs have no rail rows).
        """
        return OutputMap(out.names, out.P @ self.T, out.G @ self.T, out.D + out.G @ self.U)


def reduce_track(full: SecondOrderSystem, mass: np.ndarray, n_veh: int,
                 track: TrackModel, previous: Reduced | None = None) -> Reduced:
    """Reduce the full frozen-window system (vehicle coordinates first, rail modes after).

    Parameters
    ----------
    full : SecondOrderSystem
        Mass-normalised full system.
    mass : numpy.ndarray
        (n,) diagonal generalised masses (kg, kg·m²; rail modal masses).
    n_veh : int
        Number of vehicle coordinates.
    track : {"condensed", "modal", "rigid"}
        Track model (module docstring).
    previous : Reduced, optional
        A condensed reduction of a system with the same rail (a parameter sweep that does not
        touch the track, or another linearisation of the same contact): its condensation is
        reused where it fits (:meth:`Condensation.adapt`); the result is the same as without
        it, to rounding.
    """
    n, m = full.n, full.m
    if track == "modal":
        return Reduced(full, np.arange(n), np.eye(n), np.zeros((n, m)), mass)
    v = np.arange(n_veh)
    if track == "rigid":
        T = np.zeros((n, n_veh))
        T[v, v] = 1.0
        sys = SecondOrderSystem(full.K[np.ix_(v, v)], full.C[np.ix_(v, v)], full.B0[v],
                                full.B1[v], full.B2[v])
        return Reduced(sys, v, T, np.zeros((n, m)), mass[v])
    if track == "condensed":
        kept = previous.condensation if previous is not None else None
        cd = kept.adapt(full, mass) if kept is not None and kept.n_veh == n_veh else None
        if cd is None:
            cd = condensation(full, mass, n_veh)
        return _condensed(full, cd)
    raise ValueError(f"unknown track model {track!r}; use one of {', '.join(TRACK_MODELS)}")


def _interface_basis(Kf, Cf, Bf0, Bf1, v: slice, r: slice) -> tuple[np.ndarray, np.ndarray]:
    """Orthonormal bases of the rail coordinates the vehicle and the inputs act through (the
    rail heads under the wheels: sine values of every mode there) and of the rest.
    """
    blocks = [Kf[v, r], Cf[v, r], Kf[r, v].T, Cf[r, v].T, Bf0[r].T, Bf1[r].T]
    rows = [b / np.abs(b).max() for b in blocks if np.abs(b).max() > 0.0]
    _u, sv, vh = np.linalg.svd(np.vstack(rows), full_matrices=True)
    rank = int(np.sum(sv > INTERFACE_RTOL * sv[0]))
    return vh[:rank].T, vh[rank:].T


def condensation(full: SecondOrderSystem, mass: np.ndarray, n_veh: int) -> Condensation:
    """Guyan condensation of the rail onto its interface with the vehicle (module docstring):
    the static modes Tr, the test basis Lr and the reduced blocks that involve the rail.

    Parameters
    ----------
    full : SecondOrderSystem
        Mass-normalised full system (vehicle coordinates first).
    mass : numpy.ndarray
        (n,) diagonal generalised masses (kg, kg·m²).
    n_veh : int
        Number of vehicle coordinates.
    """
    v, r = slice(0, n_veh), slice(n_veh, full.n)
    Kf = mass[:, None] * full.K
    Cf = mass[:, None] * full.C
    Bf0 = mass[:, None] * full.B0
    Bf1 = mass[:, None] * full.B1
    Qi, Qc = _interface_basis(Kf, Cf, Bf0, Bf1, v, r)
    k_rr = Kf[r, r]
    lu = sla.lu_factor(Qc.T @ k_rr @ Qc)
    Tc = -sla.lu_solve(lu, Qc.T @ k_rr @ Qi)
    Lc = -sla.lu_solve(lu, (Qi.T @ k_rr @ Qc).T, trans=1).T
    Tr = Qi + Qc @ Tc
    Lr = Qi.T + Lc @ Qc.T
    m_ii = Lr @ (mass[r, None] * Tr)
    mi = np.linalg.inv(m_ii)
    red_mass = np.concatenate([mass[v], np.abs(np.diag(m_ii))])
    return Condensation(n_veh, Qi, Tr, Lr, mi, red_mass, _parts(full, mass, v, r, Tr, Lr, mi),
                        *_rail_blocks(full, r), mass[r].copy())


def _parts(full: SecondOrderSystem, mass: np.ndarray, v: slice, r: slice, Tr: np.ndarray,
           Lr: np.ndarray, mi: np.ndarray) -> dict[str, np.ndarray]:
    """The mass-normalised reduced blocks of ``full`` that involve the rail (static modes
    ``Tr``, test basis ``Lr``, inverse interface mass ``mi``).
    """
    m_r = mass[r, None]
    parts: dict[str, np.ndarray] = {}
    for name in ("K", "C"):
        a = getattr(full, name)
        parts[f"{name}_vi"] = a[v, r] @ Tr
        parts[f"{name}_iv"] = mi @ (Lr @ (m_r * a[r, v]))
        parts[f"{name}_ii"] = mi @ ((Lr @ (m_r * a[r, r])) @ Tr)
    parts["B0_i"] = mi @ (Lr @ (m_r * full.B0[r]))
    parts["B1_i"] = mi @ (Lr @ (m_r * full.B1[r]))
    return parts


def _rail_blocks(full: SecondOrderSystem, r: slice, copy: bool = True
                 ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The rail rows (K, C, B0, B1) and rail columns (K, C) of ``full``: copies, or views."""
    def take(a: np.ndarray) -> np.ndarray:
        return a.copy() if copy else a

    rows = {name: take(getattr(full, name)[r]) for name in ("K", "C", "B0", "B1")}
    cols = {name: take(getattr(full, name)[:, r]) for name in ("K", "C")}
    return rows, cols


def _condensed(full: SecondOrderSystem, cd: Condensation) -> Reduced:
    """The condensed system of ``full`` with the rail's part ``cd`` (which must fit it)."""
    n, nv = full.n, cd.n_veh
    p = cd.parts
    K = np.block([[full.K[:nv, :nv], p["K_vi"]], [p["K_iv"], p["K_ii"]]])
    C = np.block([[full.C[:nv, :nv], p["C_vi"]], [p["C_iv"], p["C_ii"]]])
    B0 = np.vstack([full.B0[:nv], p["B0_i"]])
    B1 = np.vstack([full.B1[:nv], p["B1_i"]])
    ni = cd.Tr.shape[1]
    T = np.zeros((n, nv + ni))
    T[:nv, :nv] = np.eye(nv)
    T[nv:, nv:] = cd.Tr
    keep = np.concatenate([np.arange(nv), -1 - np.arange(ni)])
    sys = SecondOrderSystem(K, C, B0, B1, np.zeros((nv + ni, full.m)))
    return Reduced(sys, keep, T, np.zeros((n, full.m)), cd.mass.copy(), cd)

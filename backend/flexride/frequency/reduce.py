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

from dataclasses import dataclass
from typing import Literal

import numpy as np
import scipy.linalg as sla

from flexride.frequency.lti import OutputMap, SecondOrderSystem

TrackModel = Literal["condensed", "modal", "rigid"]
TRACK_MODELS: tuple[TrackModel, ...] = ("condensed", "modal", "rigid")
#: Singular values of the coupling blocks below this fraction of the largest are not coupling.
INTERFACE_RTOL = 1e-9

__all__ = ["TRACK_MODELS", "Reduced", "TrackModel", "reduce_track"]


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
    """

    system: SecondOrderSystem
    keep: np.ndarray
    T: np.ndarray
    U: np.ndarray
    mass: np.ndarray

    def outputs(self, out: OutputMap) -> OutputMap:
        """Outputs of the full coordinates expressed in the kept ones (rail rows through T, U;
        the ω² P U term is dropped: acceleration outputs have no rail rows).
        """
        return OutputMap(out.names, out.P @ self.T, out.G @ self.T, out.D + out.G @ self.U)


def reduce_track(full: SecondOrderSystem, mass: np.ndarray, n_veh: int,
                 track: TrackModel) -> Reduced:
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
        return _condense(full, mass, n_veh)
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


def _condense(full: SecondOrderSystem, mass: np.ndarray, n_veh: int) -> Reduced:
    """Guyan condensation of the rail onto its interface with the vehicle (module docstring)."""
    n = full.n
    v, r = slice(0, n_veh), slice(n_veh, n)
    Kf = mass[:, None] * full.K
    Cf = mass[:, None] * full.C
    Bf0 = mass[:, None] * full.B0
    Bf1 = mass[:, None] * full.B1
    Qi, Qc = _interface_basis(Kf, Cf, Bf0, Bf1, v, r)
    ni = Qi.shape[1]
    k_cc = Qc.T @ Kf[r, r] @ Qc
    lu = sla.lu_factor(k_cc)
    Tc = -sla.lu_solve(lu, Qc.T @ Kf[r, r] @ Qi)
    Lc = -sla.lu_solve(lu, (Qi.T @ Kf[r, r] @ Qc).T, trans=1).T
    T = np.zeros((n, n_veh + ni))
    T[v, :n_veh] = np.eye(n_veh)
    T[r, n_veh:] = Qi + Qc @ Tc
    L = np.zeros((n_veh + ni, n))
    L[:n_veh, v] = np.eye(n_veh)
    L[n_veh:, r] = Qi.T + Lc @ Qc.T
    Mr = L @ (mass[:, None] * T)
    Mi = np.linalg.inv(Mr)
    sys = SecondOrderSystem(Mi @ (L @ Kf @ T), Mi @ (L @ Cf @ T), Mi @ (L @ Bf0),
                            Mi @ (L @ Bf1), np.zeros((n_veh + ni, full.m)))
    keep = np.concatenate([np.arange(n_veh), -1 - np.arange(ni)])
    return Reduced(sys, keep, T, np.zeros((n, full.m)), np.abs(np.diag(Mr)).copy())

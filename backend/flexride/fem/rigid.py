"""Rigid-body vectors and mass properties of a model with six DOFs per node."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp


def rigid_body_vectors(nodes: np.ndarray, reference: np.ndarray | None = None) -> np.ndarray:
    """The six rigid-body displacement fields of nodes with six DOFs each.

    Parameters
    ----------
    nodes : numpy.ndarray
        (n, 3) node coordinates (m).
    reference : array of 3 floats, optional
        Point the rotations are taken about (m); the origin when omitted.

    Returns
    -------
    numpy.ndarray
        (6 n, 6) matrix; columns: unit translations x, y, z (m) and unit small rotations about
        x, y, z through ``reference`` (rad). Small rotations: ``u = t + θ × r``.
    """
    nodes = np.asarray(nodes, dtype=float).reshape(-1, 3)
    r = nodes - (np.zeros(3) if reference is None else np.asarray(reference, dtype=float))
    n = nodes.shape[0]
    R = np.zeros((n, 6, 6))
    for k in range(3):
        R[:, k, k] = 1.0
        R[:, 3 + k, 3 + k] = 1.0
    rx, ry, rz = r[:, 0], r[:, 1], r[:, 2]
    # rotation about x: (0, -rz, ry); about y: (rz, 0, -rx); about z: (-ry, rx, 0)
    R[:, 1, 3], R[:, 2, 3] = -rz, ry
    R[:, 0, 4], R[:, 2, 4] = rz, -rx
    R[:, 0, 5], R[:, 1, 5] = -ry, rx
    return R.reshape(6 * n, 6)


@dataclass
class MassProperties:
    """Rigid-body mass properties.

    Attributes
    ----------
    mass : float
        Mass (kg).
    cg : numpy.ndarray
        Centre of gravity in model coordinates (m).
    inertia : numpy.ndarray
        (3, 3) inertia tensor about the CG, model axes (kg·m²).
    """

    mass: float
    cg: np.ndarray
    inertia: np.ndarray

    @property
    def principal_diagonal(self) -> np.ndarray:
        """Diagonal (Ixx, Iyy, Izz) of the inertia tensor about the CG (kg·m²)."""
        return np.diag(self.inertia).copy()

    def to_dict(self) -> dict:
        """JSON-able form (SI units)."""
        return {
            "mass_kg": float(self.mass),
            "cg_m": [float(v) for v in self.cg],
            "inertia_kgm2": [[float(v) for v in row] for row in self.inertia],
        }

    @classmethod
    def from_dict(cls, d: dict) -> MassProperties:
        """Inverse of :meth:`to_dict`."""
        return cls(float(d["mass_kg"]), np.asarray(d["cg_m"]), np.asarray(d["inertia_kgm2"]))


def mass_properties_from_rigid_mass(Mrr: np.ndarray) -> MassProperties:
    """Mass properties from the 6 × 6 rigid-body mass matrix about the origin.

    ``Mrr = Rᵀ M R`` with ``R`` the rigid-body vectors about the origin: its translation block is
    ``m I``, its translation–rotation block ``-m [c]×`` and its rotation block the inertia tensor
    about the origin.
    """
    Mrr = 0.5 * (np.asarray(Mrr) + np.asarray(Mrr).T)
    m = float(np.trace(Mrr[:3, :3]) / 3.0)
    B = -Mrr[:3, 3:]  # = m [c]×
    s = np.array([B[2, 1] - B[1, 2], B[0, 2] - B[2, 0], B[1, 0] - B[0, 1]]) / 2.0
    c = s / m
    J0 = Mrr[3:, 3:]
    J = J0 - m * (np.dot(c, c) * np.eye(3) - np.outer(c, c))
    return MassProperties(mass=m, cg=c, inertia=J)


def mass_properties(M: sp.spmatrix | np.ndarray, nodes: np.ndarray) -> MassProperties:
    """Mass properties of a model with six DOFs per node at ``nodes`` and mass matrix ``M``."""
    R = rigid_body_vectors(nodes)
    return mass_properties_from_rigid_mass(R.T @ (M @ R))

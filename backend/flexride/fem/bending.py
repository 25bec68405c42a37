"""First vertical bending of a car body: where it lives among a finite-element body's modes,
and what an elastic mode passes from the air springs to a point of the body — the quantities
that compare the FE car body with the beam car body (:mod:`flexride.fem.beam`; docs/fem.md,
"The beam car body against the FE body").

Bending share. The beam car body's first bending moves every cross-section up and down by the
free–free shape φ₁(x) (:func:`flexride.fem.beam.mode_shape`). Imposed on every node of an FE
body as a vertical displacement field ψ (made M-orthogonal to the rigid-body motion, unit
M-norm), its share in elastic mode n is Γₙ² = (φₙᵀ M ψ)² for mass-normalised φₙ; the shares of
all modes add up to one, those of the modes kept to less. The mode with the largest share is
the FE body's first vertical bending *by content*, whatever deformation dominates it (the
classifier, :mod:`flexride.fem.classify`, names a mode after its dominant deformation and adds
"first vertical bending" only when rigid section motion carries 30–60 % of it).

Participation. A free body loaded by a vertical force F at every air-spring seat (in phase, as
bounce of both bogies drives it) accelerates at a point P, in mode n, by
−ω² pₙ F / (ωₙ² − ω² + 2jζₙωₙω) with pₙ = φₙ,z(P) Σ_seats φₙ,z(seat) (1/kg): at resonance
|pₙ| F / (2ζₙ). For a uniform free–free beam pₙ depends on the shape alone, not on the
bending stiffness.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from flexride.fem.beam import free_free_roots, mode_shape
from flexride.fem.rigid import rigid_body_vectors
from flexride.vehicle.topology import VehicleModel

__all__ = ["bending_shares", "secondary_participation"]

#: Name prefix of the air-spring elements of a vehicle (``secondary.1L`` …,
#: :func:`flexride.vehicle.topology.build_vehicle`).
SECONDARY = "secondary."


def bending_shares(nodes: np.ndarray, mass: sp.spmatrix | np.ndarray, shapes: np.ndarray,
                   length: float) -> np.ndarray:
    """Share of each elastic mode in the first bending of a uniform free–free beam.

    Parameters
    ----------
    nodes : numpy.ndarray
        (n, 3) node coordinates (m), x along the body from its centre (the beam spans
        −length/2 … +length/2).
    mass : scipy.sparse matrix or numpy.ndarray
        (6n, 6n) mass matrix (kg, six DOFs per node: ux, uy, uz, rx, ry, rz).
    shapes : numpy.ndarray
        (n, 6, n_modes) mass-normalised elastic mode shapes at the nodes (m and rad per unit
        modal coordinate), M-orthogonal to the rigid-body motion.
    length : float
        Beam length (m).

    Returns
    -------
    numpy.ndarray
        (n_modes,) Γₙ² (-), each in [0, 1], summing to at most one (module docs).
    """
    nodes = np.asarray(nodes, dtype=float).reshape(-1, 3)
    psi = np.zeros(6 * nodes.shape[0])
    x = np.clip(nodes[:, 0] + 0.5 * length, 0.0, length)
    psi[2::6] = mode_shape(float(free_free_roots(1)[0]), length, x)[0]
    rigid = rigid_body_vectors(nodes)
    m_rigid = mass @ rigid
    psi -= rigid @ np.linalg.solve(rigid.T @ m_rigid, m_rigid.T @ psi)
    m_psi = mass @ psi
    m_psi /= np.sqrt(float(psi @ m_psi))
    phi = np.asarray(shapes, dtype=float).reshape(psi.size, -1)
    return np.asarray(phi.T @ m_psi) ** 2


def secondary_participation(vehicle: VehicleModel, point: str) -> np.ndarray:
    """pₙ = φₙ,z(point) · Σ φₙ,z(seat) over the air-spring seats (1/kg), per elastic mode of
    the body that carries the recorded ``point`` of ``vehicle`` (module docs).

    Raises
    ------
    ValueError
        If ``vehicle`` records no point of that name.
    """
    found = [(b, m) for name, b, m in vehicle.points if name == point]
    if not found:
        raise ValueError(f"no recorded point {point!r}; the vehicle records "
                         f"{', '.join(name for name, _, _ in vehicle.points)}")
    b, marker = found[0]
    body = vehicle.bodies[b]
    seats = [e.marker_a for e in vehicle.elements
             if e.name.startswith(SECONDARY) and e.body_a == b]
    seat_sum = np.sum([body.markers[s][2, 6:] for s in seats], axis=0)
    return np.asarray(body.markers[marker][2, 6:] * seat_sum)

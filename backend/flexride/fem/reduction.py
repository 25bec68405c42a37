"""Model reduction: Guyan (static condensation), Craig–Bampton, free-interface modal truncation.

Each reduction returns a :class:`ReducedModel`: reduced mass and stiffness, the recovery matrix
from reduced coordinates to all nodal DOFs and the rigid-body vectors in reduced coordinates.
:func:`flexride.fem.modal_body.reduced_to_modal_body` then diagonalises it into a ModalBody, so
the solver never knows which reduction made a body.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from flexride.errors import FEModelError
from flexride.fem.eigen import ShiftInvert, factorise, solve_modes


@dataclass
class ReducedModel:
    """A reduced model.

    Attributes
    ----------
    method : str
        ``guyan``, ``craig-bampton`` or ``modal``.
    M, K : numpy.ndarray
        Reduced mass and stiffness (dense).
    recovery : numpy.ndarray
        (n_full_dof, n_reduced) map from reduced coordinates to the nodal DOFs.
    rigid_basis : numpy.ndarray
        (n_reduced, 6) rigid-body vectors about the origin in reduced coordinates.
    master_dofs : numpy.ndarray
        Nodal DOFs kept as physical coordinates (Guyan masters / Craig–Bampton interface).
    info : dict
        Method details (number of fixed-interface modes, their cut-off...).
    guyan_residual : numpy.ndarray, optional
        Guyan only: ``H = Gᵀ M_ss G`` with ``G = K_ss⁻¹ (M_sm − M_ss K_ss⁻¹ K_sm)``, from which
        the error indicator of paper Eq. (9) follows for each mode (see
        :func:`guyan_error_indicator`).
    """

    method: str
    M: np.ndarray
    K: np.ndarray
    recovery: np.ndarray
    rigid_basis: np.ndarray
    master_dofs: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    info: dict = field(default_factory=dict)
    guyan_residual: np.ndarray | None = None

    @property
    def n_reduced(self) -> int:
        """Number of reduced coordinates."""
        return int(self.M.shape[0])


def node_dofs(nodes: list[int] | np.ndarray, components: tuple[int, ...] = tuple(range(6))):
    """Global DOF indices of ``components`` (0..5) of ``nodes``, node-major, sorted."""
    nodes = np.unique(np.asarray(nodes, dtype=np.int64))
    return np.sort((6 * nodes[:, None] + np.asarray(components)[None, :]).ravel())


def _split(n: int, masters: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    is_m = np.zeros(n, dtype=bool)
    is_m[masters] = True
    return np.flatnonzero(is_m), np.flatnonzero(~is_m)


def _factor(A: sp.spmatrix, what: str):
    try:
        return factorise(sp.csc_matrix(A))
    except RuntimeError as exc:
        raise FEModelError(
            f"{what} is singular: the master/interface DOFs do not hold the model "
            "(choose nodes that fix all six rigid-body motions)"
        ) from exc


def guyan(K: sp.spmatrix, M: sp.spmatrix, master_dofs: np.ndarray) -> ReducedModel:
    """Guyan reduction onto ``master_dofs`` (paper Eqs. 5–8).

    ``u_s = T u_m`` with ``T = −K_ss⁻¹ K_sm``: exact for static loads at the masters.
    """
    n = K.shape[0]
    m, s = _split(n, np.asarray(master_dofs))
    K, M = sp.csc_matrix(K), sp.csc_matrix(M)
    Kss, Ksm = K[s][:, s], K[s][:, m]
    Mss, Msm = M[s][:, s], M[s][:, m]
    lu = _factor(Kss, "K_ss (slave stiffness)")
    T = -lu.solve(Ksm.toarray())
    Kr = K[m][:, m].toarray() + Ksm.T @ T
    Mr = M[m][:, m].toarray() + Msm.T @ T + T.T @ Msm.toarray() + T.T @ (Mss @ T)
    E = Msm.toarray() + Mss @ T  # M_sm − M_ss K_ss⁻¹ K_sm (Eq. 10 residual)
    G = lu.solve(E)
    H = G.T @ (Mss @ G)
    rec = np.zeros((n, m.size))
    rec[m, np.arange(m.size)] = 1.0
    rec[s] = T
    return ReducedModel(
        method="guyan",
        M=0.5 * (Mr + Mr.T),
        K=0.5 * (Kr + Kr.T),
        recovery=rec,
        rigid_basis=np.zeros((m.size, 6)),  # filled by caller with nodal rigid vectors
        master_dofs=m,
        info={"n_masters": int(m.size)},
        guyan_residual=0.5 * (H + H.T),
    )


def guyan_error_indicator(reduced: ReducedModel, q: np.ndarray, freqs_hz: np.ndarray):
    """Error indicator of paper Eq. (9) for each reduced mode.

    For a mode ``u_m = q`` at ω, the inertia forces the static condensation leaves out move the
    slaves by ``Δ = ω² K_ss⁻¹ (M_sm − M_ss K_ss⁻¹ K_sm) q``; the indicator is the mass-norm of Δ
    relative to the (unit) mass-norm of the mode: ``ε = ω² √(qᵀ H q)``.
    """
    if reduced.guyan_residual is None:
        return None
    w2 = (2 * np.pi * np.asarray(freqs_hz)) ** 2
    H = reduced.guyan_residual
    return w2 * np.sqrt(np.maximum(np.einsum("ij,ik,kj->j", q, H, q), 0.0))


def craig_bampton(
    K: sp.spmatrix,
    M: sp.spmatrix,
    interface_dofs: np.ndarray,
    cutoff_hz: float | None = None,
    n_modes: int | None = None,
) -> ReducedModel:
    """Craig–Bampton reduction: interface DOFs plus fixed-interface modes.

    One sparse factorisation of ``K_ii`` is reused for the constraint modes
    ``Ψ = −K_ii⁻¹ K_ib`` and for the shift-invert eigen solution of the fixed-interface
    problem (shift 0).

    Parameters
    ----------
    K, M : sparse matrix
        Full stiffness and mass.
    interface_dofs : numpy.ndarray
        Boundary DOFs kept as physical coordinates.
    cutoff_hz : float, optional
        Keep fixed-interface modes up to this frequency (Hz).
    n_modes : int, optional
        Keep this many fixed-interface modes (overrides ``cutoff_hz`` when given).
    """
    n = K.shape[0]
    b, i = _split(n, np.asarray(interface_dofs))
    K, M = sp.csc_matrix(K), sp.csc_matrix(M)
    Kii, Kib = K[i][:, i], K[i][:, b]
    Mii, Mib = M[i][:, i], M[i][:, b]
    factor = ShiftInvert(Kii, Mii, 0.0)
    Psi = -factor.solve(Kib.toarray())
    if n_modes is not None and n_modes == 0:
        Phi = np.zeros((i.size, 0))
        f_fixed = np.zeros(0)
    else:
        modes = solve_modes(
            Kii,
            Mii,
            n_modes=n_modes,
            f_max=None if n_modes is not None else cutoff_hz,
            factor=factor,
        )
        Phi, f_fixed = modes.shapes, modes.frequencies
    nb, nq = b.size, Phi.shape[1]
    T = np.zeros((n, nb + nq))
    T[b, np.arange(nb)] = 1.0
    T[np.ix_(i, np.arange(nb))] = Psi
    T[np.ix_(i, nb + np.arange(nq))] = Phi
    # blocks without forming T^T M T on the full model
    Mbb = M[b][:, b].toarray()
    Mr_bb = Mbb + Mib.T @ Psi + Psi.T @ Mib.toarray() + Psi.T @ (Mii @ Psi)
    Mr_bq = Mib.T @ Phi + Psi.T @ (Mii @ Phi)
    Kr_bb = K[b][:, b].toarray() + Kib.T @ Psi
    Mr = np.block([[Mr_bb, Mr_bq], [Mr_bq.T, np.eye(nq)]])
    Kr = np.zeros_like(Mr)
    Kr[:nb, :nb] = Kr_bb
    Kr[nb:, nb:] = np.diag((2 * np.pi * f_fixed) ** 2)
    return ReducedModel(
        method="craig-bampton",
        M=0.5 * (Mr + Mr.T),
        K=0.5 * (Kr + Kr.T),
        recovery=T,
        rigid_basis=np.zeros((nb + nq, 6)),
        master_dofs=b,
        info={
            "n_interface_dofs": int(nb),
            "n_fixed_interface_modes": int(nq),
            "fixed_interface_frequencies_hz": [float(v) for v in f_fixed],
        },
    )


def rigid_basis_for(reduced: ReducedModel, rigid: np.ndarray) -> np.ndarray:
    """Rigid-body vectors in the reduced coordinates of a Guyan or Craig–Bampton model.

    Rigid motion is statically exact in both: the masters/interface DOFs take the rigid
    values (rows ``master_dofs`` of ``rigid``, the (n_dof, 6) rigid-body vectors of the full
    model) and the modal coordinates are zero.
    """
    out = np.zeros((reduced.n_reduced, 6))
    out[: reduced.master_dofs.size] = rigid[reduced.master_dofs]
    return out

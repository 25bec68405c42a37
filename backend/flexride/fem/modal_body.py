"""Turn a (full or reduced) FE model into the solver's :class:`~flexride.bodies.ModalBody`.

The reduced mass and stiffness matrices are diagonalised; the six rigid-body modes are replaced
by the exact rigid-body motion of the CG (the solver's six rigid coordinates), the elastic modes
are made M-orthogonal to them and mass-normalised (φᵀMφ = 1), and their shapes are recovered at
every node of the model so that markers can be placed anywhere.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from flexride.bodies import ModalBody
from flexride.errors import FEModelError
from flexride.fem.damping import DampingSpec, modal_damping_ratios
from flexride.fem.eigen import free_free_modes
from flexride.fem.rigid import (
    MassProperties,
    mass_properties_from_rigid_mass,
    rigid_body_vectors,
)


@dataclass
class BodyModes:
    """Rigid-body properties and elastic modes of a body, expressed at its nodes.

    Attributes
    ----------
    body : ModalBody
        The solver's body (rigid inertia from the model, retained elastic modes, markers).
    nodes : numpy.ndarray
        (n, 3) node coordinates in model axes (m; z above top of rail for vehicle bodies).
    mass_properties : MassProperties
        Mass, CG (model coordinates) and inertia tensor of the model.
    shapes : numpy.ndarray
        (n, 6, n_elastic) elastic mode shapes at every node (m and rad per unit modal
        coordinate), M-orthogonal to the rigid-body modes, mass-normalised.
    rigid_frequencies : numpy.ndarray
        Frequencies of the six rigid-body modes (Hz; zero, they are imposed exactly).
    reduced_modes : numpy.ndarray
        (n_reduced, n_elastic) elastic modes in the reduced coordinates.
    node_names : dict of str to int
        Named nodes.
    """

    body: ModalBody
    nodes: np.ndarray
    mass_properties: MassProperties
    shapes: np.ndarray
    rigid_frequencies: np.ndarray
    reduced_modes: np.ndarray | None = None
    node_names: dict[str, int] = field(default_factory=dict)

    def __post_init__(self) -> None:
        """Check the shapes of the inertia and elastic data."""
        # markers added later (suspension points, user and floor-grid points) take their
        # elastic shapes from the nearest node
        if self.body.shape_at is None:
            self.body.shape_at = self.shape_at

    @property
    def cg(self) -> np.ndarray:
        """CG in model coordinates (m)."""
        return self.mass_properties.cg

    def nearest_node(self, position: np.ndarray | tuple[float, float, float]) -> int:
        """Index of the node nearest to ``position`` given relative to the CG (m)."""
        p = np.asarray(position, dtype=float) + self.cg
        return int(np.argmin(np.einsum("ij,ij->i", self.nodes - p, self.nodes - p)))

    def shape_at(self, position: np.ndarray | tuple[float, float, float]) -> np.ndarray:
        """(6, n_elastic) elastic shapes at the node nearest to ``position`` (relative to CG,
        body axes, m): translations (m) and rotations (rad) per unit modal coordinate.
        """
        return np.array(self.shapes[self.nearest_node(position)])

    def node_position(self, node: int) -> np.ndarray:
        """Position of ``node`` relative to the CG (m)."""
        return self.nodes[node] - self.cg


def _dense(a) -> np.ndarray:
    return a.toarray() if sp.issparse(a) else np.asarray(a, dtype=float)


def reduced_to_modal_body(
    name: str,
    nodes_xyz: np.ndarray,
    M,
    K,
    *,
    recovery=None,
    rigid_basis: np.ndarray | None = None,
    cutoff_hz: float | None = 100.0,
    n_modes: int | None = None,
    damping: DampingSpec = 0.02,
    x_ref: float = 0.0,
    markers: dict[str, int] | None = None,
) -> BodyModes:
    """Diagonalise a (reduced) FE model into a :class:`~flexride.bodies.ModalBody`.

    Parameters
    ----------
    name : str
        Body name.
    nodes_xyz : numpy.ndarray
        (n, 3) coordinates (model axes, m; z above top of rail) of the nodes whose six DOFs are
        the rows of ``recovery`` (or of ``M`` and ``K`` when ``recovery`` is None).
    M, K : sparse or dense matrix
        Mass and stiffness in the reduced coordinates (free–free: six rigid-body modes).
    recovery : matrix, optional
        (6 n, n_reduced) map from reduced coordinates to the nodal DOFs (Guyan / Craig–Bampton
        transformation, or the retained mode shapes); None when ``M`` and ``K`` are nodal.
    rigid_basis : numpy.ndarray, optional
        (n_reduced, 6) rigid-body vectors (about the origin) in reduced coordinates; computed
        from the nodes when omitted.
    cutoff_hz : float or None
        Keep elastic modes up to this frequency (Hz).
    n_modes : int, optional
        Keep (at most) this many elastic modes.
    damping : float, sequence or RayleighDamping
        Modal damping of the elastic modes.
    x_ref : float
        Position of the body's reference frame along the vehicle (m).
    markers : dict of str to int, optional
        Named nodes whose elastic shapes go into ``ModalBody.elastic_shapes``.

    Returns
    -------
    BodyModes
        The ModalBody and the nodal elastic shapes (for :meth:`BodyModes.shape_at`).

    Raises
    ------
    FEModelError
        If the model does not have six rigid-body modes (constrained or with mechanisms).
    """
    nodes_xyz = np.asarray(nodes_xyz, dtype=float).reshape(-1, 3)
    R = _rigid_basis(nodes_xyz, M, recovery, rigid_basis)
    Mrr, props = _rigid_mass(name, M, R)
    f_max = None if cutoff_hz is None else float(cutoff_hz)
    if f_max is None and n_modes is None:
        raise ValueError("give cutoff_hz or n_modes")
    f_el, q = _elastic_modes(K, M, R, Mrr, f_max, n_modes)
    full = q if recovery is None else recovery @ q
    shapes = np.asarray(full).reshape(nodes_xyz.shape[0], 6, -1)
    body = _modal_body(name, props, f_el, modal_damping_ratios(damping, f_el), shapes, x_ref,
                       markers)
    return BodyModes(
        body=body,
        nodes=nodes_xyz,
        mass_properties=props,
        shapes=shapes,
        rigid_frequencies=np.zeros(6),
        reduced_modes=q,
        node_names=dict(markers or {}),
    )


def _modal_body(name: str, props: MassProperties, f_el: np.ndarray, zeta: np.ndarray,
                shapes: np.ndarray, x_ref: float, markers: dict[str, int] | None) -> ModalBody:
    """The :class:`~flexride.bodies.ModalBody` of the diagonalised model.

    Parameters
    ----------
    name : str
        Body name.
    props : MassProperties
        Mass (kg), CG (m) and inertia tensor about the CG (kg·m²); the diagonal is kept.
    f_el : numpy.ndarray
        Elastic eigenfrequencies (Hz).
    zeta : numpy.ndarray
        Modal damping ratios of the elastic modes (-).
    shapes : numpy.ndarray
        (n_nodes, 6, n_modes) nodal elastic shapes (m and rad per unit modal coordinate).
    x_ref : float
        Position of the body's reference frame along the vehicle (m).
    markers : dict of str to int, optional
        Named nodes whose shapes go into ``elastic_shapes``.

    Returns
    -------
    ModalBody
        The body, with copies of the frequencies and marker shapes.
    """
    return ModalBody(
        name=name,
        mass=props.mass,
        inertia=np.diag(props.inertia).copy(),
        x_ref=float(x_ref),
        cg_height=float(props.cg[2]),
        elastic_frequencies=f_el.copy(),
        elastic_damping=zeta,
        elastic_shapes={k: shapes[v].copy() for k, v in (markers or {}).items()},
    )


def _rigid_basis(nodes_xyz: np.ndarray, M, recovery, rigid_basis: np.ndarray | None) -> np.ndarray:
    """(n_reduced, 6) rigid-body vectors about the origin in the model's coordinates: the given
    ones, those of the nodes (nodal model) or their least-squares fit through ``recovery``.

    Raises
    ------
    FEModelError
        If a nodal model's matrices do not have six DOFs per node.
    """
    n_red = M.shape[0]
    R_nodes = rigid_body_vectors(nodes_xyz)
    if recovery is None:
        if n_red != R_nodes.shape[0]:
            raise FEModelError(
                f"matrices have {n_red} DOFs but {nodes_xyz.shape[0]} nodes need "
                f"{R_nodes.shape[0]} (6 per node)"
            )
        return R_nodes if rigid_basis is None else np.asarray(rigid_basis, dtype=float)
    if rigid_basis is not None:
        return rigid_basis
    R, *_ = np.linalg.lstsq(_dense(recovery), R_nodes, rcond=None)
    return R


def _rigid_mass(name: str, M, R: np.ndarray) -> tuple[np.ndarray, MassProperties]:
    """The 6 × 6 rigid-body mass matrix ``Rᵀ M R`` (kg, kg·m, kg·m²) and the mass properties
    it gives (mass, CG, inertia tensor about the CG).

    Raises
    ------
    FEModelError
        If the mass or a principal inertia is not positive.
    """
    Mrr = R.T @ (M @ R)
    props = mass_properties_from_rigid_mass(Mrr)
    if props.mass <= 0 or np.any(np.linalg.eigvalsh(props.inertia) <= 0):
        raise FEModelError(f"model {name!r} has no positive mass or inertia: check M")
    return Mrr, props


def _elastic_modes(K, M, R: np.ndarray, Mrr: np.ndarray, f_max: float | None,
                   n_modes: int | None) -> tuple[np.ndarray, np.ndarray]:
    """The elastic modes kept (up to ``f_max`` Hz and at most ``n_modes``): frequencies (Hz)
    and shapes in the model's coordinates, made exactly M-orthogonal to the rigid-body vectors
    ``R`` (rigid mass matrix ``Mrr``) and mass-normalised.
    """
    modes = free_free_modes(K, M, R, n_elastic=n_modes if n_modes is not None else 6, f_max=f_max)
    f_el = modes.frequencies[6:]
    q = modes.shapes[:, 6:]
    Mrr_inv = np.linalg.inv(Mrr)
    MR = M @ R
    # exact M-orthogonality to the rigid-body modes, then unit modal mass
    q = q - R @ (Mrr_inv @ (MR.T @ q))
    q = q / np.sqrt(np.einsum("ij,ij->j", q, M @ q))
    keep = np.ones(f_el.size, dtype=bool)
    if f_max is not None:
        keep &= f_el <= f_max
    if n_modes is not None:
        keep &= np.arange(f_el.size) < n_modes
    return f_el[keep], q[:, keep]

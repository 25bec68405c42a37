"""The finite-element model container shared by the generators, importers and reductions."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from flexride.fem.pyfe3d_adapter import BeamSection, Mesh, ShellSection, assemble
from flexride.fem.rigid import MassProperties, mass_properties


@dataclass
class FEModel:
    """A structural FE model with six DOFs per node.

    Attributes
    ----------
    name : str
        Model name (``carbody``, ``frame`` or a user name).
    mesh : Mesh
        Nodes, elements and lumped masses.
    shell_sections, beam_sections : list
        Sections indexed by the mesh's group arrays.
    shell_group_names, beam_group_names : list of str
        Readable names of those groups.
    named_nodes : dict of str to int
        Nodes with a meaning (suspension seats, output points, floor grid...).
    node_region : numpy.ndarray
        (n_nodes,) region index of each node, names in ``region_names`` (for mode
        classification and drawing).
    region_names : list of str
        Region names.
    K, M : scipy.sparse.csc_matrix, optional
        Assembled matrices (given directly for imported models).
    info : dict
        Free-form description (mass-distribution report, parameters).
    """

    name: str
    mesh: Mesh
    shell_sections: list[ShellSection] = field(default_factory=list)
    beam_sections: list[BeamSection] = field(default_factory=list)
    shell_group_names: list[str] = field(default_factory=list)
    beam_group_names: list[str] = field(default_factory=list)
    named_nodes: dict[str, int] = field(default_factory=dict)
    node_region: np.ndarray | None = None
    region_names: list[str] = field(default_factory=list)
    K: sp.csc_matrix | None = None
    M: sp.csc_matrix | None = None
    info: dict = field(default_factory=dict)

    @property
    def nodes(self) -> np.ndarray:
        """(n, 3) node coordinates (m)."""
        return self.mesh.nodes

    @property
    def n_dof(self) -> int:
        """Number of DOFs."""
        return self.mesh.n_dof

    def assemble(self, force: bool = False) -> tuple[sp.csc_matrix, sp.csc_matrix]:
        """Assemble (once) and return ``K, M``."""
        if self.K is None or self.M is None or force:
            self.K, self.M = assemble(self.mesh, self.shell_sections, self.beam_sections)
        return self.K, self.M

    def mass_properties(self) -> MassProperties:
        """Mass, CG and inertia tensor from the assembled mass matrix."""
        _, M = self.assemble()
        return mass_properties(M, self.nodes)

    def nearest_node(self, point: np.ndarray) -> int:
        """Index of the node nearest to ``point`` (model coordinates, m)."""
        d = np.linalg.norm(self.nodes - np.asarray(point, dtype=float)[None, :], axis=1)
        return int(np.argmin(d))

"""Distribution of non-structural mass so that a model matches a mass, CG and inertias.

The non-structural mass (equipment, interior, passengers) is split into *groups*: sets of nodes
with fixed relative weights and an offset (e.g. under-floor equipment hanging below the floor).
The group masses are the unknowns of a bounded linear least-squares problem whose rows are the
targets (mass, first moments, the three second moments about the origin) weighted strongly, plus
a weak pull of every group towards a prior (a plausible split), so the answer is unique and
plausible. Groups are built symmetric, so the products of inertia vanish.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import lsq_linear

from flexride.fem.rigid import MassProperties


@dataclass
class MassGroup:
    """Nodes that share one unknown non-structural mass.

    Attributes
    ----------
    name : str
        Group name (``underfloor.x3`` ...).
    kind : str
        What the mass stands for (``floor``, ``underfloor``, ``roof``...).
    nodes : numpy.ndarray
        Node indices.
    weights : numpy.ndarray
        Share of the group mass at each node (sums to 1).
    offsets : numpy.ndarray
        (n, 3) offset of each point mass from its node (m).
    prior : float
        Plausible group mass (kg), the regularisation target.
    """

    name: str
    kind: str
    nodes: np.ndarray
    weights: np.ndarray
    offsets: np.ndarray
    prior: float = 0.0

    def unit_moments(self, coords: np.ndarray) -> np.ndarray:
        """Moments of a unit group mass: 1, x, y, z, y²+z², x²+z², x²+y² (origin)."""
        p = coords[self.nodes] + self.offsets
        w = self.weights
        x, y, z = p[:, 0], p[:, 1], p[:, 2]
        return np.array(
            [
                w.sum(),
                w @ x,
                w @ y,
                w @ z,
                w @ (y**2 + z**2),
                w @ (x**2 + z**2),
                w @ (x**2 + y**2),
            ]
        )


@dataclass
class InertiaTarget:
    """Target rigid-body properties.

    Attributes
    ----------
    mass : float
        Mass (kg).
    cg : numpy.ndarray
        Centre of gravity, model coordinates (m).
    inertia : numpy.ndarray
        Ixx, Iyy, Izz about the CG (kg·m²).
    """

    mass: float
    cg: np.ndarray
    inertia: np.ndarray

    def origin_moments(self) -> np.ndarray:
        """Target moments 1, x, y, z, y²+z², x²+z², x²+y² (times mass, about the origin)."""
        m, c, i = self.mass, np.asarray(self.cg, float), np.asarray(self.inertia, float)
        j0 = i + m * (np.dot(c, c) - c**2)
        return np.array([m, m * c[0], m * c[1], m * c[2], j0[0], j0[1], j0[2]])

    def errors(self, props: MassProperties) -> dict:
        """Relative errors of mass and inertias, CG error (m)."""
        return {
            "mass": float(props.mass / self.mass - 1.0),
            "cg_m": [float(v) for v in (props.cg - self.cg)],
            "ixx": float(props.inertia[0, 0] / self.inertia[0] - 1.0),
            "iyy": float(props.inertia[1, 1] / self.inertia[1] - 1.0),
            "izz": float(props.inertia[2, 2] / self.inertia[2] - 1.0),
        }


def structural_moments(props: MassProperties) -> np.ndarray:
    """Moments (as in :meth:`InertiaTarget.origin_moments`) of a structure's mass properties."""
    t = InertiaTarget(props.mass, props.cg, np.diag(props.inertia))
    return t.origin_moments()


def solve_group_masses(
    coords: np.ndarray,
    groups: list[MassGroup],
    structure: MassProperties,
    target: InertiaTarget,
    weight: float = 1.0e4,
) -> np.ndarray:
    """Non-negative group masses that make structure + groups match ``target``.

    Parameters
    ----------
    coords : numpy.ndarray
        (n, 3) node coordinates (m).
    groups : list of MassGroup
        Candidate groups with their priors.
    structure : MassProperties
        Mass properties of the structure alone (about its CG).
    target : InertiaTarget
        Required properties of the whole body.
    weight : float
        Weight of the target rows against the prior rows.

    Returns
    -------
    numpy.ndarray
        Mass of each group (kg).
    """
    A = np.array([g.unit_moments(coords) for g in groups]).T  # (7, ng)
    b = target.origin_moments() - structural_moments(structure)
    m = target.mass
    # mass and first moments are matched (almost) exactly; the three second-moment rows are
    # relative errors of the inertias about the CG, weighted by sqrt(I) so that an
    # inconsistent target (e.g. Izz > Ixx + Iyy) is missed by the same fraction on each axis
    inertia = np.maximum(np.asarray(target.inertia, float), 1e-9)
    row_w = np.concatenate([[100.0] * 4, np.sqrt(inertia / inertia.mean())])
    scale = np.concatenate([[m, m * 0.01, m * 0.01, m * 0.01], inertia]) / row_w
    As = A / scale[:, None]
    bs = b / scale
    prior = np.array([max(g.prior, 0.0) for g in groups])
    s = np.maximum(prior, 1e-3 * max(b[0], 1.0) / max(len(groups), 1))
    rows = np.vstack([weight * As, np.diag(1.0 / s)])
    rhs = np.concatenate([weight * bs, prior / s])
    res = lsq_linear(rows, rhs, bounds=(0.0, np.inf), lsmr_tol="auto", max_iter=5000)
    return np.maximum(res.x, 0.0)


def groups_to_point_masses(
    groups: list[MassGroup], masses: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Flatten groups with their masses to (nodes, masses, offsets) arrays."""
    nodes = np.concatenate([g.nodes for g in groups])
    vals = np.concatenate([g.weights * mg for g, mg in zip(groups, masses, strict=False)])
    offs = np.vstack([g.offsets for g in groups])
    keep = vals > 0.0
    return nodes[keep], vals[keep], offs[keep]

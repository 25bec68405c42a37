"""Left–right symmetry of the linearised one-step map: two independent halves where it holds.

On straight, level track the vehicle and the track are mirror images of themselves about the
vertical plane through the track centre line. The mirror maps every coordinate of the system
onto itself or its partner with a sign — the rigid coordinates of a body on the centre line
onto themselves (x, z, pitch even; y, roll, yaw odd), a coordinate of the left rail onto the
same coordinate of the right rail, the creep forces of a left wheel onto those of the right
wheel — and the linearised map commutes with it. Its symmetric and antisymmetric parts are then
invariant subspaces: the map's eigenvalues are those of two matrices of half the size, found
for an eighth of the work each.

Nothing is assumed about the signs (how the model orients a rail's torsion, which of an elastic
body's modes are symmetric): the pairing comes from the names, the signs are read from the
Jacobian itself — propagated along its couplings from the car body's vertical coordinate
(even) — and the symmetry is accepted only if every block of the Jacobian is reproduced by the
mirror to :data:`RTOL`. On a curve, with cant, or with elastic modes of mixed parity it is not,
and the map is treated whole.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexride.solver.step_map import StepJacobian

#: Relative size (to the largest entry of its block) below which an entry of the Jacobian is
#: taken as zero when the signs are propagated, and the relative error to which the mirror
#: must reproduce every block.
RTOL = 1.0e-6


@dataclass(frozen=True)
class Half:
    """One half (symmetric or antisymmetric) of a mirror-symmetric state.

    Columns a of the basis are ``w1[a]·e[p1[a]] + w2[a]·e[p2[a]]`` (orthonormal), separately
    for the coordinates (``x``) and the creep states (``c``).
    """

    x: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]
    c: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]

    def project(self, jac: StepJacobian) -> StepJacobian:
        """The blocks of ``jac`` in this half's basis (Pᵀ J P)."""
        x, c = self.x, self.c
        return StepJacobian(_pjp(jac.ax, x, x), _pjp(jac.av, x, x), _pjp(jac.ac, x, c),
                            _pjp(jac.cx, c, x), _pjp(jac.cv, c, x), _pjp(jac.cc, c, c))

    def expand(self, shape: np.ndarray) -> np.ndarray:
        """A coordinate vector of this half in the full coordinates."""
        p1, p2, w1, w2 = self.x
        n = int(max(p1.max(initial=-1), p2.max(initial=-1))) + 1
        out = np.zeros(n, dtype=shape.dtype)
        np.add.at(out, p1, w1 * shape)
        np.add.at(out, p2, w2 * shape)
        return out


def _pjp(m: np.ndarray, left: tuple, right: tuple) -> np.ndarray:
    """Pᵀ M Q for bases given as (p1, p2, w1, w2) of :class:`Half`."""
    lp1, lp2, lw1, lw2 = left
    rp1, rp2, rw1, rw2 = right
    out = lw1[:, None] * m[np.ix_(lp1, rp1)] * rw1[None, :]
    out += lw1[:, None] * m[np.ix_(lp1, rp2)] * rw2[None, :]
    out += lw2[:, None] * m[np.ix_(lp2, rp1)] * rw1[None, :]
    out += lw2[:, None] * m[np.ix_(lp2, rp2)] * rw2[None, :]
    return out


def coordinate_partners(names: list[str]) -> np.ndarray:
    """The mirror partner of each coordinate by name: ``rail.left.…`` ↔ ``rail.right.…``,
    every other coordinate (a body on the centre line) its own.
    """
    index = {n: i for i, n in enumerate(names)}
    swap = {"left": "right", "right": "left"}

    def partner(name: str) -> int:
        parts = name.split(".")
        if parts[0] == "rail" and len(parts) > 1 and parts[1] in swap:
            return index.get(".".join([parts[0], swap[parts[1]], *parts[2:]]), -1)
        return index[name]

    return np.array([partner(n) for n in names], dtype=np.int64)


def creep_partners(flat_index: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """The partner of each kept creep state (flat indices into ``cst`` of ``shape`` =
    (wheelsets, 2 sides, values)): the same value of the other wheel; −1 if not kept.
    """
    w, side, k = np.unravel_index(flat_index, shape)
    mirror = np.ravel_multi_index((w, 1 - side, k), shape)
    where = {int(f): i for i, f in enumerate(flat_index)}
    return np.array([where.get(int(m), -1) for m in mirror], dtype=np.int64)


def mirror_halves(jac: StepJacobian, x_partner: np.ndarray, c_partner: np.ndarray,
                  anchor: int) -> tuple[Half, Half] | None:
    """The symmetric and antisymmetric halves of ``jac`` under the mirror pairing
    (``x_partner``, ``c_partner``), with the coordinate ``anchor`` even; None when the blocks
    are not mirror-symmetric (module docs).
    """
    n = jac.n
    partner = np.concatenate([x_partner, np.where(c_partner >= 0, c_partner + n, -1)])
    if np.any(partner < 0) or np.any(partner[partner] != np.arange(partner.size)):
        return None
    full = _state_matrix(jac)
    sign = _signs(full, partner, anchor)
    if sign is None or np.any(sign[partner] != sign):
        return None
    mirrored = sign[:, None] * full[np.ix_(partner, partner)] * sign[None, :]
    if not np.all(np.abs(mirrored - full) <= RTOL * _scale(full)):
        return None
    halves = tuple(_half(partner, sign, parity, n) for parity in (1.0, -1.0))
    return halves[0], halves[1]


def _state_matrix(jac: StepJacobian) -> np.ndarray:
    """The couplings of the state (coordinates, then creep states) in one square matrix: the
    coordinates' rows hold ∂A/∂X + ∂A/∂V and ∂A/∂c, the creep states' ∂c/∂X + ∂c/∂V and ∂c/∂c
    (each block scaled to its largest entry, so that every coupling counts alike).
    """
    def unit(m: np.ndarray) -> np.ndarray:
        top = np.abs(m).max() if m.size else 0.0
        return m / top if top > 0.0 else m

    return np.block([[unit(jac.ax) + unit(jac.av), unit(jac.ac)],
                     [unit(jac.cx) + unit(jac.cv), unit(jac.cc)]])


def _scale(m: np.ndarray) -> float:
    return float(np.abs(m).max()) if m.size else 0.0


def _signs(full: np.ndarray, partner: np.ndarray, anchor: int) -> np.ndarray | None:
    """Mirror signs of the state read from its couplings: along a breadth-first tree of the
    couplings from ``anchor`` (even; then from each state no coupling reaches, taken even),
    sign_k = sign_i · sgn(M[partner i, partner k] / M[i, k]); None if any coupling disagrees
    with the signs so found.
    """
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import breadth_first_order

    significant = np.abs(full) > RTOL * _scale(full)
    significant |= significant.T
    mirrored = full[np.ix_(partner, partner)]
    agree = np.where(full * mirrored != 0.0, np.sign(full * mirrored),
                     np.sign(full.T * mirrored.T))  # ±1 on every significant coupling
    graph = csr_matrix(significant)
    sign = np.zeros(full.shape[0])
    for start in [anchor, *range(full.shape[0])]:
        if sign[start] != 0.0:
            continue
        order, pred = breadth_first_order(graph, start, directed=False)
        sign[start] = 1.0
        for k in order[1:]:
            sign[k] = sign[pred[k]] * agree[pred[k], k]
    rows, cols = np.nonzero(significant)
    if np.any(sign[rows] * sign[cols] != agree[rows, cols]):
        return None
    return sign


def _half(partner: np.ndarray, sign: np.ndarray, parity: float, n: int) -> Half:
    """The orthonormal basis of the states of ``parity`` (+1 symmetric, −1 antisymmetric),
    split into coordinates and creep states.
    """
    p1, p2, w1, w2 = [], [], [], []
    for i in range(partner.size):
        j = int(partner[i])
        if j == i:
            if sign[i] == parity:
                p1.append(i)
                p2.append(i)
                w1.append(1.0)
                w2.append(0.0)
        elif i < j:
            p1.append(i)
            p2.append(j)
            w1.append(np.sqrt(0.5))
            w2.append(parity * sign[i] * np.sqrt(0.5))
    p1a, p2a = np.array(p1, dtype=np.int64), np.array(p2, dtype=np.int64)
    w1a, w2a = np.array(w1), np.array(w2)
    xs = p1a < n
    return Half((p1a[xs], p2a[xs], w1a[xs], w2a[xs]),
                (p1a[~xs] - n, p2a[~xs] - n, w1a[~xs], w2a[~xs]))

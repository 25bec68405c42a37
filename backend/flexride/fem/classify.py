"""Mode classification by dominant deformation (car bodies and other slender shells).

Each cross-section (nodes that share an x coordinate) is fitted with a rigid in-plane motion:
lateral ``v``, vertical ``w`` and twist ``θx``. The share of the mode's kinetic energy that these
section motions carry tells beam-like modes (vertical / lateral bending, torsion) from modes that
deform the cross-section. A cross-section deformation whose in-plane shear (the section's
rectangle becoming a rhombus) carries at least half of the displacement is *rhombic*; the others
are named after the region that carries most of their energy (roof, floor, side walls: breathing
when the two walls move in opposite directions). Every name comes from the vocabulary of
:mod:`flexride.fem.mode_types`.
"""

from __future__ import annotations

import numpy as np

from flexride.fem.mode_types import (
    FLOOR_LOCAL,
    LATERAL_BENDING,
    RHOMBIC,
    ROOF_FLOOR_BREATHING,
    ROOF_LOCAL,
    SECTION_DEFORMATION,
    SIDE_WALL_BREATHING,
    SIDE_WALLS_LATERAL,
    TORSION,
    UNCLASSIFIED,
    VERTICAL_BENDING,
    beam_mode_name,
)

#: Share of a mode's (geometric) displacement carried by the in-plane shear of the
#: cross-sections from which a non-beam-like mode is rhombic.
RHOMBIC_THRESHOLD = 0.5


def _energy_density(phi: np.ndarray, M) -> np.ndarray:
    """Per-DOF kinetic-energy density ``φ ⊙ Mφ`` (non-negative part)."""
    return np.maximum(phi * (M @ phi), 0.0)


def _zero_crossings(values: np.ndarray) -> int:
    v = values[np.abs(values) > 0.05 * np.max(np.abs(values))]
    return int(np.sum(np.sign(v[1:]) != np.sign(v[:-1]))) if v.size > 1 else 0


def classify_mode(
    phi: np.ndarray,
    M,
    nodes: np.ndarray,
    node_region: np.ndarray | None = None,
    region_names: list[str] | None = None,
    beam_threshold: float = 0.6,
) -> str:
    """Classify one elastic mode of a car body (or any slender shell along x).

    Parameters
    ----------
    phi : numpy.ndarray
        Mode shape (6 per node).
    M : sparse matrix
        Mass matrix (unused by the geometric criteria; kept for a uniform signature).
    nodes : numpy.ndarray
        (n, 3) node coordinates (m); x is the long axis.
    node_region, region_names : optional
        Region index of each node and region names (``floor``, ``roof``, ``wall_left``...).
    beam_threshold : float
        Share of the (geometric) displacement carried by rigid section motion above which a
        mode is beam-like.

    Returns
    -------
    str
        A name built from :data:`flexride.fem.mode_types.MODE_TYPES`, e.g.
        ``first vertical bending``, ``torsion``, ``rhombic``, ``breathing (side walls)``,
        ``floor local``, ``roof–floor breathing``; a beam-like part of 30–60 % of a
        cross-section deformation is added (``floor local + first vertical bending``).
    """
    n = nodes.shape[0]
    u = phi.reshape(n, 6)[:, :3]
    total = float(np.sum(u**2))
    if total <= 0:
        return UNCLASSIFIED
    energies, sections = _section_motions(u, nodes)
    beam = sum(energies) / total
    beam_name = _beam_name(energies, sections)
    if beam >= beam_threshold:
        return beam_name
    needed = {"floor", "roof", "wall_left", "wall_right"}
    if section_shear_share(u, nodes) >= RHOMBIC_THRESHOLD:
        local = RHOMBIC
    elif node_region is None or not region_names or not needed <= set(region_names):
        return SECTION_DEFORMATION
    else:
        local = _local_name(u, nodes, node_region, region_names)
    return f"{local} + {beam_name}" if beam >= 0.3 else local


def section_shear_share(u: np.ndarray, nodes: np.ndarray) -> float:
    """Share of the displacement ``u`` (n, 3) carried by the in-plane shear of the
    cross-sections (nodes sharing an x coordinate, at least four).

    Each section's in-plane translations are fitted by least squares with a linear field
    about its centroid, ``u_y = v + (γ − θ) Δz + ε_y Δy`` and ``u_z = w + (γ + θ) Δy + ε_z Δz``:
    translations ``v``, ``w``, twist ``θ``, stretches ``ε_y``, ``ε_z`` and the pure shear
    ``γ`` that turns the section's rectangle into a rhombus (one diagonal lengthens, the
    other shortens) — the rhombic distortion.

    Returns
    -------
    float
        ``Σ γ² (Δy² + Δz²)`` over all sections' nodes divided by ``Σ |u|²`` (-).
    """
    total = float(np.sum(u**2))
    if total <= 0:
        return 0.0
    shear = 0.0
    for idx in _stations(nodes, 4):
        dy = nodes[idx, 1] - nodes[idx, 1].mean()
        dz = nodes[idx, 2] - nodes[idx, 2].mean()
        m = idx.size
        A = np.zeros((2 * m, 6))
        A[:m, 0], A[m:, 1] = 1.0, 1.0
        A[:m, 2], A[m:, 2] = -dz, dy  # twist θ
        A[:m, 3], A[m:, 3] = dz, dy  # shear γ
        A[:m, 4], A[m:, 5] = dy, dz  # stretches ε_y, ε_z
        sol, *_ = np.linalg.lstsq(A, np.concatenate([u[idx, 1], u[idx, 2]]), rcond=None)
        shear += sol[3] ** 2 * float(np.sum(dy**2 + dz**2))
    return shear / total


def _stations(nodes: np.ndarray, min_nodes: int) -> list[np.ndarray]:
    """Node indices of each cross-section (nodes sharing x to 0.1 mm) with at least
    ``min_nodes`` nodes, in ascending x.
    """
    _, inv = np.unique(np.round(nodes[:, 0], 4), return_inverse=True)
    groups = [np.flatnonzero(inv == s) for s in range(int(inv.max()) + 1)] if inv.size else []
    return [g for g in groups if g.size >= min_nodes]


def _section_motions(u: np.ndarray, nodes: np.ndarray) -> tuple[
        tuple[float, float, float], tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Rigid in-plane motion of each cross-section (nodes sharing an x coordinate, at least
    three) fitted to the nodal translations ``u`` (n, 3) by least squares.

    Returns
    -------
    energies : (float, float, float)
        Geometric share of the lateral ``v``, vertical ``w`` and twist ``θx`` motions (Σ of
        squared displacements they carry, m²).
    sections : (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        ``v`` (m), ``w`` (m) and ``θx`` (rad) of each section along x.
    """
    xr = np.round(nodes[:, 0], 4)
    stations, inv = np.unique(xr, return_inverse=True)
    v_sec = np.zeros(stations.size)
    w_sec = np.zeros(stations.size)
    t_sec = np.zeros(stations.size)
    e_v = e_w = e_t = 0.0
    for s in range(stations.size):
        idx = np.flatnonzero(inv == s)
        if idx.size < 3:
            continue
        y, z = nodes[idx, 1], nodes[idx, 2]
        y0, z0 = y.mean(), z.mean()
        # u_y = v - θ (z - z0) ; u_z = w + θ (y - y0)
        A = np.zeros((2 * idx.size, 3))
        A[: idx.size, 0] = 1.0
        A[: idx.size, 2] = -(z - z0)
        A[idx.size :, 1] = 1.0
        A[idx.size :, 2] = y - y0
        b = np.concatenate([u[idx, 1], u[idx, 2]])
        sol, *_ = np.linalg.lstsq(A, b, rcond=None)
        v_sec[s], w_sec[s], t_sec[s] = sol
        e_v += sol[0] ** 2 * idx.size
        e_w += sol[1] ** 2 * idx.size
        e_t += sol[2] ** 2 * float(np.sum((y - y0) ** 2 + (z - z0) ** 2))
    return (e_v, e_w, e_t), (v_sec, w_sec, t_sec)


def _beam_name(energies: tuple[float, float, float],
               sections: tuple[np.ndarray, np.ndarray, np.ndarray]) -> str:
    """Name of the dominant beam-like motion (vertical or lateral bending, torsion) with its
    order from the sign changes of the section motion along x.
    """
    e_v, e_w, e_t = energies
    v_sec, w_sec, t_sec = sections
    kind = int(np.argmax([e_w, e_v, e_t]))
    series = (w_sec, v_sec, t_sec)[kind]
    order = _zero_crossings(series)
    if kind == 2:
        return beam_mode_name(TORSION, max(order, 1))
    return beam_mode_name((VERTICAL_BENDING, LATERAL_BENDING)[kind], max(order - 1, 1))


def _local_name(u: np.ndarray, nodes: np.ndarray, node_region: np.ndarray,
                region_names: list[str]) -> str:
    """Name of a cross-section deformation after the region with the largest rms translation:
    side walls (breathing when they move against each other), floor or roof (roof–floor
    breathing when the other moves against it by more than half as much).
    """
    rms = {}
    for r, name in enumerate(region_names):
        sel = node_region == r
        rms[name] = float(np.sqrt(np.mean(np.sum(u[sel] ** 2, axis=1)))) if sel.any() else 0.0
    wall = max(rms.get("wall_left", 0.0), rms.get("wall_right", 0.0))
    floor, roof = rms.get("floor", 0.0), rms.get("roof", 0.0)
    if wall >= max(floor, roof):
        return _walls(u, nodes, node_region, region_names)
    if floor >= roof:
        local = FLOOR_LOCAL
        if roof > 0.5 * floor:
            local = _roof_floor(u, nodes, node_region, region_names) or local
        return local
    local = ROOF_LOCAL
    if floor > 0.5 * roof:
        local = _roof_floor(u, nodes, node_region, region_names) or local
    return local


def _walls(u: np.ndarray, nodes: np.ndarray, node_region: np.ndarray,
           region_names: list[str]) -> str:
    """``breathing (side walls)`` when the walls move laterally against each other (matching
    nodes by x and z), else ``side walls lateral``.
    """
    il, ir = region_names.index("wall_left"), region_names.index("wall_right")
    left, right = nodes[node_region == il], nodes[node_region == ir]
    key_r = {(round(a, 3), round(c, 3)): k for k, (a, _, c) in enumerate(right)}
    uy_l, uy_r = u[node_region == il, 1], u[node_region == ir, 1]
    dot = 0.0
    for k, (a, _, c) in enumerate(left):
        j = key_r.get((round(a, 3), round(c, 3)))
        if j is not None:
            dot += uy_l[k] * uy_r[j]
    return SIDE_WALL_BREATHING if dot < 0 else SIDE_WALLS_LATERAL


def _roof_floor(u, nodes, node_region, region_names) -> str | None:
    """``roof–floor breathing`` when roof and floor move vertically against each other."""
    ir, ifl = region_names.index("roof"), region_names.index("floor")
    roof = node_region == ir
    floor = node_region == ifl
    xs = np.unique(np.round(nodes[floor, 0], 4))
    dot = 0.0
    for x in xs:
        wr = u[roof & (np.abs(nodes[:, 0] - x) < 1e-3), 2].mean() if roof.any() else 0.0
        wf = u[floor & (np.abs(nodes[:, 0] - x) < 1e-3), 2].mean()
        dot += wr * wf
    return ROOF_FLOOR_BREATHING if dot < 0 else None


def classify_plane_frame_mode(phi: np.ndarray, M, nodes: np.ndarray) -> str:
    """Classify a mode of a flat frame (bogie frame) by direction and symmetry.

    The kinetic energy decides whether the mode is out of plane (vertical) or in plane; the
    symmetry of the dominant displacement about the x = 0 and y = 0 planes names it: vertical
    and antisymmetric in both is frame twist.
    """
    n = nodes.shape[0]
    u = phi.reshape(n, 6)[:, :3]
    e = _energy_density(phi, M).reshape(n, 6)[:, :3].sum(axis=0)
    if e.sum() <= 0:
        return "unclassified"
    c = nodes[:, :2] - nodes[:, :2].mean(axis=0)
    key = {(round(a, 3), round(b, 3)): k for k, (a, b) in enumerate(c)}

    def parity(comp: int, flip_x: bool, flip_y: bool) -> float:
        num = den = 0.0
        for k, (a, b) in enumerate(c):
            j = key.get((round(-a if flip_x else a, 3), round(-b if flip_y else b, 3)))
            if j is None:
                continue
            num += u[k, comp] * u[j, comp]
            den += u[k, comp] ** 2
        return num / den if den > 0 else 0.0

    if e[2] >= 0.5 * e.sum():
        px, py = parity(2, True, False), parity(2, False, True)
        if px < 0 and py < 0:
            return "frame twist"
        if px > 0 and py > 0:
            return "vertical bending"
        return "vertical bending (antisymmetric)"
    comp = 0 if e[0] > e[1] else 1
    px, py = parity(comp, True, False), parity(comp, False, True)
    if (comp == 0 and py < 0) or (comp == 1 and px < 0):
        return "in-plane shear (rhombic)"
    return "in-plane bending"

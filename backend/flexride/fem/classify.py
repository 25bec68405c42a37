"""Mode classification by dominant deformation (car bodies and other slender shells).

Each cross-section (nodes that share an x coordinate) is fitted with a rigid in-plane motion:
lateral ``v``, vertical ``w`` and twist ``θx``. The share of the mode's kinetic energy that these
section motions carry tells beam-like modes (vertical / lateral bending, torsion) from modes that
deform the cross-section; the latter are named after the region that carries most of their
energy (roof, floor, side walls: breathing when the two walls move in opposite directions).
"""

from __future__ import annotations

import numpy as np


def _energy_density(phi: np.ndarray, M) -> np.ndarray:
    """Per-DOF kinetic-energy density ``φ ⊙ Mφ`` (non-negative part)."""
    return np.maximum(phi * (M @ phi), 0.0)


def _zero_crossings(values: np.ndarray) -> int:
    v = values[np.abs(values) > 0.05 * np.max(np.abs(values))]
    return int(np.sum(np.sign(v[1:]) != np.sign(v[:-1]))) if v.size > 1 else 0


_ORD = {1: "first", 2: "second", 3: "third", 4: "fourth"}


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
        E.g. ``first vertical bending``, ``torsion``, ``breathing (side walls)``,
        ``floor local``, ``roof–floor breathing``; a beam-like part of a local mode is added
        (``floor local + first vertical bending``).
    """
    n = nodes.shape[0]
    u = phi.reshape(n, 6)[:, :3]
    total = float(np.sum(u**2))
    if total <= 0:
        return "unclassified"
    energies, sections = _section_motions(u, nodes)
    beam = sum(energies) / total
    beam_name = _beam_name(energies, sections)
    if beam >= beam_threshold:
        return beam_name
    needed = {"floor", "roof", "wall_left", "wall_right"}
    if node_region is None or not region_names or not needed <= set(region_names):
        return "cross-section deformation"
    local = _local_name(u, nodes, node_region, region_names)
    return f"{local} + {beam_name}" if beam >= 0.3 else local


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
        return "torsion" if order <= 1 else f"{_ORD.get(order, f'{order}th')} torsion"
    k = max(order - 1, 1)
    return f"{_ORD.get(k, f'{k}th')} {('vertical', 'lateral')[kind]} bending"


def _local_name(u: np.ndarray, nodes: np.ndarray, node_region: np.ndarray,
                region_names: list[str]) -> str:
    """Name of a cross-section deformation after the region with the largest rms translation:
    side walls (breathing when they move against each other), floor or roof (roof–floor
    breathing, rhombic deformation when the roof moves mostly laterally).
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
        local = "floor local"
        if roof > 0.5 * floor:
            local = _roof_floor(u, nodes, node_region, region_names) or local
        return local
    local = "roof local"
    ir = region_names.index("roof")
    sel = node_region == ir
    if np.sum(u[sel, 1] ** 2) > np.sum(u[sel, 2] ** 2):
        local = "rhombic (lateral shear) deformation"
    elif floor > 0.5 * roof:
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
    return "breathing (side walls)" if dot < 0 else "side walls lateral"


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
    return "roof–floor breathing" if dot < 0 else None


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

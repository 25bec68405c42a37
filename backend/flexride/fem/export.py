"""Export of a mesh and its mode shapes in a form a browser can draw (JSON-able dict)."""

from __future__ import annotations

import numpy as np


def export_mesh(
    nodes: np.ndarray,
    quads: np.ndarray,
    beams: np.ndarray,
    frequencies: np.ndarray | None = None,
    shapes: np.ndarray | None = None,
    classification: list[str] | None = None,
    max_modes: int = 12,
    named_nodes: dict[str, int] | None = None,
    node_region: np.ndarray | None = None,
    region_names: list[str] | None = None,
    digits: int = 4,
) -> dict:
    """Nodes, elements and mode shapes as plain lists.

    Parameters
    ----------
    nodes : numpy.ndarray
        (n, 3) coordinates (m).
    quads, beams : numpy.ndarray
        (nq, 4) and (nb, 2) node indices.
    frequencies : numpy.ndarray, optional
        Elastic frequencies (Hz).
    shapes : numpy.ndarray, optional
        (n, 6, n_modes) elastic shapes; the translations are exported, each mode scaled so its
        largest nodal translation is 1 (``scale`` gives the factor back to unit modal mass).
    classification : list of str, optional
        Name of each mode.
    max_modes : int
        Number of modes exported.
    named_nodes, node_region, region_names : optional
        Extra annotations.
    digits : int
        Decimals kept.

    Returns
    -------
    dict
        ``{"units", "nodes", "quads", "beams", "named_nodes", "regions", "modes"}``, where each
        mode is ``{"index", "frequency_hz", "classification", "scale_m", "displacements"}``.
    """
    out: dict = {
        "units": {"length": "m", "frequency": "Hz"},
        "nodes": np.round(np.asarray(nodes, float), digits).tolist(),
        "quads": np.asarray(quads, dtype=int).tolist(),
        "beams": np.asarray(beams, dtype=int).tolist(),
        "named_nodes": dict(named_nodes or {}),
        "modes": [],
    }
    if node_region is not None and region_names:
        out["regions"] = {
            "names": list(region_names),
            "node_region": np.asarray(node_region).tolist(),
        }
    if frequencies is not None and shapes is not None:
        for k in range(min(max_modes, len(frequencies))):
            u = shapes[:, :3, k]
            s = float(np.max(np.abs(u))) or 1.0
            out["modes"].append(
                {
                    "index": k + 1,
                    "frequency_hz": float(frequencies[k]),
                    "classification": classification[k] if classification else "",
                    "scale_m": s,
                    "displacements": np.round(u / s, digits).tolist(),
                }
            )
    return out

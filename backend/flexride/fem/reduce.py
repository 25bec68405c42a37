"""Reduction of an FE model by a named method, and the report on it.

:func:`reduce_model` applies modal truncation, Guyan or Craig–Bampton reduction (the algorithms
are in :mod:`flexride.fem.reduction`), turns the result into the solver's body
(:func:`~flexride.fem.modal_body.reduced_to_modal_body`) and compares it with the full model's
modes (:class:`~flexride.fem.report.ReductionReport`: frequencies, MAC, mass properties, mode
names).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
import scipy.sparse as sp

from flexride.errors import FEModelError
from flexride.fem.classify import classify_mode, classify_plane_frame_mode
from flexride.fem.massmatch import InertiaTarget
from flexride.fem.modal_body import BodyModes, reduced_to_modal_body
from flexride.fem.model import FEModel
from flexride.fem.reduction import (
    craig_bampton,
    guyan,
    guyan_error_indicator,
    node_dofs,
    rigid_basis_for,
)
from flexride.fem.report import ReductionReport, mac_matrix, mass_summary, match_modes
from flexride.fem.rigid import rigid_body_vectors

Method = Literal["guyan", "craig-bampton", "modal"]
METHODS: tuple[Method, ...] = ("guyan", "craig-bampton", "modal")

#: Fixed-interface modes of a Craig–Bampton reduction are kept up to this multiple of the
#: cut-off, so that the modes below the cut-off converge (rule of thumb 1.5–2).
CB_FIXED_INTERFACE_FACTOR = 1.5
#: Number of modes classified in reports (classification is per mode and not free).
N_CLASSIFIED = 30


def _classify(model: FEModel, shapes: np.ndarray, M, kind: str) -> list[str]:
    """Names of the first :data:`N_CLASSIFIED` modes of ``shapes`` ((n, 6, n_modes) nodal
    shapes) by the frame or car-body classifier; the others are left unnamed (``""``).
    """
    out = []
    for k in range(min(shapes.shape[2], N_CLASSIFIED)):
        phi = shapes[:, :, k].ravel()
        if kind == "frame" or "side_beam" in model.region_names:
            out.append(classify_plane_frame_mode(phi, M, model.nodes))
        elif "wall_left" in model.region_names:
            out.append(classify_mode(phi, M, model.nodes, model.node_region, model.region_names))
        else:
            out.append(classify_mode(phi, M, model.nodes))
    return out + [""] * (shapes.shape[2] - len(out))


def _reduced_modes(modes: BodyModes) -> np.ndarray:
    """The modes in reduced coordinates (always set by :func:`reduced_to_modal_body`)."""
    if modes.reduced_modes is None:
        raise FEModelError(f"body {modes.body.name!r} has no modes in reduced coordinates")
    return modes.reduced_modes


def dof_layout(model: FEModel):
    """(P, R, dof_nodes) of a model: the map from its matrix DOFs to six DOFs per node (None
    when the matrices are already nodal), its rigid-body vectors in matrix DOFs, and the node
    of each matrix DOF (None for nodal models).
    """
    nodes = model.nodes
    Rn = rigid_body_vectors(nodes)
    if "dof_nodes" not in model.info:
        return None, Rn, None
    dn = np.asarray(model.info["dof_nodes"], dtype=np.int64)
    dc = np.asarray(model.info["dof_components"], dtype=np.int64)
    glob = 6 * dn + dc
    P = sp.csc_matrix(
        (np.ones(glob.size), (glob, np.arange(glob.size))), shape=(6 * nodes.shape[0], glob.size)
    )
    return P, Rn[glob], dn


def reduce_model(
    model: FEModel,
    method: Method,
    cutoff_hz: float,
    master_names: list[str],
    interface_names: list[str],
    target: InertiaTarget | None = None,
    kind: str = "carbody",
) -> tuple[BodyModes, ReductionReport]:
    """Reduce an FE model and report on the reduction.

    Parameters
    ----------
    model : FEModel
        Assembled (or assemblable) model with named nodes.
    method : {"guyan", "craig-bampton", "modal"}
        Reduction.
    cutoff_hz : float
        Cut-off frequency (Hz): elastic modes kept up to it (and fixed-interface modes for
        Craig–Bampton).
    master_names, interface_names : list of str
        Named nodes used as Guyan masters / Craig–Bampton interface.
    target : InertiaTarget, optional
        For the mass block of the report.
    kind : str
        ``frame`` selects the frame mode classifier.
    """
    if method not in METHODS:
        raise FEModelError(f"unknown reduction method {method!r}: use one of {', '.join(METHODS)}")
    if not (cutoff_hz > 0 and np.isfinite(cutoff_hz)):
        raise FEModelError(f"cut-off frequency must be positive, got {cutoff_hz}")
    K, M = model.assemble()
    P, R, dof_nodes = dof_layout(model)
    full_modes = reduced_to_modal_body(
        model.name, model.nodes, M, K, recovery=P, rigid_basis=R, cutoff_hz=cutoff_hz, damping=0.0
    )
    if method == "modal":
        reduced = _modal_truncation(model, full_modes)
    else:
        names = master_names if method == "guyan" else interface_names
        reduced = _reduce_on_nodes(model, method, cutoff_hz, names, K, M, P, R, dof_nodes)
    return reduced.modes, _report(model, method, cutoff_hz, reduced, full_modes, K, M, P, target,
                                  kind)


@dataclass
class _Reduced:
    """A reduced model as the report needs it.

    Attributes
    ----------
    modes : BodyModes
        The reduced body and its nodal shapes.
    n_reduced : int
        Number of reduced coordinates.
    master : dict of str to int
        Named master / interface nodes (empty for modal truncation).
    A : numpy.ndarray
        The retained elastic modes in the model's matrix DOFs (for the MAC).
    info : dict
        Reduction details (sizes, fixed-interface frequencies, Guyan error...).
    guyan_error : numpy.ndarray or None
        Guyan error indicator per retained mode (Guyan only).
    """

    modes: BodyModes
    n_reduced: int
    master: dict[str, int]
    A: np.ndarray
    info: dict[str, Any]
    guyan_error: np.ndarray | None = None


def _modal_truncation(model: FEModel, full_modes: BodyModes) -> _Reduced:
    """Modal truncation: the full model's modes up to the cut-off, with the model's named nodes
    (six rigid plus the elastic coordinates).
    """
    modes = full_modes
    modes.node_names = dict(model.named_nodes)
    return _Reduced(modes, 6 + modes.body.n_elastic, {}, _reduced_modes(modes), {})


def _reduce_on_nodes(model: FEModel, method: Method, cutoff_hz: float, names: list[str], K, M,
                     P, R: np.ndarray, dof_nodes: np.ndarray | None) -> _Reduced:
    """Guyan or Craig–Bampton reduction on the DOFs of the named nodes ``names``.

    Craig–Bampton keeps fixed-interface modes up to :data:`CB_FIXED_INTERFACE_FACTOR` times
    the cut-off (Hz); Guyan adds its error indicator per retained mode.

    Raises
    ------
    FEModelError
        If the model has no node of one of the names.
    """
    markers = dict(model.named_nodes)
    missing = [n for n in names if n not in markers]
    if missing:
        raise FEModelError(f"model {model.name!r} has no nodes named {missing}")
    master = {n: markers[n] for n in names}
    if dof_nodes is None:
        dofs = node_dofs(list(master.values()))
    else:
        dofs = np.flatnonzero(np.isin(dof_nodes, list(master.values())))
    if method == "guyan":
        red = guyan(K, M, dofs)
    else:
        red = craig_bampton(K, M, dofs, cutoff_hz=CB_FIXED_INTERFACE_FACTOR * cutoff_hz)
    red.rigid_basis = rigid_basis_for(red, R)
    modes = reduced_to_modal_body(
        model.name,
        model.nodes,
        red.M,
        red.K,
        recovery=red.recovery if P is None else P @ red.recovery,
        rigid_basis=red.rigid_basis,
        cutoff_hz=cutoff_hz,
        markers=markers,
        damping=0.0,
    )
    info = dict(red.info)
    q = _reduced_modes(modes)
    g_err = None
    if method == "guyan":
        g_err = guyan_error_indicator(red, q, modes.body.elastic_frequencies)
        info["guyan_error_max"] = float(np.max(g_err)) if g_err.size else 0.0
    return _Reduced(modes, red.n_reduced, master, red.recovery @ q, info, g_err)


def _report(model: FEModel, method: Method, cutoff_hz: float, reduced: _Reduced,
            full_modes: BodyModes, K, M, P, target: InertiaTarget | None,
            kind: str) -> ReductionReport:
    """The report of a reduction: sizes, reduced against full frequencies (Hz), MAC and its
    mode matching, mode names (nodal models only), mass properties against ``target`` and the
    reduction's details.
    """
    modes = reduced.modes
    ne = modes.body.n_elastic
    B = _reduced_modes(full_modes)
    mac = mac_matrix(reduced.A, B, M) if ne and B.shape[1] else np.zeros((ne, B.shape[1]))
    cls = _classify(model, modes.shapes, M, kind) if P is None else [""] * ne
    g_err = reduced.guyan_error
    return ReductionReport(
        body=model.name,
        method=method,
        cutoff_hz=float(cutoff_hz),
        n_full_dof=int(K.shape[0]),
        n_reduced_dof=int(reduced.n_reduced),
        master_nodes=reduced.master,
        reduced_frequencies=[float(v) for v in modes.body.elastic_frequencies],
        full_frequencies=[float(v) for v in full_modes.body.elastic_frequencies],
        classification=cls,
        match=match_modes(mac),
        mac=np.round(mac, 4).tolist(),
        mass=mass_summary(modes.mass_properties, target),
        guyan_error=None if g_err is None else [float(v) for v in g_err],
        info={**reduced.info, "rigid_frequencies_hz": [float(v) for v in modes.rigid_frequencies]},
    )

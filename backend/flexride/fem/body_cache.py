"""Reduced bodies in the FE cache (:mod:`flexride.fem.cache`): what identifies one (its inputs),
what an entry holds, and loading an entry or building and storing it.

A vehicle's body is identified by its model parameters (with the vehicle's suspension geometry),
the vehicle's inertia target, the reduction method, the cut-off, the element size, the extra
named points and the attachment and output nodes (:func:`vehicle_body_inputs`); any other model
by a hash of its matrices and nodes (:func:`model_inputs`). Damping, name and reference position
are not part of an entry: they are applied when the body is made from it.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from typing import Any

import numpy as np

from flexride.fem import cache
from flexride.fem.modal_body import BodyModes
from flexride.fem.model import FEModel
from flexride.fem.report import ReductionReport
from flexride.fem.vehicle_models import (
    ATTACHMENTS,
    OUTPUTS,
    carbody_params_for,
    carbody_target,
    frame_params_for,
    frame_target,
)

#: A cache entry: arrays (nodes in m, shapes, frequencies in Hz, elements, MAC) and metadata.
Entry = tuple[dict[str, np.ndarray], dict[str, Any]]


def vehicle_body_inputs(kind, vehicle, method, cutoff_hz, element_size, extra_points,
                        params) -> dict:
    """What determines a reduced car body or frame of a vehicle.

    Parameters
    ----------
    kind : {"carbody", "frame"}
        Which model.
    vehicle : flexride.scenario.vehicle.Vehicle
        Vehicle parameters (suspension geometry, inertia target).
    method : str
        Reduction method.
    cutoff_hz : float
        Cut-off frequency (Hz).
    element_size : float
        Element size (m).
    extra_points : dict of str to (x, y, z), optional
        Extra named points (m).
    params : CarBodyParams or FrameParams, optional
        Model parameters instead of the calibrated defaults.
    """
    if kind == "carbody":
        p = carbody_params_for(vehicle, params).to_dict()
        t = carbody_target(vehicle)
    else:
        p = frame_params_for(vehicle, params).to_dict()
        t = frame_target(vehicle)
    return {
        "kind": kind,
        "method": method,
        "cutoff_hz": float(cutoff_hz),
        "element_size": float(element_size),
        "params": p,
        "target": {"mass": t.mass, "cg": t.cg, "inertia": t.inertia},
        "extra_points": {k: list(map(float, v)) for k, v in sorted((extra_points or {}).items())},
        "attachments": ATTACHMENTS[kind],
        "outputs": OUTPUTS[kind],
    }


def _model_hash(model: FEModel) -> dict:
    """SHA-256 of a model's matrices (sorted CSC arrays), nodes and DOF map, and its named
    nodes.
    """
    h = hashlib.sha256()
    K, M = model.assemble()
    for A in (K, M):
        A = A.tocsc()
        A.sort_indices()
        for arr in (A.indptr, A.indices, A.data):
            h.update(np.ascontiguousarray(arr).tobytes())
    h.update(np.ascontiguousarray(model.nodes).tobytes())
    for key in ("dof_nodes", "dof_components"):
        if key in model.info:
            h.update(np.ascontiguousarray(model.info[key]).tobytes())
    return {"matrices": h.hexdigest(), "named_nodes": model.named_nodes}


def model_inputs(model: FEModel, method: str, cutoff_hz: float, attachments: list[str],
                 outputs: list[str]) -> dict:
    """What determines a reduced body of any FE model: its content hash, the reduction method,
    the cut-off (Hz) and the attachment and output nodes.
    """
    return {
        "kind": "model",
        "model": _model_hash(model),
        "method": method,
        "cutoff_hz": float(cutoff_hz),
        "attachments": attachments,
        "outputs": outputs,
    }


def cache_entry(inputs: dict, model: FEModel, modes: BodyModes, report: ReductionReport, *,
                regions: bool, **meta: Any) -> Entry:
    """The cache entry of a reduced body.

    Parameters
    ----------
    inputs : dict
        What determines the body (stored with it).
    model : FEModel
        The model that was reduced (nodes, elements, named nodes).
    modes, report :
        The result of :func:`~flexride.fem.reduce.reduce_model`.
    regions : bool
        Keep the model's node regions, region names and floor grid (the vehicle's own models).
    **meta
        More metadata.
    """
    region = model.node_region if regions and model.node_region is not None else None
    arrays = {
        "nodes": model.nodes,
        "shapes": modes.shapes,
        "frequencies": modes.body.elastic_frequencies,
        "rigid_frequencies": modes.rigid_frequencies,
        "quads": model.mesh.quads,
        "beams": model.mesh.beams,
        "node_region": region if region is not None else np.zeros(0),
        "mac": np.asarray(report.mac, dtype=float),
    }
    info = {
        "inputs": inputs,
        "mass_properties": modes.mass_properties.to_dict(),
        "node_names": model.named_nodes,
        "region_names": model.region_names if regions else [],
        "floor_grid": model.info.get("floor_grid", []) if regions else [],
        "report": {**report.to_dict(), "mac": None},
        **meta,
    }
    return arrays, info


def load_or_build(inputs: dict, build: Callable[[], Entry], use_cache: bool) -> tuple[
        dict[str, np.ndarray], dict[str, Any], bool]:
    """The cache entry of ``inputs``: loaded when present (and ``use_cache``), otherwise built
    by ``build()`` and stored (when ``use_cache``).

    Returns
    -------
    arrays, meta : dict
        The entry.
    from_cache : bool
        Whether it was loaded.
    """
    key = cache.content_hash(inputs)
    hit = cache.load(key) if use_cache else None
    if hit is not None:
        arrays, meta = hit
        return arrays, meta, True
    arrays, meta = build()
    if use_cache:
        cache.store(key, arrays, meta)
    return arrays, meta, False

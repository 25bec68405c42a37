"""Flexible car body / bogie frame for the solver: build, reduce, cache, convert to ModalBody.

:func:`build_flexible_body` is the entry point used by the vehicle assembly. The expensive part
(mesh, assembly, eigen solution, reduction, report) depends only on the model parameters, the
vehicle inertia targets, the method, the cut-off and the element size; it is cached on disk by a
content hash of those inputs (:mod:`flexride.fem.cache`). Damping, name and reference position
are applied afterwards.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import scipy.sparse as sp

from flexride.bodies import ModalBody
from flexride.errors import FEModelError
from flexride.fem import cache
from flexride.fem.carbody import CarBodyParams, build_carbody
from flexride.fem.classify import classify_mode, classify_plane_frame_mode
from flexride.fem.damping import DampingSpec, modal_damping_ratios
from flexride.fem.defaults import default_carbody_params, default_frame_params
from flexride.fem.export import export_mesh
from flexride.fem.frame import FrameParams, build_frame
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
from flexride.fem.rigid import MassProperties, rigid_body_vectors
from flexride.vehicle.topology import PAPER_POINT_NAMES

Kind = Literal["carbody", "frame"]
Method = Literal["guyan", "craig-bampton", "modal"]
METHODS: tuple[Method, ...] = ("guyan", "craig-bampton", "modal")

#: Suspension attachment nodes (Guyan masters, Craig–Bampton interface) of each model.
ATTACHMENTS = {
    "carbody": ("as1L", "as1R", "as2L", "as2R", "bogie1", "bogie2"),
    "frame": ("ab1L", "ab1R", "ab2L", "ab2R", "asL", "asR", "centre"),
}
#: Output points (extra Guyan masters) of each model: the paper's points on the car body.
OUTPUTS = {
    "carbody": PAPER_POINT_NAMES,
    "frame": ("centre",),
}
#: Fixed-interface modes of a Craig–Bampton reduction are kept up to this multiple of the
#: cut-off, so that the modes below the cut-off converge (rule of thumb 1.5–2).
CB_FIXED_INTERFACE_FACTOR = 1.5
#: Number of modes classified in reports (classification is per mode and not free).
N_CLASSIFIED = 30


@dataclass
class FlexibleBody:
    """A reduced flexible body ready for the solver.

    Attributes
    ----------
    body : ModalBody
        Rigid inertia and CG height from the FE model, retained elastic modes, modal damping,
        and ``elastic_shapes`` at the named attachment and output nodes.
    report : ReductionReport
        Reduced vs full frequencies, MAC, mass properties.
    modes : BodyModes
        Nodal elastic shapes (for markers anywhere on the body).
    quads, beams : numpy.ndarray
        Element connectivity (for drawing).
    floor_grid : list of str
        Names of the floor-grid nodes (car body).
    build_seconds : float
        Time to build (or load) the body.
    from_cache : bool
        Whether the body was loaded from the cache.
    """

    body: ModalBody
    report: ReductionReport
    modes: BodyModes
    quads: np.ndarray
    beams: np.ndarray
    node_region: np.ndarray | None = None
    region_names: list[str] = field(default_factory=list)
    floor_grid: list[str] = field(default_factory=list)
    build_seconds: float = 0.0
    from_cache: bool = False

    def shape_at(self, position_xyz: tuple[float, float, float] | np.ndarray) -> np.ndarray:
        """(6, n_elastic) elastic shapes at the node nearest to ``position_xyz`` (m, relative
        to the body's CG, body axes): translations (m) and rotations (rad) per unit
        mass-normalised modal coordinate."""
        return self.modes.shape_at(position_xyz)

    def node_position(self, name: str) -> np.ndarray:
        """Position of a named node relative to the CG (m)."""
        return self.modes.node_position(self.modes.node_names[name])

    def floor_grid_nodes(self) -> tuple[list[str], np.ndarray]:
        """Names and positions (relative to the CG, m) of the regular floor grid (car body):
        x every 1 m from −9 to +9 m, y at −1.0, −0.5, 0, 0.5, 1.0 m."""
        names = list(self.floor_grid)
        pos = np.array([self.node_position(n) for n in names]).reshape(-1, 3)
        return names, pos

    @property
    def mesh(self) -> dict:
        """Browser export (nodes, elements, first 12 mode shapes), see :meth:`export`."""
        return self.export()

    def export(self, max_modes: int = 12) -> dict:
        """Nodes, elements and mode shapes as a JSON-able dict (:func:`export_mesh`)."""
        return export_mesh(
            self.modes.nodes,
            self.quads,
            self.beams,
            self.body.elastic_frequencies,
            self.modes.shapes,
            self.report.classification,
            max_modes=max_modes,
            named_nodes=self.modes.node_names,
            node_region=self.node_region,
            region_names=self.region_names,
        )


def _inertia_target(body) -> InertiaTarget:
    """Mass, CG (on the centre line, at the body's CG height) and Ixx/Iyy/Izz of a body's
    parameters (kg, m, kg·m²)."""
    return InertiaTarget(body.mass, np.array([0.0, 0.0, body.cg_height]),
                         np.array([body.ixx, body.iyy, body.izz]))


def carbody_target(vehicle) -> InertiaTarget:
    """Inertia target of the car body from the vehicle parameters (CG on the centre line)."""
    return _inertia_target(vehicle.carbody)


def frame_target(vehicle) -> InertiaTarget:
    """Inertia target of one bogie frame from the vehicle parameters."""
    return _inertia_target(vehicle.frame)


def carbody_params_for(vehicle, base: CarBodyParams | None = None) -> CarBodyParams:
    """Car-body parameters with the vehicle's suspension geometry."""
    g = vehicle.geometry
    return (base or default_carbody_params()).with_values(
        bogie_spacing=g.bogie_centre_spacing,
        air_spring_y=g.secondary_lateral_half_spacing,
        underframe_height=g.secondary_height,
    )


def frame_params_for(vehicle, base: FrameParams | None = None) -> FrameParams:
    """Frame parameters with the vehicle's suspension geometry."""
    g = vehicle.geometry
    return (base or default_frame_params()).with_values(
        wheelbase=g.wheelbase,
        primary_y=g.primary_lateral_half_spacing,
        primary_height=g.primary_height,
        air_spring_y=g.secondary_lateral_half_spacing,
        air_spring_height=g.secondary_height,
        beam_height=vehicle.frame.cg_height,
    )


def build_fe_model(
    kind: Kind, vehicle, element_size: float = 0.2, params=None
) -> tuple[FEModel, InertiaTarget]:
    """The (mass-matched) FE model of ``kind`` for ``vehicle`` and its inertia target.

    The frame's element size is ``min(element_size / 2, 0.1)`` m (beam elements).
    """
    if element_size <= 0 or not np.isfinite(element_size):
        raise FEModelError(f"element size must be positive, got {element_size}")
    if kind == "carbody":
        if element_size > 1.0 or element_size < 0.05:
            raise FEModelError(f"car-body element size must be 0.05–1.0 m, got {element_size}")
        target = carbody_target(vehicle)
        return build_carbody(carbody_params_for(vehicle, params), target, element_size), target
    if kind == "frame":
        target = frame_target(vehicle)
        frame = build_frame(frame_params_for(vehicle, params), target, min(element_size / 2.0, 0.1))
        return frame, target
    raise FEModelError(f"unknown body kind {kind!r}: use 'carbody' or 'frame'")


def _classify(model: FEModel, shapes: np.ndarray, M, kind: str) -> list[str]:
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
    nodes = model.nodes
    markers = dict(model.named_nodes)
    P, R, dof_nodes = dof_layout(model)
    full_modes = reduced_to_modal_body(
        model.name, nodes, M, K, recovery=P, rigid_basis=R, cutoff_hz=cutoff_hz, damping=0.0
    )
    info: dict = {}
    g_err = None
    if method == "modal":
        modes = full_modes
        modes.node_names = markers
        n_red = 6 + modes.body.n_elastic
        master: dict[str, int] = {}
        A = _reduced_modes(modes)
    else:
        names = master_names if method == "guyan" else interface_names
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
            nodes,
            red.M,
            red.K,
            recovery=red.recovery if P is None else P @ red.recovery,
            rigid_basis=red.rigid_basis,
            cutoff_hz=cutoff_hz,
            markers=markers,
            damping=0.0,
        )
        n_red = red.n_reduced
        info = dict(red.info)
        q = _reduced_modes(modes)
        A = red.recovery @ q
        if method == "guyan":
            g_err = guyan_error_indicator(red, q, modes.body.elastic_frequencies)
            info["guyan_error_max"] = float(np.max(g_err)) if g_err.size else 0.0
    ne = modes.body.n_elastic
    B = _reduced_modes(full_modes)
    mac = mac_matrix(A, B, M) if ne and B.shape[1] else np.zeros((ne, B.shape[1]))
    cls = _classify(model, modes.shapes, M, kind) if P is None else [""] * ne
    report = ReductionReport(
        body=model.name,
        method=method,
        cutoff_hz=float(cutoff_hz),
        n_full_dof=int(K.shape[0]),
        n_reduced_dof=int(n_red),
        master_nodes=master,
        reduced_frequencies=[float(v) for v in modes.body.elastic_frequencies],
        full_frequencies=[float(v) for v in full_modes.body.elastic_frequencies],
        classification=cls,
        match=match_modes(mac),
        mac=np.round(mac, 4).tolist(),
        mass=mass_summary(modes.mass_properties, target),
        guyan_error=None if g_err is None else [float(v) for v in g_err],
        info={**info, "rigid_frequencies_hz": [float(v) for v in modes.rigid_frequencies]},
    )
    return modes, report


def dof_layout(model: FEModel):
    """(P, R, dof_nodes) of a model: the map from its matrix DOFs to six DOFs per node (None
    when the matrices are already nodal), its rigid-body vectors in matrix DOFs, and the node
    of each matrix DOF (None for nodal models)."""
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


def _cache_inputs(kind, vehicle, method, cutoff_hz, element_size, extra_points, params) -> dict:
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


def build_flexible_body(
    kind: Kind,
    vehicle,
    method: Method = "modal",
    cutoff_hz: float = 100.0,
    damping_ratio: DampingSpec = 0.02,
    element_size: float = 0.2,
    extra_points: dict[str, tuple[float, float, float]] | None = None,
    name: str = "carbody",
    x_ref: float = 0.0,
    *,
    params: CarBodyParams | FrameParams | None = None,
    use_cache: bool = True,
) -> FlexibleBody:
    """Build (or load from the cache) a reduced flexible car body or bogie frame.

    Parameters
    ----------
    kind : {"carbody", "frame"}
        Which default FE model.
    vehicle : flexride.model.vehicle.Vehicle
        Vehicle parameters: inertia targets (mass, CG height, Ixx/Iyy/Izz) and suspension
        geometry (bogie spacing, spring positions and heights).
    method : {"guyan", "craig-bampton", "modal"}
        Reduction method.
    cutoff_hz : float
        Cut-off frequency (Hz) of the retained elastic modes.
    damping_ratio : float, sequence of float or RayleighDamping
        Modal damping ratio of every elastic mode, one per mode, or Rayleigh damping.
    element_size : float
        Car-body shell element size (m); the frame uses ``min(element_size/2, 0.1)``.
    extra_points : dict of str to (x, y, z), optional
        More named points in model coordinates (m: x from the body centre, y left, z above top
        of rail): Guyan masters and entries of ``body.elastic_shapes``.
    name : str
        Body name for the ModalBody (``carbody``, ``frame1``...).
    x_ref : float
        Longitudinal position of the body's reference frame (m).
    params : CarBodyParams or FrameParams, optional
        Model parameters instead of the calibrated defaults.
    use_cache : bool
        Read and write the on-disk cache.

    Returns
    -------
    FlexibleBody
    """
    t0 = time.perf_counter()
    if kind not in ("carbody", "frame"):
        raise FEModelError(f"unknown body kind {kind!r}: use 'carbody' or 'frame'")
    if method not in METHODS:
        raise FEModelError(f"unknown reduction method {method!r}: use one of {', '.join(METHODS)}")
    inputs = _cache_inputs(kind, vehicle, method, cutoff_hz, element_size, extra_points, params)
    key = cache.content_hash(inputs)
    hit = cache.load(key) if use_cache else None
    if hit is None:
        model, target = build_fe_model(kind, vehicle, element_size, params)
        for pname, xyz in (extra_points or {}).items():
            model.named_nodes[pname] = model.nearest_node(np.asarray(xyz, dtype=float))
        masters = list(ATTACHMENTS[kind]) + list(OUTPUTS[kind]) + list(extra_points or {})
        masters = list(dict.fromkeys(masters))
        modes, report = reduce_model(
            model, method, cutoff_hz, masters, list(ATTACHMENTS[kind]), target, kind
        )
        arrays = {
            "nodes": model.nodes,
            "shapes": modes.shapes,
            "frequencies": modes.body.elastic_frequencies,
            "rigid_frequencies": modes.rigid_frequencies,
            "quads": model.mesh.quads,
            "beams": model.mesh.beams,
            "node_region": model.node_region if model.node_region is not None else np.zeros(0),
            "mac": np.asarray(report.mac, dtype=float),
        }
        meta = {
            "inputs": inputs,
            "mass_properties": modes.mass_properties.to_dict(),
            "node_names": model.named_nodes,
            "region_names": model.region_names,
            "floor_grid": model.info.get("floor_grid", []),
            "report": {**report.to_dict(), "mac": None},
            "model_info": {k: v for k, v in model.info.items() if k != "floor_grid"},
        }
        if use_cache:
            cache.store(key, arrays, meta)
        from_cache = False
    else:
        arrays, meta = hit
        from_cache = True
    return _assemble_body(
        arrays, meta, name, x_ref, damping_ratio, kind, extra_points, t0, from_cache
    )


def _assemble_body(arrays, meta, name, x_ref, damping, kind, extra_points, t0, from_cache):
    props = MassProperties.from_dict(meta["mass_properties"])
    f = np.asarray(arrays["frequencies"], dtype=float)
    shapes = arrays["shapes"]
    names = {k: int(v) for k, v in meta["node_names"].items()}
    fixed = (list(ATTACHMENTS[kind]) + list(OUTPUTS[kind])) if kind in ATTACHMENTS else []
    marker_names = fixed + list(extra_points or {})
    body = ModalBody(
        name=name,
        mass=props.mass,
        inertia=np.diag(props.inertia).copy(),
        x_ref=float(x_ref),
        cg_height=float(props.cg[2]),
        elastic_frequencies=f.copy(),
        elastic_damping=modal_damping_ratios(damping, f),
        elastic_shapes={k: np.array(shapes[names[k]]) for k in dict.fromkeys(marker_names)},
    )
    modes = BodyModes(
        body=body,
        nodes=arrays["nodes"],
        mass_properties=props,
        shapes=shapes,
        rigid_frequencies=arrays["rigid_frequencies"],
        node_names=names,
    )
    region = arrays.get("node_region")
    return FlexibleBody(
        body=body,
        report=ReductionReport.from_dict({**meta["report"], "mac": arrays["mac"]}),
        modes=modes,
        quads=arrays["quads"],
        beams=arrays["beams"],
        node_region=region if region is not None and region.size else None,
        region_names=list(meta.get("region_names", [])),
        floor_grid=list(meta.get("floor_grid", [])),
        build_seconds=time.perf_counter() - t0,
        from_cache=from_cache,
    )


def _model_hash(model: FEModel) -> dict:
    import hashlib

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


def flexible_body_from_model(
    model: FEModel,
    method: Method = "modal",
    cutoff_hz: float = 100.0,
    damping_ratio: DampingSpec = 0.02,
    attachments: list[str] | None = None,
    outputs: list[str] | None = None,
    name: str | None = None,
    x_ref: float = 0.0,
    target: InertiaTarget | None = None,
    use_cache: bool = True,
) -> FlexibleBody:
    """Reduce any FE model (e.g. an imported one) to a :class:`FlexibleBody`.

    Parameters
    ----------
    model : FEModel
        Model with ``K``, ``M`` (or assemblable) and named nodes; coordinates in body axes
        (x forward, y left, z up from top of rail, m).
    method, cutoff_hz, damping_ratio, name, x_ref :
        As for :func:`build_flexible_body`.
    attachments : list of str, optional
        Named nodes where suspension elements attach (Guyan masters, Craig–Bampton interface);
        default ``model.info["attachments"]``.
    outputs : list of str, optional
        Named output nodes (further Guyan masters); default ``model.info["outputs"]``.
    target : InertiaTarget, optional
        Reference mass properties for the report.
    use_cache : bool
        Read and write the on-disk cache (keyed by a hash of the matrices).

    Returns
    -------
    FlexibleBody
    """
    t0 = time.perf_counter()
    att = list(attachments if attachments is not None else model.info.get("attachments", []))
    outs = list(outputs if outputs is not None else model.info.get("outputs", []))
    if method in ("guyan", "craig-bampton") and not att:
        raise FEModelError(f"{method} reduction needs attachment nodes (named nodes)")
    inputs = {
        "kind": "model",
        "model": _model_hash(model),
        "method": method,
        "cutoff_hz": float(cutoff_hz),
        "attachments": att,
        "outputs": outs,
    }
    key = cache.content_hash(inputs)
    hit = cache.load(key) if use_cache else None
    if hit is None:
        masters = list(dict.fromkeys(att + outs))
        modes, report = reduce_model(model, method, cutoff_hz, masters, att, target, "model")
        arrays = {
            "nodes": model.nodes,
            "shapes": modes.shapes,
            "frequencies": modes.body.elastic_frequencies,
            "rigid_frequencies": modes.rigid_frequencies,
            "quads": model.mesh.quads,
            "beams": model.mesh.beams,
            "node_region": np.zeros(0),
            "mac": np.asarray(report.mac, dtype=float),
        }
        meta = {
            "inputs": inputs,
            "mass_properties": modes.mass_properties.to_dict(),
            "node_names": model.named_nodes,
            "region_names": [],
            "floor_grid": [],
            "report": {**report.to_dict(), "mac": None},
            "markers": masters,
        }
        if use_cache:
            cache.store(key, arrays, meta)
        from_cache = False
    else:
        arrays, meta = hit
        from_cache = True
    markers = {k: None for k in list(dict.fromkeys(att + outs))}
    return _assemble_body(
        arrays, meta, name or model.name, x_ref, damping_ratio, None, markers, t0, from_cache
    )

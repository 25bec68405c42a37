"""A reduced flexible body ready for the solver (:class:`FlexibleBody`), made from a cache entry
(:mod:`flexride.fem.body_cache`) with its damping, name and reference position.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.bodies import ModalBody
from flexride.fem.damping import DampingSpec, modal_damping_ratios
from flexride.fem.export import export_mesh
from flexride.fem.modal_body import BodyModes
from flexride.fem.report import ReductionReport
from flexride.fem.rigid import MassProperties
from flexride.fem.vehicle_models import ATTACHMENTS, OUTPUTS


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
    calibration : dict or None
        For a car body calibrated at build time (``bodies.carbody.calibration``): the
        targets, the calibrated values and the pairing with each target's frequency error
        (:meth:`flexride.fem.calibrated_body.CalibratedCarBody.summary`); None otherwise.
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
    calibration: dict[str, Any] | None = None

    def shape_at(self, position_xyz: tuple[float, float, float] | np.ndarray) -> np.ndarray:
        """(6, n_elastic) elastic shapes at the node nearest to ``position_xyz`` (m, relative
        to the body's CG, body axes): translations (m) and rotations (rad) per unit
        mass-normalised modal coordinate.
        """
        return self.modes.shape_at(position_xyz)

    def node_position(self, name: str) -> np.ndarray:
        """Position of a named node relative to the CG (m)."""
        return self.modes.node_position(self.modes.node_names[name])

    def floor_grid_nodes(self) -> tuple[list[str], np.ndarray]:
        """Names and positions (relative to the CG, m) of the regular floor grid (car body):
        x every 1 m from −9 to +9 m, y at −1.0, −0.5, 0, 0.5, 1.0 m.
        """
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


def body_from_entry(
    arrays: dict[str, np.ndarray],
    meta: dict[str, Any],
    name: str,
    x_ref: float,
    damping: DampingSpec,
    kind: str | None,
    extra_points: dict[str, Any] | None,
    t0: float,
    from_cache: bool,
) -> FlexibleBody:
    """The :class:`FlexibleBody` of a cache entry.

    Parameters
    ----------
    arrays, meta : dict
        The entry (:func:`~flexride.fem.body_cache.cache_entry`).
    name : str
        Body name.
    x_ref : float
        Longitudinal position of the body's reference frame (m).
    damping : float, sequence of float or RayleighDamping
        Modal damping of the elastic modes.
    kind : {"carbody", "frame"} or None
        A vehicle model, whose attachment and output nodes get elastic shapes; None for any
        other model.
    extra_points : dict, optional
        Further named nodes that get elastic shapes (its keys).
    t0 : float
        ``time.perf_counter()`` when the build started (for ``build_seconds``, s).
    from_cache : bool
        Whether the entry was loaded from the cache.
    """
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

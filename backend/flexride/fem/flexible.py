"""Flexible car body / bogie frame for the solver: build, reduce, cache, convert to ModalBody.

:func:`build_flexible_body` is the entry point used by the vehicle assembly. The expensive part
(mesh, assembly, eigen solution, reduction, report) depends only on the model parameters, the
vehicle inertia targets, the method, the cut-off and the element size; it is cached on disk by a
content hash of those inputs (:mod:`flexride.fem.body_cache`). Damping, name and reference
position are applied afterwards. :func:`flexible_body_from_model` does the same for any FE
model (e.g. an imported one).

The steps live in their own modules: :mod:`~flexride.fem.vehicle_models` (the vehicle's FE
models and inertia targets), :mod:`~flexride.fem.reduce` (reduction and report),
:mod:`~flexride.fem.body_cache` (cache inputs and entries) and
:mod:`~flexride.fem.flexible_body` (:class:`~flexride.fem.flexible_body.FlexibleBody`).
"""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from flexride.errors import FEModelError
from flexride.fem.body_cache import (
    Entry,
    cache_entry,
    load_or_build,
    model_inputs,
    vehicle_body_inputs,
)
from flexride.fem.carbody import CarBodyParams
from flexride.fem.damping import DampingSpec
from flexride.fem.flexible_body import FlexibleBody, body_from_entry
from flexride.fem.frame import FrameParams
from flexride.fem.massmatch import InertiaTarget
from flexride.fem.model import FEModel
from flexride.fem.reduce import METHODS, Method, reduce_model
from flexride.fem.vehicle_models import ATTACHMENTS, OUTPUTS, Kind, build_fe_model
from flexride.scenario.bodies import CarBodyCalibration

CalibrationProgress = Callable[[int, np.ndarray], None]
"""``progress(n_evaluations, frequencies_hz)`` of a calibration."""


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
    calibration: CarBodyCalibration | None = None,
    calibration_progress: CalibrationProgress | None = None,
) -> FlexibleBody:
    """Build (or load from the cache) a reduced flexible car body or bogie frame.

    Parameters
    ----------
    kind : {"carbody", "frame"}
        Which default FE model.
    vehicle : flexride.scenario.vehicle.Vehicle
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
    calibration : CarBodyCalibration, optional
        The car body only (``bodies.carbody.calibration``): calibrate the model to typed
        targets first (:func:`flexride.fem.calibrated_body.calibrated_carbody`, at
        ``element_size``, cached by content), then build the body from the calibrated values;
        ``FlexibleBody.calibration`` and ``body.info["calibration"]`` report it.
    calibration_progress : callable, optional
        ``progress(n_evaluations, frequencies_hz)`` after each FE evaluation of a
        calibration that runs.

    Returns
    -------
    FlexibleBody

    Raises
    ------
    FEModelError
        For an unknown kind or method, a calibration of the frame or together with
        ``params``, or a calibration whose targets pair with no model mode.
    """
    t0 = time.perf_counter()
    if kind not in ("carbody", "frame"):
        raise FEModelError(f"unknown body kind {kind!r}: use 'carbody' or 'frame'")
    if method not in METHODS:
        raise FEModelError(f"unknown reduction method {method!r}: use one of {', '.join(METHODS)}")
    calibrated = None
    if calibration is not None:
        if kind != "carbody" or params is not None:
            raise FEModelError("a calibration applies to the car body's default model only "
                               "(kind 'carbody', no params)")
        from flexride.fem.calibrated_body import calibrated_carbody

        calibrated = calibrated_carbody(vehicle, calibration, element_size,
                                        use_cache=use_cache, progress=calibration_progress)
        params = calibrated.params
    inputs = vehicle_body_inputs(kind, vehicle, method, cutoff_hz, element_size, extra_points,
                                 params)

    def build() -> Entry:
        return _reduce_vehicle_model(inputs, kind, vehicle, method, cutoff_hz, element_size,
                                     extra_points, params)

    arrays, meta, from_cache = load_or_build(inputs, build, use_cache)
    fb = body_from_entry(
        arrays, meta, name, x_ref, damping_ratio, kind, extra_points, t0, from_cache
    )
    if calibrated is not None:
        fb.calibration = calibrated.summary()
        fb.body.info["calibration"] = fb.calibration
    return fb


def _reduce_vehicle_model(inputs: dict, kind: Kind, vehicle, method: Method, cutoff_hz: float,
                          element_size: float,
                          extra_points: dict[str, tuple[float, float, float]] | None,
                          params: CarBodyParams | FrameParams | None) -> Entry:
    """Build the FE model of ``kind`` for ``vehicle`` (element size in m), name the node
    nearest to each extra point (m, model coordinates), reduce it with the attachment, output
    and extra nodes as Guyan masters (attachments as Craig–Bampton interface) up to
    ``cutoff_hz`` (Hz), and return its cache entry.
    """
    model, target = build_fe_model(kind, vehicle, element_size, params)
    for pname, xyz in (extra_points or {}).items():
        model.named_nodes[pname] = model.nearest_node(np.asarray(xyz, dtype=float))
    masters = list(ATTACHMENTS[kind]) + list(OUTPUTS[kind]) + list(extra_points or {})
    masters = list(dict.fromkeys(masters))
    modes, report = reduce_model(
        model, method, cutoff_hz, masters, list(ATTACHMENTS[kind]), target, kind
    )
    return cache_entry(inputs, model, modes, report, regions=True,
                       model_info={k: v for k, v in model.info.items() if k != "floor_grid"})


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
    inputs = model_inputs(model, method, cutoff_hz, att, outs)
    masters = list(dict.fromkeys(att + outs))

    def build() -> Entry:
        modes, report = reduce_model(model, method, cutoff_hz, masters, att, target, "model")
        return cache_entry(inputs, model, modes, report, regions=False, markers=masters)

    arrays, meta, from_cache = load_or_build(inputs, build, use_cache)
    markers = {k: None for k in masters}
    return body_from_entry(
        arrays, meta, name or model.name, x_ref, damping_ratio, None, markers, t0, from_cache
    )

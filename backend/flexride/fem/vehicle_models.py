"""The FE models of a vehicle's car body and bogie frame: the parametric models
(:mod:`~flexride.fem.carbody`, :mod:`~flexride.fem.frame`) with the vehicle's suspension geometry,
mass-matched to its inertia targets, and their named attachment and output nodes.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from flexride.errors import FEModelError
from flexride.fem.carbody import CarBodyParams, build_carbody
from flexride.fem.defaults import default_carbody_params, default_frame_params
from flexride.fem.frame import FrameParams, build_frame
from flexride.fem.massmatch import InertiaTarget
from flexride.fem.model import FEModel
from flexride.vehicle.topology import PAPER_POINT_NAMES

Kind = Literal["carbody", "frame"]

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


def _inertia_target(body) -> InertiaTarget:
    """Mass, CG (on the centre line, at the body's CG height) and Ixx/Iyy/Izz of a body's
    parameters (kg, m, kg·m²).
    """
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


def frame_element_size(element_size: float) -> float:
    """The frame's beam element size (m) for a body model's ``element_size`` (m, the car
    body's shells): half of it, at most 0.1 m.
    """
    return min(element_size / 2.0, 0.1)


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
        frame = build_frame(frame_params_for(vehicle, params), target,
                            frame_element_size(element_size))
        return frame, target
    raise FEModelError(f"unknown body kind {kind!r}: use 'carbody' or 'frame'")

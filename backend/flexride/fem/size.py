"""Size of an FE model before it is built: degrees of freedom from the element size.

A shell mesh of element size h has about area / h² nodes, so the car body's degrees of freedom
are counted exactly on a coarse reference mesh (h = 0.25 m, well under a second, remembered per
vehicle) and scaled by (0.25 / h)² for finer meshes: an upper estimate, within +11 % at 0.1 m
and +18 % at 0.05 m of the exact counts of the paper's car body (the finer meshes resolve
fewer boundary rows than the square law assumes). The frame's beam model is small and counted
exactly. A service uses this to refuse builds beyond its limits before starting them.
"""

from __future__ import annotations

from functools import lru_cache

from flexride.scenario.vehicle import Vehicle

REFERENCE_ELEMENT_SIZE_M = 0.25
"""Car-body element size (m) at which degrees of freedom are counted exactly."""


@lru_cache(maxsize=32)
def _exact_dofs(kind: str, vehicle_json: str, element_size: float) -> int:
    from flexride.fem.vehicle_models import build_fe_model

    vehicle = Vehicle.model_validate_json(vehicle_json)
    model, _target = build_fe_model(kind, vehicle, element_size=element_size)  # type: ignore[arg-type]
    return int(model.n_dof)


def estimated_dofs(kind: str, vehicle: Vehicle, element_size: float) -> int:
    """Degrees of freedom of the FE model of ``kind`` at ``element_size``.

    Parameters
    ----------
    kind : {"carbody", "frame"}
        Which body.
    vehicle : Vehicle
        Vehicle parameters (dimensions and inertia targets of the bodies).
    element_size : float
        Element size (m).

    Returns
    -------
    int
        Exact for the frame and for car-body element sizes of at least 0.25 m, otherwise an
        upper estimate (module docs).
    """
    key = vehicle.model_dump_json()
    if kind == "frame" or element_size >= REFERENCE_ELEMENT_SIZE_M:
        return _exact_dofs(kind, key, float(element_size))
    n_ref = _exact_dofs(kind, key, REFERENCE_ELEMENT_SIZE_M)
    return round(n_ref * (REFERENCE_ELEMENT_SIZE_M / element_size) ** 2)


def smallest_element_size(kind: str, vehicle: Vehicle, max_dofs: int) -> float | None:
    """The smallest car-body element size (m, rounded up to the millimetre) whose estimated
    degrees of freedom (:func:`estimated_dofs`) stay within ``max_dofs``; None for the frame
    and when even the reference size :data:`REFERENCE_ELEMENT_SIZE_M` is beyond it (the
    estimate below it is the square law, exact at the reference: so is this bound).
    """
    import math

    if kind != "carbody":
        return None
    n_ref = _exact_dofs(kind, vehicle.model_dump_json(), REFERENCE_ELEMENT_SIZE_M)
    if n_ref > max_dofs:
        return None
    h = REFERENCE_ELEMENT_SIZE_M * math.sqrt(n_ref / max_dofs)
    h = math.ceil(h * 1000.0 - 1e-9) / 1000.0
    while estimated_dofs(kind, vehicle, h) > max_dofs:  # rounding of the estimate
        h += 0.001
    return h

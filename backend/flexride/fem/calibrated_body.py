"""The calibrated car body of a scenario (``bodies.carbody.calibration``) or an FE build
request: the calibration run at body-build time and cached by content.

A :class:`~flexride.scenario.bodies.CarBodyCalibration` (typed targets, variables, evaluation
budget) is run through :func:`flexride.fem.calibration.calibrate_carbody` — the code of
``flexride fe calibrate`` — on the vehicle's car body at the body's element size, starting
from the calibrated defaults (:mod:`flexride.fem.defaults`). Its outcome (the calibrated values
and the pairing report) is an entry of the FE cache (:mod:`flexride.fem.cache`), keyed by
everything it depends on (:func:`calibration_inputs`), so it runs once per distinct input;
the reduced body built from the calibrated values is then an ordinary FE-cache entry keyed by
those values (:func:`flexride.fem.flexible.build_flexible_body`).

A target that the starting model cannot pair (no mode of its type among the computed ones) is
refused after the first evaluation, before the budget is spent (``require_paired``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from flexride.errors import FEModelError
from flexride.fem import cache
from flexride.fem.carbody import CarBodyParams
from flexride.fem.vehicle_models import carbody_params_for, carbody_target
from flexride.scenario.bodies import CarBodyCalibration

#: Version of a calibration cache entry's content (bump when it changes).
CALIBRATION_ENTRY = 1
#: Relative frequency error a calibration reports as met (-), as ``flexride fe calibrate``.
TOLERANCE = 0.05

Progress = Callable[[int, np.ndarray], None]
"""``progress(n_evaluations, frequencies_hz)`` after each FE evaluation of a calibration."""


@dataclass(frozen=True)
class CalibratedCarBody:
    """The outcome of a car body's calibration, as cached.

    Attributes
    ----------
    key : str
        Content key of the calibration in the FE cache.
    params : CarBodyParams
        The car body's parameters with the calibrated values (and the vehicle's geometry).
    report : dict
        ``targets`` (the spelling ``FREQ[:TYPE],…``), ``values`` (calibrated variables, SI),
        ``initial``, ``bounds``, ``at_bound``, ``pairs`` (each target with its paired mode:
        ``mode`` 1-based, ``model_hz``, ``error`` model/target − 1, ``model_type``; or the
        ``message`` why none), ``errors``, ``initial_frequencies_hz`` (Hz of each target's
        paired mode at the starting values), ``success`` (all within ``tolerance``),
        ``tolerance``, ``n_evaluations``, ``max_evaluations``, ``seconds`` (s, of the run
        that made it), ``element_size_m`` (m), ``model_modes`` and ``key``.
    from_cache : bool
        Whether the outcome was loaded from the FE cache (no calibration ran).
    """

    key: str
    params: CarBodyParams
    report: dict[str, Any]
    from_cache: bool

    def summary(self) -> dict[str, Any]:
        """What a body built from it says about its calibration: the report without the
        list of computed modes, with ``from_cache``.
        """
        out = {k: v for k, v in self.report.items() if k != "model_modes"}
        return {**out, "from_cache": self.from_cache}


def calibration_inputs(vehicle: Any, calibration: CarBodyCalibration,
                       element_size: float) -> dict[str, Any]:
    """What determines the outcome of ``calibration`` of ``vehicle``'s car body at
    ``element_size`` (m): the targets (canonical), the variables, the budget, the computed
    modes, the starting parameters (defaults with the vehicle's geometry) and the inertia
    target, with the calibration's fixed settings.
    """
    t = carbody_target(vehicle)
    return {
        "kind": "carbody-calibration",
        "entry": CALIBRATION_ENTRY,
        "targets": [[x.frequency_hz, x.mode_type] for x in calibration.targets],
        "variables": list(calibration.variable_names),
        "max_evaluations": int(calibration.max_evaluations),
        "n_modes": calibration.n_modes,
        "element_size": float(element_size),
        "base": carbody_params_for(vehicle).to_dict(),
        "target": {"mass": t.mass, "cg": t.cg, "inertia": t.inertia},
        "tolerance": TOLERANCE,
    }


def calibration_key(vehicle: Any, calibration: CarBodyCalibration, element_size: float) -> str:
    """Content key of the calibration in the FE cache (see :func:`calibration_inputs`)."""
    return cache.content_hash(calibration_inputs(vehicle, calibration, element_size))


def cached_calibration(vehicle: Any, calibration: CarBodyCalibration,
                       element_size: float) -> CalibratedCarBody | None:
    """The cached outcome of ``calibration`` (milliseconds), or None when it has not run."""
    key = calibration_key(vehicle, calibration, element_size)
    hit = cache.load(key)
    if hit is None:
        return None
    return _outcome(key, vehicle, hit[1], from_cache=True)


def calibrated_carbody(vehicle: Any, calibration: CarBodyCalibration, element_size: float,
                       *, use_cache: bool = True,
                       progress: Progress | None = None) -> CalibratedCarBody:
    """Calibrate ``vehicle``'s car body to ``calibration`` (or load the outcome from the FE
    cache).

    Parameters
    ----------
    vehicle : flexride.scenario.vehicle.Vehicle
        Vehicle parameters: the car body's inertia target and suspension geometry.
    calibration : CarBodyCalibration
        Targets, variables and evaluation budget (``bodies.carbody.calibration``).
    element_size : float
        Shell element size (m) of the car body being calibrated (and then built).
    use_cache : bool
        Read and write the FE cache.
    progress : callable, optional
        ``progress(n_evaluations, frequencies_hz)`` after each FE evaluation.

    Returns
    -------
    CalibratedCarBody

    Raises
    ------
    FEModelError
        When a target pairs with no mode of the starting model (before the budget is spent)
        or with none at the calibrated values (the outcome is cached: a repeated request fails
        at once), or the calibration's inputs are invalid.
    """
    from flexride.fem.calibration import calibrate_carbody
    from flexride.fem.targets import ModeTarget

    inputs = calibration_inputs(vehicle, calibration, element_size)
    key = cache.content_hash(inputs)
    hit = cache.load(key) if use_cache else None
    if hit is not None:
        return _checked(_outcome(key, vehicle, hit[1], from_cache=True))
    res = calibrate_carbody(
        [ModeTarget(x.frequency_hz, x.mode_type) for x in calibration.targets],
        carbody_target(vehicle),
        base=carbody_params_for(vehicle),
        variables=calibration.variable_names,
        element_size=float(element_size),
        tolerance=TOLERANCE,
        max_evaluations=int(calibration.max_evaluations),
        progress=progress,
        n_modes=calibration.n_modes,
        require_paired=True,
    )
    data = res.to_dict()
    start = res.history[0]["frequencies"] if res.history else [None] * len(res.pairs)
    report = {
        "targets": calibration.targets_spelling(),
        "values": data["values"],
        "initial": data["initial"],
        "bounds": data["bounds"],
        "at_bound": data["at_bound"],
        "pairs": data["pairs"],
        "unpaired": data["unpaired"],
        "errors": data["errors"],
        "initial_frequencies_hz": start,
        "success": data["success"],
        "tolerance": data["tolerance"],
        "n_evaluations": data["n_evaluations"],
        "max_evaluations": int(calibration.max_evaluations),
        "seconds": data["seconds"],
        "element_size_m": float(element_size),
        "model_modes": data["model_modes"],
        "key": key,
    }
    if use_cache:
        cache.store(key, {}, {"inputs": inputs, "calibration": report})
    return _checked(_outcome(key, vehicle, {"calibration": report}, from_cache=False))


def _outcome(key: str, vehicle: Any, meta: dict[str, Any], *,
             from_cache: bool) -> CalibratedCarBody:
    """The outcome of a cache entry's metadata."""
    report = dict(meta["calibration"])
    params = carbody_params_for(vehicle).with_values(**report["values"])
    return CalibratedCarBody(key=key, params=params, report=report, from_cache=from_cache)


def _checked(outcome: CalibratedCarBody) -> CalibratedCarBody:
    """``outcome``, unless a target ended unpaired (FEModelError with the reasons)."""
    unpaired = outcome.report.get("unpaired") or []
    if unpaired:
        raise FEModelError(
            f"the calibrated car body pairs no mode with {len(unpaired)} target(s) "
            f"({outcome.report['targets']}): " + "; ".join(unpaired))
    return outcome

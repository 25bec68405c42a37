"""Model updating of the car body against target modes: frequencies, types, measured shapes.

Bounded nonlinear least squares (SciPy ``least_squares``, trust-region reflective) on the
relative frequency errors of the targets, over panel sections (depth and face thickness of the
double-skin extrusions), a stiffness scale of the underframe beams and the share of under-floor
equipment in the non-structural mass. Each target is compared with the model mode *paired* with
it (:mod:`flexride.fem.pairing`: by type, by MAC where the target has a shape, by frequency),
never with the mode of the same rank: at every evaluation more modes than targets are computed
and classified, and the pairing is made anew. The Jacobian follows each paired mode through its
finite-difference steps by its shape (mass-weighted MAC), so a change of mode order between
two nearby points does not enter the derivatives. Mass, CG and inertias stay matched at every
evaluation (the non-structural mass is redistributed each time), and a weak pull towards the
starting values keeps the answer unique when there are more variables than targets.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np
from scipy.optimize import least_squares

from flexride.errors import FEModelError
from flexride.fem.calibration_eval import (
    CalibrationSetup,
    Evaluations,
    ModelPoint,
    paired_residuals,
)
from flexride.fem.calibration_result import CalibrationResult
from flexride.fem.calibration_variables import BOUNDS as BOUNDS
from flexride.fem.calibration_variables import DEFAULT_VARIABLES as DEFAULT_VARIABLES
from flexride.fem.carbody import CarBodyParams, build_carbody
from flexride.fem.eigen import Modes, free_free_modes
from flexride.fem.massmatch import InertiaTarget
from flexride.fem.modal_test import Sensors
from flexride.fem.model import FEModel
from flexride.fem.pairing import MIN_MAC, TargetPair
from flexride.fem.rigid import rigid_body_vectors
from flexride.fem.targets import ModeTarget, as_targets

#: Finite-difference step of the Jacobian on the log of each variable (5 %).
LOG_STEP = 0.05


def carbody_frequencies(
    params: CarBodyParams, target: InertiaTarget, element_size: float, n: int
) -> tuple[np.ndarray, FEModel, Modes]:
    """First ``n`` elastic frequencies (Hz) of the mass-matched car body, and (model, modes)."""
    model = build_carbody(params, target, element_size)
    K, M = model.assemble()
    modes = free_free_modes(K, M, rigid_body_vectors(model.nodes), n_elastic=n, tol=1e-8)
    return modes.frequencies[6 : 6 + n], model, modes


def default_mode_count(n_targets: int) -> int:
    """Elastic modes computed for ``n_targets`` targets: three times as many, at least six
    more, so that every target type has modes to choose from.
    """
    return max(3 * n_targets, n_targets + 6)


def calibrate_carbody(
    targets: Sequence[ModeTarget | float],
    target: InertiaTarget,
    base: CarBodyParams | None = None,
    variables: Sequence[str] = DEFAULT_VARIABLES,
    element_size: float = 0.2,
    tolerance: float = 0.05,
    regularisation: float = 0.02,
    max_evaluations: int = 60,
    progress: Callable[[int, np.ndarray], None] | None = None,
    *,
    n_modes: int | None = None,
    sensors: Sensors | None = None,
    max_sensor_distance: float | None = None,
    min_mac: float = MIN_MAC,
    require_paired: bool = False,
) -> CalibrationResult:
    """Update car-body sections and mass split so that the paired modes hit the targets.

    Parameters
    ----------
    targets : sequence of ModeTarget or float
        Targets in any order: :class:`~flexride.fem.targets.ModeTarget` (frequency in Hz,
        optional type and reference shape at ``sensors``) or bare frequencies (Hz), which are
        untyped targets paired with the nearest free mode in frequency.
    target : InertiaTarget
        Mass, CG and inertias kept matched.
    base : CarBodyParams, optional
        Starting parameters (the calibrated defaults when omitted).
    variables : sequence of str
        Names from :data:`BOUNDS` to update.
    element_size : float
        Element size (m) of the model being calibrated.
    tolerance : float
        Relative error accepted (reported as ``success``).
    regularisation : float
        Weight of the pull towards the starting values (on the log of each variable).
    max_evaluations : int
        Budget of FE evaluations.
    progress : callable, optional
        Called as ``progress(n_evaluations, frequencies)`` after each evaluation, with the
        frequency (Hz) of each target's paired mode (NaN if unpaired).
    n_modes : int, optional
        Elastic modes computed and classified per evaluation (:func:`default_mode_count`
        when omitted); a target can only be paired with one of them.
    sensors : Sensors, optional
        Sensor DOFs of the targets' shapes (e.g. from
        :func:`flexride.fem.modal_test.read_modal_test`); each is taken at its nearest node.
    max_sensor_distance : float, optional
        Largest accepted sensor-to-node distance (m); the element size when omitted.
    min_mac : float
        Least MAC of a pair for targets with a shape (-).
    require_paired : bool
        Refuse, after the first evaluation (at the starting values, before the optimisation
        spends its budget), targets that pair with no computed mode there: a target left
        unpaired is fitted by nothing, so the calibration could not move towards it.

    Returns
    -------
    CalibrationResult
        The pairs at the calibrated values (targets without a mode of their type, or without
        a similar enough shape, are listed with the reason), the variables and the modes.

    Raises
    ------
    FEModelError
        For no or invalid targets, unknown variables, fewer computed modes than targets,
        shapes without sensors or sensors far from the model; with ``require_paired``, for
        targets the starting model cannot pair (the message gives each one's reason).
    """
    setup = _setup(targets, target, base, variables, element_size, n_modes, sensors,
                   max_sensor_distance, min_mac)
    x0, lo, hi = _start_values(setup.base, list(setup.names))
    z0 = np.log(x0)
    t_start = time.perf_counter()
    evaluate = Evaluations(setup, progress)
    if require_paired:
        _require_paired(evaluate(z0).pairs, setup.n_modes)

    def residual(z: np.ndarray) -> np.ndarray:
        return np.concatenate([paired_residuals(evaluate(z).pairs),
                               regularisation * (z - z0)])

    def jacobian(z: np.ndarray) -> np.ndarray:
        return _jacobian(evaluate, z, np.log(hi), regularisation)

    res = least_squares(residual, z0, jac=jacobian, bounds=(np.log(lo), np.log(hi)),
                        x_scale=1.0,
                        max_nfev=max(1, max_evaluations // (len(setup.names) + 1)),
                        xtol=1e-4, ftol=1e-5)
    best = evaluate(res.x)
    return _result(setup, best, np.exp(res.x), x0, lo, hi, evaluate, tolerance,
                   time.perf_counter() - t_start)


def _setup(targets: Sequence[ModeTarget | float], inertia: InertiaTarget,
           base: CarBodyParams | None, variables: Sequence[str], element_size: float,
           n_modes: int | None, sensors: Sensors | None, max_sensor_distance: float | None,
           min_mac: float) -> CalibrationSetup:
    """The checked inputs of a calibration.

    Raises
    ------
    FEModelError
        See :func:`calibrate_carbody`.
    """
    t = as_targets(targets)
    unknown = [v for v in variables if v not in BOUNDS]
    if unknown or not variables:
        raise FEModelError(f"unknown calibration variables {unknown}; use {sorted(BOUNDS)}")
    n = default_mode_count(len(t)) if n_modes is None else int(n_modes)
    if n < len(t):
        raise FEModelError(f"{n} computed modes cannot pair {len(t)} targets: compute more")
    if sensors is None and any(x.shape is not None for x in t):
        raise FEModelError("targets with shapes need the sensors their shapes are given at")
    if not 0.0 <= min_mac <= 1.0:
        raise FEModelError(f"min_mac must lie in [0, 1], got {min_mac}")
    if base is None:
        from flexride.fem.defaults import default_carbody_params

        base = default_carbody_params()
    return CalibrationSetup(
        base=base, names=tuple(variables), inertia=inertia, element_size=float(element_size),
        n_modes=n, targets=tuple(t), sensors=sensors,
        max_sensor_distance=float(max_sensor_distance or element_size), min_mac=float(min_mac),
    )


def _require_paired(pairs: Sequence[TargetPair], n_modes: int) -> None:
    """Refuse targets without a paired mode (:class:`FEModelError` with each one's reason)."""
    missing = [f"target {k + 1} ({p.target.describe()}): {p.message}"
               for k, p in enumerate(pairs) if p.mode is None]
    if missing:
        raise FEModelError(
            f"the car body at the starting values pairs no mode with {len(missing)} of "
            f"{len(pairs)} targets among its {n_modes} lowest elastic modes, so the calibration "
            "cannot fit them: " + "; ".join(missing))


def _jacobian(evaluate: Evaluations, z: np.ndarray, z_hi: np.ndarray,
              regularisation: float) -> np.ndarray:
    """Derivatives of the residuals by forward differences of :data:`LOG_STEP` on each log
    variable (backward at the upper bound), each target's paired mode followed by its shape.
    """
    base = evaluate(z)
    f0 = base.modes.frequencies_hz
    n_t, n_v = len(base.pairs), z.size
    J = np.zeros((n_t + n_v, n_v))
    J[n_t:] = regularisation * np.eye(n_v)
    for k in range(n_v):
        step = LOG_STEP if z[k] + LOG_STEP <= z_hi[k] else -LOG_STEP
        moved = evaluate(z + step * np.eye(n_v)[k])
        for i, pair in enumerate(base.pairs):
            if pair.mode is None:
                continue
            j = base.follow(pair.mode, moved)
            df = moved.modes.frequencies_hz[j] - f0[pair.mode]
            J[i, k] = df / pair.target.frequency_hz / step
    return J


def _start_values(base: CarBodyParams, names: list[str]) -> tuple[np.ndarray, np.ndarray,
                                                                  np.ndarray]:
    """Starting values of the variables ``names`` (from ``base``, moved just inside their
    bounds) and their lower and upper bounds (SI units).
    """
    x0 = np.array([getattr(base, v) for v in names], dtype=float)
    lo = np.array([BOUNDS[v][0] for v in names])
    hi = np.array([BOUNDS[v][1] for v in names])
    return np.clip(x0, lo * 1.0001, hi * 0.9999), lo, hi


def _at_bound(names: Sequence[str], x: np.ndarray, lo: np.ndarray,
              hi: np.ndarray) -> list[str]:
    """The variables whose values ``x`` are within 0.1 % of a bound."""
    return [
        n
        for n, v, a, b in zip(names, x, lo, hi, strict=True)
        if v <= a * 1.001 or v >= b * 0.999
    ]


def _result(setup: CalibrationSetup, best: ModelPoint, x: np.ndarray, x0: np.ndarray,
            lo: np.ndarray, hi: np.ndarray, evaluate: Evaluations, tolerance: float,
            seconds: float) -> CalibrationResult:
    """The result at the calibrated point ``best`` (variables ``x``, started at ``x0``)."""
    names = setup.names
    errors = [p.error for p in best.pairs]
    sn = evaluate.sensor_nodes
    return CalibrationResult(
        pairs=best.pairs,
        model_modes=[(float(f), t) for f, t in zip(best.modes.frequencies_hz, best.modes.types,
                                                   strict=True)],
        values={n: float(v) for n, v in zip(names, x, strict=True)},
        initial={n: float(v) for n, v in zip(names, x0, strict=True)},
        bounds={n: BOUNDS[n] for n in names},
        at_bound=_at_bound(names, x, lo, hi),
        n_evaluations=len(evaluate.history),
        seconds=seconds,
        element_size=setup.element_size,
        success=all(e is not None and abs(e) <= tolerance for e in errors),
        tolerance=float(tolerance),
        min_mac=setup.min_mac,
        sensors=None if sn is None else {"n_dofs": int(sn.dofs.size),
                                         "max_distance_m": float(sn.distances.max())},
        history=evaluate.history,
    )

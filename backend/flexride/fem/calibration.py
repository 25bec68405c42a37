"""Model updating of the car body against target natural frequencies.

Bounded nonlinear least squares (SciPy ``least_squares``, trust-region reflective) on the
relative errors of the first elastic frequencies (sorted), over panel sections (depth and face
thickness of the double-skin extrusions), a stiffness scale of the underframe beams and the
share of under-floor equipment in the non-structural mass. Mass, CG and inertias stay matched at
every evaluation (the non-structural mass is redistributed each time), and a weak pull towards
the starting values keeps the answer unique when there are more variables than targets.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from flexride.errors import FEModelError
from flexride.fem.carbody import CarBodyParams, build_carbody
from flexride.fem.classify import classify_mode
from flexride.fem.eigen import Modes, free_free_modes
from flexride.fem.massmatch import InertiaTarget
from flexride.fem.model import FEModel
from flexride.fem.rigid import rigid_body_vectors

#: Calibration variables and their bounds (SI units).
BOUNDS: dict[str, tuple[float, float]] = {
    "floor_depth": (0.020, 0.080),
    "wall_depth": (0.020, 0.080),
    "roof_depth": (0.015, 0.060),
    "end_depth": (0.020, 0.080),
    "floor_face": (1.5e-3, 4.0e-3),
    "wall_face": (1.5e-3, 4.0e-3),
    "roof_face": (1.5e-3, 4.0e-3),
    "end_face": (1.5e-3, 4.0e-3),
    "beam_scale": (0.5, 2.0),
    "nsm_underfloor": (0.10, 0.60),
}
DEFAULT_VARIABLES: tuple[str, ...] = (
    "floor_depth",
    "wall_depth",
    "roof_depth",
    "end_depth",
    "beam_scale",
    "nsm_underfloor",
)


@dataclass
class CalibrationResult:
    """Outcome of a calibration.

    Attributes
    ----------
    targets_hz : list of float
        Target frequencies (Hz).
    frequencies_hz : list of float
        Calibrated first elastic frequencies (Hz).
    errors : list of float
        Relative errors (-).
    classification : list of str
        Dominant deformation of each calibrated mode.
    values : dict of str to float
        Calibrated variables (SI).
    initial : dict of str to float
        Starting values.
    bounds : dict of str to (float, float)
        Bounds used.
    at_bound : list of str
        Variables that ended on a bound.
    n_evaluations : int
        Number of FE evaluations.
    seconds : float
        Wall time (s).
    element_size : float
        Element size (m).
    success : bool
        Whether every error is within ``tolerance``.
    tolerance : float
        Accepted relative error.
    history : list of dict
        Variables and frequencies of every evaluation.
    """

    targets_hz: list[float]
    frequencies_hz: list[float]
    errors: list[float]
    classification: list[str]
    values: dict[str, float]
    initial: dict[str, float]
    bounds: dict[str, tuple[float, float]]
    at_bound: list[str]
    n_evaluations: int
    seconds: float
    element_size: float
    success: bool
    tolerance: float
    history: list[dict] = field(default_factory=list)

    def to_dict(self) -> dict:
        """JSON-able dict (history left out)."""
        return {
            "targets_hz": self.targets_hz,
            "frequencies_hz": self.frequencies_hz,
            "errors": self.errors,
            "classification": self.classification,
            "values": self.values,
            "initial": self.initial,
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "at_bound": self.at_bound,
            "n_evaluations": self.n_evaluations,
            "seconds": self.seconds,
            "element_size": self.element_size,
            "success": self.success,
            "tolerance": self.tolerance,
        }

    def table(self) -> str:
        """Readable summary."""
        lines = [
            f"calibration ({self.n_evaluations} FE evaluations, {self.seconds:.0f} s, "
            f"element size {self.element_size:g} m): "
            + ("all within" if self.success else "NOT all within")
            + f" ±{100 * self.tolerance:g} %",
            f"{'mode':>4} {'target Hz':>10} {'model Hz':>9} {'error %':>8}  classification",
        ]
        for k, (t, f, e) in enumerate(
            zip(self.targets_hz, self.frequencies_hz, self.errors, strict=False)
        ):
            c = self.classification[k] if k < len(self.classification) else ""
            lines.append(f"{k + 1:4d} {t:10.3f} {f:9.3f} {100 * e:8.2f}  {c}")
        lines.append("variables (initial -> calibrated, bounds):")
        for name, v in self.values.items():
            lo, hi = self.bounds[name]
            flag = "  AT BOUND" if name in self.at_bound else ""
            lines.append(
                f"  {name:15s} {self.initial[name]:.5g} -> {v:.5g}  [{lo:g}, {hi:g}]{flag}"
            )
        return "\n".join(lines)


def carbody_frequencies(
    params: CarBodyParams, target: InertiaTarget, element_size: float, n: int
) -> tuple[np.ndarray, FEModel, Modes]:
    """First ``n`` elastic frequencies (Hz) of the mass-matched car body, and (model, modes)."""
    model = build_carbody(params, target, element_size)
    K, M = model.assemble()
    modes = free_free_modes(K, M, rigid_body_vectors(model.nodes), n_elastic=n, tol=1e-8)
    return modes.frequencies[6 : 6 + n], model, modes


def calibrate_carbody(
    targets_hz: Sequence[float],
    target: InertiaTarget,
    base: CarBodyParams | None = None,
    variables: Sequence[str] = DEFAULT_VARIABLES,
    element_size: float = 0.2,
    tolerance: float = 0.05,
    regularisation: float = 0.02,
    max_evaluations: int = 60,
    progress: Callable[[int, np.ndarray], None] | None = None,
) -> CalibrationResult:
    """Update car-body sections and mass split so the first elastic modes hit ``targets_hz``.

    Parameters
    ----------
    targets_hz : sequence of float
        Target frequencies (Hz) of the first ``len(targets_hz)`` elastic modes, ascending.
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
        Called as ``progress(n_evaluations, frequencies)`` after each evaluation.

    Returns
    -------
    CalibrationResult
    """
    t = _check_targets(targets_hz, variables)
    if base is None:
        from flexride.fem.defaults import default_carbody_params

        base = default_carbody_params()
    names = list(variables)
    x0, lo, hi = _start_values(base, names)
    z0 = np.log(x0)
    t_start = time.perf_counter()
    evaluate = _Evaluations(base, names, target, element_size, t.size, progress)

    def residual(z: np.ndarray) -> np.ndarray:
        f = evaluate(z)
        return np.concatenate([f / t - 1.0, regularisation * (z - z0)])

    res = least_squares(residual, z0, bounds=(np.log(lo), np.log(hi)), x_scale=1.0,
                        diff_step=0.03, max_nfev=max(1, max_evaluations // (len(names) + 1)),
                        xtol=1e-4, ftol=1e-5)
    z_best = res.x
    f_best = evaluate(z_best)
    x_best = np.exp(z_best)
    err = f_best / t - 1.0
    p_best = base.with_values(**dict(zip(names, map(float, x_best), strict=False)))
    return CalibrationResult(
        targets_hz=t.tolist(),
        frequencies_hz=[float(v) for v in f_best],
        errors=[float(v) for v in err],
        classification=_mode_names(p_best, target, element_size, t.size),
        values={n: float(v) for n, v in zip(names, x_best, strict=False)},
        initial={n: float(v) for n, v in zip(names, x0, strict=False)},
        bounds={n: BOUNDS[n] for n in names},
        at_bound=_at_bound(names, x_best, lo, hi),
        n_evaluations=len(evaluate.history),
        seconds=time.perf_counter() - t_start,
        element_size=float(element_size),
        success=bool(np.all(np.abs(err) <= tolerance)),
        tolerance=float(tolerance),
        history=evaluate.history,
    )


def _start_values(base: CarBodyParams, names: list[str]) -> tuple[np.ndarray, np.ndarray,
                                                                  np.ndarray]:
    """Starting values of the variables ``names`` (from ``base``, moved just inside their
    bounds) and their lower and upper bounds (SI units).
    """
    x0 = np.array([getattr(base, v) for v in names], dtype=float)
    lo = np.array([BOUNDS[v][0] for v in names])
    hi = np.array([BOUNDS[v][1] for v in names])
    return np.clip(x0, lo * 1.0001, hi * 0.9999), lo, hi


def _at_bound(names: list[str], x: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> list[str]:
    """The variables whose values ``x`` are within 0.1 % of a bound."""
    return [
        n
        for n, v, a, b in zip(names, x, lo, hi, strict=False)
        if v <= a * 1.001 or v >= b * 0.999
    ]


def _check_targets(targets_hz: Sequence[float], variables: Sequence[str]) -> np.ndarray:
    """The target frequencies (Hz) as an array, after checking them and the variable names.

    Raises
    ------
    FEModelError
        Targets that are not positive, finite and ascending, or unknown variables.
    """
    t = np.asarray(targets_hz, dtype=float)
    if t.size == 0 or np.any(~np.isfinite(t)) or np.any(t <= 0):
        raise FEModelError("target frequencies must be positive numbers")
    if np.any(np.diff(t) < 0):
        raise FEModelError("target frequencies must be in ascending order")
    unknown = [v for v in variables if v not in BOUNDS]
    if unknown:
        raise FEModelError(f"unknown calibration variables {unknown}; use {sorted(BOUNDS)}")
    return t


class _Evaluations:
    """The first elastic frequencies (Hz) of the car body at the log-values ``z`` of the
    calibration variables, each point evaluated once (remembered at 12 decimals of ``z``).

    Attributes
    ----------
    history : list of dict
        Every FE evaluation: ``values`` of the variables (SI) and ``frequencies`` (Hz).
    """

    def __init__(self, base: CarBodyParams, names: list[str], target: InertiaTarget,
                 element_size: float, n: int,
                 progress: Callable[[int, np.ndarray], None] | None) -> None:
        self.base, self.names, self.target = base, names, target
        self.element_size, self.n, self.progress = element_size, n, progress
        self.history: list[dict] = []
        self._memo: dict[tuple, np.ndarray] = {}

    def __call__(self, z: np.ndarray) -> np.ndarray:
        key = tuple(np.round(z, 12))
        if key in self._memo:
            return self._memo[key]
        x = np.exp(z)
        p = self.base.with_values(**dict(zip(self.names, map(float, x), strict=False)))
        f, _, _ = carbody_frequencies(p, self.target, self.element_size, self.n)
        self._memo[key] = f
        self.history.append(
            {"values": dict(zip(self.names, map(float, x), strict=False)),
             "frequencies": f.tolist()}
        )
        if self.progress is not None:
            self.progress(len(self.history), f)
        return f


def _mode_names(params: CarBodyParams, target: InertiaTarget, element_size: float,
                n: int) -> list[str]:
    """Names of the first ``n`` elastic modes of the car body with ``params`` (element size
    in m).
    """
    _, model, modes = carbody_frequencies(params, target, element_size, n)
    _, M = model.assemble()
    return [
        classify_mode(modes.shapes[:, 6 + k], M, model.nodes, model.node_region, model.region_names)
        for k in range(n)
    ]

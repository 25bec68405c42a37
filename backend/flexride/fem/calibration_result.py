"""The outcome of a car-body calibration: the pairs of targets and model modes, the variables,
and its readable and JSON forms.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from flexride.fem.pairing import TargetPair


@dataclass
class CalibrationResult:
    """Outcome of a calibration (:func:`flexride.fem.calibration.calibrate_carbody`).

    Attributes
    ----------
    pairs : list of TargetPair
        Each target (in the given order) with its paired model mode at the calibrated values:
        mode number, frequency (Hz), error, type, MAC; or why none is paired.
    model_modes : list of (float, str)
        Frequency (Hz) and type of every computed elastic mode at the calibrated values.
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
        Whether every target is paired and within ``tolerance``.
    tolerance : float
        Accepted relative error (-).
    min_mac : float
        Least MAC of a pair for targets with a shape (-).
    sensors : dict or None
        With measured shapes: ``n_dofs`` and ``max_distance_m`` (largest sensor-to-node
        distance, m).
    history : list of dict
        Every evaluation: ``values`` (SI), ``frequencies`` (Hz of the paired mode of each
        target, None if unpaired) and ``modes`` (Hz of all computed modes).
    """

    pairs: list[TargetPair]
    model_modes: list[tuple[float, str]]
    values: dict[str, float]
    initial: dict[str, float]
    bounds: dict[str, tuple[float, float]]
    at_bound: list[str]
    n_evaluations: int
    seconds: float
    element_size: float
    success: bool
    tolerance: float
    min_mac: float
    sensors: dict | None = None
    history: list[dict] = field(default_factory=list)

    @property
    def targets_hz(self) -> list[float]:
        """Target frequencies (Hz), in the given order."""
        return [p.target.frequency_hz for p in self.pairs]

    @property
    def frequencies_hz(self) -> list[float | None]:
        """Frequency (Hz) of the model mode paired with each target (None: unpaired)."""
        return [p.frequency_hz for p in self.pairs]

    @property
    def errors(self) -> list[float | None]:
        """Relative error of each target (-) (None: unpaired)."""
        return [p.error for p in self.pairs]

    @property
    def classification(self) -> list[str | None]:
        """Type of the model mode paired with each target (None: unpaired)."""
        return [p.mode_type for p in self.pairs]

    @property
    def unpaired(self) -> list[str]:
        """One message per target without a model mode."""
        return [f"target {k + 1} ({p.target.describe()}): {p.message}"
                for k, p in enumerate(self.pairs) if p.mode is None]

    def to_dict(self) -> dict:
        """JSON-able dict (history left out)."""
        return {
            "pairs": [p.to_dict() for p in self.pairs],
            "unpaired": self.unpaired,
            "targets_hz": self.targets_hz,
            "frequencies_hz": self.frequencies_hz,
            "errors": self.errors,
            "classification": self.classification,
            "model_modes": [{"mode": k + 1, "frequency_hz": f, "type": t}
                            for k, (f, t) in enumerate(self.model_modes)],
            "values": self.values,
            "initial": self.initial,
            "bounds": {k: list(v) for k, v in self.bounds.items()},
            "at_bound": self.at_bound,
            "n_evaluations": self.n_evaluations,
            "seconds": self.seconds,
            "element_size": self.element_size,
            "success": self.success,
            "tolerance": self.tolerance,
            "min_mac": self.min_mac,
            "sensors": self.sensors,
        }

    def table(self) -> str:
        """Readable summary: the pairs, the unpaired targets, the variables, the modes."""
        state = "all paired and within" if self.success else "NOT all paired and within"
        lines = [
            f"calibration ({self.n_evaluations} FE evaluations, {self.seconds:.0f} s, element "
            f"size {self.element_size:g} m, {len(self.model_modes)} model modes): {state} "
            f"±{100 * self.tolerance:g} %",
            f"{'#':>3} {'target Hz':>9}  {'wanted type':<24} {'mode':>4} {'model Hz':>8} "
            f"{'error %':>8} {'MAC':>5}  model mode type",
            *(_pair_line(k, p) for k, p in enumerate(self.pairs)),
            *(f"NOT PAIRED: {m}" for m in self.unpaired),
            "variables (initial -> calibrated, bounds):",
            *self._variable_lines(),
            "model modes at the calibrated values (mode, Hz, type; * = paired):",
            *self._mode_lines(),
        ]
        if self.sensors:
            lines.insert(1, f"measured shapes: {self.sensors['n_dofs']} sensor DOFs, each at "
                            f"its nearest node (at most {self.sensors['max_distance_m']:.3f} m "
                            "away)")
        return "\n".join(lines)

    def _variable_lines(self) -> list[str]:
        out = []
        for name, v in self.values.items():
            lo, hi = self.bounds[name]
            flag = "  AT BOUND" if name in self.at_bound else ""
            out.append(f"  {name:15s} {self.initial[name]:.5g} -> {v:.5g}  [{lo:g}, {hi:g}]{flag}")
        return out

    def _mode_lines(self) -> list[str]:
        paired = {p.mode for p in self.pairs}
        return [f"  {k + 1:3d}{'*' if k in paired else ' '} {f:8.3f}  {t}"
                for k, (f, t) in enumerate(self.model_modes)]


def _pair_line(k: int, p: TargetPair) -> str:
    """One row of the pairs table."""
    wanted = p.target.mode_type or "(any)"
    mac = "-" if p.mac is None else f"{p.mac:.3f}"
    if p.mode is None or p.frequency_hz is None or p.error is None:
        return (f"{k + 1:3d} {p.target.frequency_hz:9.3f}  {wanted:<24} {'-':>4} {'-':>8} "
                f"{'-':>8} {'-':>5}  NOT PAIRED")
    return (f"{k + 1:3d} {p.target.frequency_hz:9.3f}  {wanted:<24} {p.mode + 1:4d} "
            f"{p.frequency_hz:8.3f} {100 * p.error:+8.2f} {mac:>5}  {p.mode_type}")

"""Critical (hunting) speed of a vehicle, by two independent methods.

* **Linear**: the speed at which the linearised vehicle–track model (:mod:`flexride.frequency`)
  first has a growing mode: bisection in speed on whether :func:`~flexride.frequency.
  linear_model` refuses the system as unstable. This is the Hopf point of the steady running
  on smooth straight track; it says nothing of large disturbances.
* **Nonlinear**: time-domain runs on smooth straight track that start from static equilibrium
  with the leading wheelset displaced laterally by ``disturbance_m``. Its lateral displacement
  is measured over the first and the last ``window_m`` (after a run-in); the run *hunts* when
  the motion has not decayed (last amplitude ≥ ``decay_ratio`` × first, or the run is stopped
  as a runaway). Bisection in speed gives the lowest speed that hunts for this
  disturbance: with a subcritical bifurcation (a limit cycle that a large disturbance reaches
  below the Hopf point, as flange contact and the profiles' rising conicity give), it lies
  below the linear one; both agree for small disturbances when the bifurcation is
  supercritical.

The excitations and the line of the scenario are replaced by smooth straight track; everything
else (vehicle, track, contact geometry, time step) is kept.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from flexride.errors import FlexrideError
from flexride.scenario.scenario import Scenario, scenario_from_dict


@dataclass(frozen=True)
class DecayRun:
    """One time-domain run after a lateral disturbance.

    Attributes
    ----------
    speed_kmh : float
        Running speed (km/h).
    amplitude_start_m, amplitude_end_m : float
        Half peak-to-peak lateral displacement of the leading wheelset over the first and the
        last window (m).
    hunting : bool
        Whether the motion did not decay (or the run stopped as a runaway).
    note : str
        Why, in words.
    growth_rate_per_s : float or None
        Slope of the logarithm of the displacement's peaks over the second half of the run
        (1/s): the real part of the eigenvalue of the least damped mode the disturbance
        started, when the motion is small enough to be linear; None when not measurable.
    """

    speed_kmh: float
    amplitude_start_m: float
    amplitude_end_m: float
    hunting: bool
    note: str = ""
    growth_rate_per_s: float | None = None


@dataclass(frozen=True)
class CriticalSpeed:
    """Critical speeds of a vehicle and how they were found.

    Attributes
    ----------
    linear_kmh, nonlinear_kmh : float or None
        Lowest unstable speed by each method within the searched range (km/h); None when the
        vehicle is stable up to ``v_max_kmh`` (or, linear, when the model cannot be built).
    v_min_kmh, v_max_kmh, tolerance_kmh : float
        The searched range and the bisection tolerance (km/h).
    disturbance_m : float
        Initial lateral displacement of the leading wheelset in the nonlinear runs (m).
    runs : list of DecayRun
        Every nonlinear run, in the order made.
    notes : list of str
        What limited a method, if anything.
    """

    linear_kmh: float | None
    nonlinear_kmh: float | None
    v_min_kmh: float
    v_max_kmh: float
    tolerance_kmh: float
    disturbance_m: float
    runs: list[DecayRun] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-able data."""
        return asdict(self)


def smooth_straight(scenario: Scenario, speed_kmh: float, distance_m: float) -> Scenario:
    """``scenario`` on smooth straight track at ``speed_kmh`` over ``distance_m``."""
    data = scenario.model_dump(mode="json")
    data.update(line={"kind": "straight"}, excitation=[], speed_kmh=float(speed_kmh),
                duration_s=None, distance_m=float(distance_m))
    return scenario_from_dict(data, source=f"smooth straight track at {speed_kmh:g} km/h")


def _amplitude(y: np.ndarray) -> float:
    return 0.5 * float(np.ptp(y)) if y.size else 0.0


def growth_rate(t: np.ndarray, y: np.ndarray) -> float | None:
    """Slope of log |peak| against time over the second half of ``t`` (1/s): the growth rate
    of a free oscillation ``y(t)`` (negative: decaying); None with fewer than 4 peaks.
    """
    from scipy.signal import find_peaks

    later = t >= 0.5 * (t[0] + t[-1])
    a = np.abs(y[later] - np.mean(y[later]))
    peaks, _ = find_peaks(a)
    peaks = peaks[a[peaks] > 1e-12]
    if peaks.size < 4:
        return None
    return float(np.polyfit(t[later][peaks], np.log(a[peaks]), 1)[0])


def decay_run(scenario: Scenario, speed_kmh: float, *, disturbance_m: float = 0.003,
              distance_m: float = 400.0, run_in_m: float = 20.0, window_m: float = 60.0,
              decay_ratio: float = 0.9) -> DecayRun:
    """Run ``scenario`` on smooth straight track at ``speed_kmh`` after displacing the leading
    wheelset laterally by ``disturbance_m`` (m) and say whether it hunts (module docs).
    """
    from flexride.solver.assemble import assemble
    from flexride.solver.setup_cache import default_cache
    from flexride.solver.simulate import integrate, prepare_run

    sc = smooth_straight(scenario, speed_kmh, distance_m)
    asm, ready = prepare_run(sc, assemble(sc), default_cache(), sc.solver.check_stability)
    X0 = ready.X0
    Xi = X0.copy()
    # the leading wheelset alone: in phase and in antiphase modes of the bogies both start
    # (all wheelsets displaced alike would leave the car body's yaw modes at rest)
    Xi[asm.sys.body_off[asm.vehicle.wheelsets[0]] + 1] += disturbance_m
    try:
        res = integrate(asm, Xi, np.zeros_like(Xi), sc, lambda _f, _m: None, X_ref=X0)
    except FlexrideError as err:  # a runaway: the motion grew without bound
        return DecayRun(speed_kmh, disturbance_m, float("inf"), True, f"stopped: {err}")
    y, s = res.channels["wheelset1.cg.disp.y"], res.distance
    first = _amplitude(y[(s >= run_in_m) & (s < run_in_m + window_m)])
    last = _amplitude(y[s >= s[-1] - window_m])
    hunting = last >= decay_ratio * first
    note = (f"amplitude {1e3 * first:.3g} → {1e3 * last:.3g} mm over "
            f"{s[-1] - run_in_m - window_m:.0f} m")
    return DecayRun(speed_kmh, first, last, bool(hunting), note, growth_rate(res.time, y))


def linear_stable(scenario: Scenario, speed_kmh: float) -> bool:
    """Whether the linearised model on smooth straight track at ``speed_kmh`` has no growing
    mode (:class:`~flexride.frequency.LinearisationError` with reason ``unstable``).
    """
    from flexride.frequency import LinearisationError, linear_model

    sc = smooth_straight(scenario, speed_kmh, 100.0)
    try:
        linear_model(sc, strict=False)
    except LinearisationError as err:
        if err.reason == "unstable":
            return False
        raise
    return True


def lowest_unstable(stable: Callable[[float], bool], v_min: float, v_max: float,
                    tolerance: float) -> float | None:
    """The lowest speed in [``v_min``, ``v_max``] (km/h) at which ``stable`` is False, to
    ``tolerance`` (km/h) by bisection (stability assumed below it); None when stable at
    ``v_max``; ``v_min`` when already unstable there.
    """
    if stable(v_max):
        return None
    if not stable(v_min):
        return v_min
    lo, hi = v_min, v_max
    while hi - lo > tolerance:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return hi


def critical_speed(scenario: Scenario, *, v_min_kmh: float = 40.0, v_max_kmh: float = 200.0,
                   tolerance_kmh: float = 2.0, disturbance_m: float = 0.003,
                   distance_m: float = 400.0, linear: bool = True,
                   progress: Callable[[str], None] | None = None) -> CriticalSpeed:
    """Linear and nonlinear critical speeds of ``scenario``'s vehicle (module docs).

    Parameters
    ----------
    scenario : Scenario
        The vehicle, track, contact geometry and time step to use.
    v_min_kmh, v_max_kmh, tolerance_kmh : float
        Searched speed range and bisection tolerance (km/h).
    disturbance_m : float
        Initial lateral displacement of the leading wheelset in the nonlinear runs (m).
    distance_m : float
        Length of each nonlinear run (m).
    linear : bool
        Also find the linear critical speed.
    progress : callable, optional
        ``progress(message)`` after each run.
    """
    runs: list[DecayRun] = []
    notes: list[str] = []

    def nonlinear_stable(v: float) -> bool:
        run = decay_run(scenario, v, disturbance_m=disturbance_m, distance_m=distance_m)
        runs.append(run)
        if progress is not None:
            progress(f"{v:.1f} km/h: {'hunting' if run.hunting else 'decays'} ({run.note})")
        return not run.hunting

    v_nl = lowest_unstable(nonlinear_stable, v_min_kmh, v_max_kmh, tolerance_kmh)
    v_lin = None
    if linear:
        try:
            v_lin = lowest_unstable(lambda v: linear_stable(scenario, v), v_min_kmh, v_max_kmh,
                                    tolerance_kmh)
        except FlexrideError as err:
            notes.append(f"linear critical speed not found: {err}")
    return CriticalSpeed(v_lin, v_nl, v_min_kmh, v_max_kmh, tolerance_kmh, disturbance_m,
                         runs, notes)

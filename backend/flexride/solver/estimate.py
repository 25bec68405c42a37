"""What a run will cost, known before it runs: time steps, recorded points, channels, samples
and the size of the recorded results.

Computed from the scenario and a rigid build of the vehicle (milliseconds), so a service can
refuse work beyond its limits before anything expensive starts.
"""

from __future__ import annotations

from dataclasses import dataclass

from flexride.errors import ErrorItem
from flexride.scenario.scenario import Scenario, located_error
from flexride.solver.assemble import channel_layout, output_rate_for
from flexride.vehicle.topology import build_vehicle, carbody_output_points

BYTES_PER_SAMPLE = 8
"""Bytes of one recorded value (float64, in memory and in the uncompressed results file)."""


@dataclass(frozen=True)
class RunEstimate:
    """Size of a run.

    Attributes
    ----------
    steps : int or None
        Time steps (duration / dt); None for ``solver.dt: auto`` before the set-up has chosen
        the step.
    output_points : int
        Recorded car-body points (the paper's six, user points and the floor grid).
    channels : int
        Recorded channels.
    samples : int
        Recorded samples per channel.
    result_bytes : int
        Recorded values × 8 bytes: the memory of the results and, within the few kB of
        metadata, the size of the results file.
    """

    steps: int | None
    output_points: int
    channels: int
    samples: int
    result_bytes: int

    @property
    def result_mb(self) -> float:
        """``result_bytes`` in MB (10⁶ bytes)."""
        return self.result_bytes / 1.0e6


def count_output_points(scenario: Scenario) -> int:
    """Recorded car-body points of ``scenario`` (cheap: no vehicle is built)."""
    return len(carbody_output_points(scenario.vehicle, scenario.output))


def known_step(scenario: Scenario, dt: float | None = None) -> float | None:
    """The step (s): ``dt`` if given, else the scenario's; None for ``solver.dt: auto``."""
    step = scenario.solver.dt if dt is None else dt
    return None if isinstance(step, str) else float(step)


def count_steps(scenario: Scenario, dt: float | None = None) -> int | None:
    """Time steps of ``scenario`` (as the solver rounds them) with the step ``dt`` (s; default
    the scenario's); None for ``solver.dt: auto`` without ``dt``.
    """
    step = known_step(scenario, dt)
    return None if step is None else round(scenario.duration / step)


def estimate_run(scenario: Scenario, dt: float | None = None) -> RunEstimate:
    """The size of a run.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario (its car-body points should be bounded first with
        :func:`count_output_points`: the rigid vehicle built here has one marker per point).
    dt : float, optional
        The step (s) when known (``solver.dt: auto``: once the set-up has chosen it); with auto
        the samples do not depend on it, the step dividing the output interval.

    Returns
    -------
    RunEstimate
    """
    step = known_step(scenario, dt)
    rate = output_rate_for(scenario, step)
    if step is None:  # auto: the step will divide the output interval
        steps, samples = None, round(scenario.duration * rate)
    else:
        n = round(scenario.duration / step)
        steps, samples = n, n // max(1, round(1.0 / (step * rate)))
    names, _units, _kinds = channel_layout(build_vehicle(scenario.vehicle, scenario.output),
                                           profiles=scenario.contact.geometry == "profiles")
    return RunEstimate(steps=steps, output_points=count_output_points(scenario),
                       channels=len(names), samples=samples,
                       result_bytes=len(names) * samples * BYTES_PER_SAMPLE)


def length_field(scenario: Scenario) -> str:
    """The field that sets the run's length (``duration_s`` or ``distance_m``)."""
    return "duration_s" if scenario.duration_s is not None else "distance_m"


def check_steps(scenario: Scenario, dt: float, max_steps: int) -> None:
    """Refuse a run of more than ``max_steps`` steps of ``dt`` (s): a
    :class:`~flexride.errors.ScenarioError` located at the length field (the service's bound,
    ``FLEXRIDE_MAX_STEPS``, checked on admission and, for ``solver.dt: auto``, once the set-up
    has chosen the step).
    """
    steps = round(scenario.duration / dt)
    if steps > max_steps:
        raise located_error([ErrorItem(
            (length_field(scenario),),
            f"{steps:,} time steps (simulated time {scenario.duration:g} s / solver.dt "
            f"{dt:g} s) exceed the service's limit of {max_steps:,} (FLEXRIDE_MAX_STEPS)")],
            "scenario")

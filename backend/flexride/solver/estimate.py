"""What a run will cost, known before it runs: time steps, recorded points, channels, samples
and the size of the recorded results.

Computed from the scenario and a rigid build of the vehicle (milliseconds), so a service can
refuse work beyond its limits before anything expensive starts.
"""

from __future__ import annotations

from dataclasses import dataclass

from flexride.scenario.scenario import Scenario
from flexride.solver.assemble import channel_layout, output_rate_for
from flexride.vehicle.topology import build_vehicle, carbody_output_points

BYTES_PER_SAMPLE = 8
"""Bytes of one recorded value (float64, in memory and in the uncompressed results file)."""


@dataclass(frozen=True)
class RunEstimate:
    """Size of a run.

    Attributes
    ----------
    steps : int
        Time steps (duration / dt).
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

    steps: int
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


def count_steps(scenario: Scenario) -> int:
    """Time steps of ``scenario`` (as the solver rounds them)."""
    return round(scenario.duration / scenario.solver.dt)


def estimate_run(scenario: Scenario) -> RunEstimate:
    """The size of a run of ``scenario``.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario (its car-body points should be bounded first with
        :func:`count_output_points`: the rigid vehicle built here has one marker per point).

    Returns
    -------
    RunEstimate
    """
    steps = count_steps(scenario)
    ndec = max(1, round(1.0 / (scenario.solver.dt * output_rate_for(scenario))))
    samples = steps // ndec
    names, _units, _kinds = channel_layout(build_vehicle(scenario.vehicle, scenario.output),
                                           profiles=scenario.contact.geometry == "profiles")
    return RunEstimate(steps=steps, output_points=count_output_points(scenario),
                       channels=len(names), samples=samples,
                       result_bytes=len(names) * samples * BYTES_PER_SAMPLE)

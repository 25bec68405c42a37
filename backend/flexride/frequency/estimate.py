"""``estimate(scenario)``: linear model, response spectra and comfort table in one call — what
the CLI and a web route run (synchronously: a second or less for a rigid vehicle).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from flexride.frequency.comfort import ComfortTable, comfort
from flexride.frequency.errors import LinearisationError
from flexride.frequency.floor import FloorMap, floor_map, floor_scenario
from flexride.frequency.model import (
    DEFAULT_LINEARISATION,
    LinearisationMethod,
    LinearModel,
    linear_model,
)
from flexride.frequency.reduce import TrackModel
from flexride.frequency.response import ResponseSpectra, response
from flexride.frequency.track_input import STATIONARY_KINDS
from flexride.scenario.scenario import Scenario
from flexride.solver.simulate import small_dense_problems
from flexride.track.measured import LIBRARY, MeasuredSources
from flexride.vehicle.topology import VehicleModel

__all__ = ["Estimate", "estimate"]

NO_RANDOM = ("the scenario has no random irregularity to estimate the response to (use the "
             "time-domain solver)")
"""Why a scenario without a random irregularity has no estimate."""


@dataclass
class Estimate:
    """A frequency-domain estimate.

    Attributes
    ----------
    model : LinearModel
        The linearised model.
    response : ResponseSpectra
        The response PSDs.
    comfort : ComfortTable
        The comfort indices.
    floor : FloorMap or None
        The comfort map over the floor grid, when asked for.
    """

    model: LinearModel
    response: ResponseSpectra
    comfort: ComfortTable
    floor: FloorMap | None = None

    def to_dict(self, arrays: bool = False) -> dict[str, Any]:
        """JSON form: comfort table, model summary, rms per channel (PSDs with ``arrays``) and
        the floor map (``floor_map``) when there is one.
        """
        out = {"comfort": self.comfort.to_dict(), "model": self.model.to_dict(),
               "response": self.response.to_dict(arrays=arrays)}
        if self.floor is not None:
            out["floor_map"] = self.floor.to_dict()
        return out


def estimate(scenario: Scenario, points: Sequence[str] | None = None,
             track: TrackModel = "condensed", *, strict: bool = True,
             vehicle: VehicleModel | None = None,
             sources: MeasuredSources = LIBRARY, floor_grid_m: float | None = None,
             linearisation: LinearisationMethod = DEFAULT_LINEARISATION) -> Estimate:
    """Frequency-domain comfort estimate of ``scenario``.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario with a random irregularity.
    points : sequence of str, optional
        Points (default every car-body point; with ``floor_grid_m`` but the grid's).
    track : {"condensed", "modal", "rigid"}
        Track model.
    strict : bool
        See :func:`~flexride.frequency.model.linear_model`.
    vehicle : VehicleModel, optional
        Prebuilt vehicle.
    sources : MeasuredSources
        Where uploaded wheel and rail profiles are read from (default: files by path).
    floor_grid_m : float, optional
        Also map the comfort over the floor grid of this spacing (m; ``Estimate.floor``,
        :mod:`flexride.frequency.floor`). Not with a prebuilt ``vehicle``.
    linearisation : {"statistical", "local"}
        How the contact is linearised (:func:`~flexride.frequency.model.linear_model`).

    Raises
    ------
    LinearisationError
        The linear estimate does not hold (reason in the message).
    """
    if not any(e.kind in STATIONARY_KINDS for e in scenario.excitation) and (
            not strict or not scenario.excitation):
        raise LinearisationError(NO_RANDOM, "excitation")  # before building a model
    if floor_grid_m is not None:
        scenario = floor_scenario(scenario, floor_grid_m)
    with small_dense_problems():
        model = linear_model(scenario, track, vehicle=vehicle, strict=strict, sources=sources,
                             linearisation=linearisation)
        if model.spectra is None:  # nothing random to respond to
            raise LinearisationError(NO_RANDOM, "excitation")
        if points is None and floor_grid_m is not None:  # the grid is in the floor map
            points = [p.name for p in model.points if p.body == "carbody" and p.kind != "grid"]
        resp = response(model, points=points)
        floor = floor_map(model) if floor_grid_m is not None else None
        return Estimate(model, resp, comfort(resp), floor)

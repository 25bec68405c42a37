"""``estimate(scenario)``: linear model, response spectra and comfort table in one call — what
the CLI and a web route run (synchronously: a second or less for a rigid vehicle).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from flexride.frequency.comfort import ComfortTable, comfort
from flexride.frequency.errors import LinearisationError
from flexride.frequency.model import LinearModel, linear_model
from flexride.frequency.reduce import TrackModel
from flexride.frequency.response import ResponseSpectra, response
from flexride.scenario.scenario import Scenario
from flexride.solver.simulate import small_dense_problems
from flexride.track.measured import LIBRARY, MeasuredSources
from flexride.vehicle.topology import VehicleModel

__all__ = ["Estimate", "estimate"]


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
    """

    model: LinearModel
    response: ResponseSpectra
    comfort: ComfortTable

    def to_dict(self, arrays: bool = False) -> dict[str, Any]:
        """JSON form: comfort table, model summary, rms per channel (PSDs with ``arrays``)."""
        return {"comfort": self.comfort.to_dict(), "model": self.model.to_dict(),
                "response": self.response.to_dict(arrays=arrays)}


def estimate(scenario: Scenario, points: Sequence[str] | None = None,
             track: TrackModel = "condensed", *, strict: bool = True,
             vehicle: VehicleModel | None = None,
             sources: MeasuredSources = LIBRARY) -> Estimate:
    """Frequency-domain comfort estimate of ``scenario``.

    Parameters
    ----------
    scenario : Scenario
        Validated scenario with a random irregularity.
    points : sequence of str, optional
        Points (default every car-body point).
    track : {"condensed", "modal", "rigid"}
        Track model.
    strict : bool
        See :func:`~flexride.frequency.model.linear_model`.
    vehicle : VehicleModel, optional
        Prebuilt vehicle.
    sources : MeasuredSources
        Where uploaded wheel and rail profiles are read from (default: files by path).

    Raises
    ------
    LinearisationError
        The linear estimate does not hold (reason in the message).
    """
    with small_dense_problems():
        model = linear_model(scenario, track, vehicle=vehicle, strict=strict, sources=sources)
        if model.spectra is None:  # nothing random to respond to (no excitation at all)
            raise LinearisationError("the scenario has no random irregularity to estimate the "
                                     "response to (use the time-domain solver)", "excitation")
        resp = response(model, points=points)
        return Estimate(model, resp, comfort(resp))

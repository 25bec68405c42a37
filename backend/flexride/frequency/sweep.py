"""``sweep(scenario, parameter_path, values)``: the comfort estimate over values of one
scenario field (dotted path, as ``--set`` takes it: ``speed_kmh``,
``vehicle.secondary.kz``…). Per value the scenario is re-validated and its linear model rebuilt
reusing what the value does not change (:mod:`flexride.frequency.rebuild`: contact tables,
the previous steady state as the start of the next, the Jacobians but for the rows and columns
of a changed suspension element, the track condensation); the results equal a rebuild from
scratch (``reuse=False``) to rounding. A vehicle with flexible bodies is built once unless the
path changes the vehicle, its bodies or its output points.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.errors import FlexrideError
from flexride.frequency.comfort import ComfortTable, comfort
from flexride.frequency.estimate import estimate
from flexride.frequency.model import DEFAULT_LINEARISATION, LinearisationMethod
from flexride.frequency.rebuild import ModelRebuilder
from flexride.frequency.reduce import TrackModel
from flexride.frequency.response import response
from flexride.scenario.scenario import Scenario, apply_overrides, scenario_from_dict
from flexride.solver.assemble import vehicle_for
from flexride.solver.simulate import small_dense_problems
from flexride.track.measured import LIBRARY, MeasuredSources
from flexride.vehicle.topology import VehicleModel

__all__ = ["SweepResult", "sweep", "sweep_scenarios"]

_VEHICLE_PATHS = ("vehicle", "bodies", "output")


@dataclass
class SweepResult:
    """Comfort estimates over the values of one parameter.

    Attributes
    ----------
    parameter : str
        Dotted path of the field.
    values : list
        The values, in order.
    tables : list of ComfortTable or None
        One per value (None where the estimate was refused).
    errors : list of str or None
        Why a value was refused (its :class:`LinearisationError` or scenario error).
    reasons : list of str or None
        The refusal's key (:attr:`LinearisationError.reason`, else the error's class name).
    seconds : float
        Wall time of the whole sweep (s).
    reuse : dict of str to int
        What the rebuilds reused and what they made anew
        (:attr:`flexride.frequency.rebuild.ModelRebuilder.stats`; empty without reuse).
    """

    parameter: str
    values: list[Any]
    tables: list[ComfortTable | None]
    errors: list[str | None] = field(default_factory=list)
    reasons: list[str | None] = field(default_factory=list)
    seconds: float = 0.0
    reuse: dict[str, int] = field(default_factory=dict)

    def series(self, point: str, direction: str, quantity: str = "sperling") -> list[float | None]:
        """One index against the values: ``quantity`` a field of DirectionComfort (``rms``,
        ``sperling``, ``sperling_filter``, ``a_p95``, ``peak``) or an ISO weighting name.
        """
        out: list[float | None] = []
        for t in self.tables:
            if t is None:
                out.append(None)
                continue
            d = t.point(point).directions[direction]
            out.append(d.iso[quantity] if quantity in d.iso else getattr(d, quantity))
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        return {"parameter": self.parameter, "values": list(self.values),
                "tables": [t.to_dict() if t is not None else None for t in self.tables],
                "errors": list(self.errors), "reasons": list(self.reasons),
                "seconds": self.seconds, "reuse": dict(self.reuse)}


def sweep(scenario: Scenario, parameter_path: str, values: Sequence[Any],
          points: Sequence[str] | None = None, track: TrackModel = "condensed", *,
          strict: bool = True, reuse: bool = True,
          sources: MeasuredSources = LIBRARY,
          linearisation: LinearisationMethod = DEFAULT_LINEARISATION) -> SweepResult:
    """Estimate the comfort of ``scenario`` with ``parameter_path`` set to each of ``values``.

    Parameters
    ----------
    scenario : Scenario
        The base scenario.
    parameter_path : str
        Dotted path of the field (``vehicle.secondary.kz``).
    values : sequence
        Its values (in the field's units).
    points : sequence of str, optional
        Points (default every car-body point).
    track : {"condensed", "modal", "rigid"}
        Track model.
    strict : bool
        See :func:`~flexride.frequency.model.linear_model`.
    reuse : bool
        Rebuild reusing what a value does not change (default); False rebuilds every model
        from scratch (:func:`~flexride.frequency.estimate.estimate`, the reference).
    sources : MeasuredSources
        Where uploaded profiles are read from.
    linearisation : {"statistical", "local"}
        How the contact is linearised (:func:`~flexride.frequency.model.linear_model`).

    Raises
    ------
    ScenarioError
        The path or a value makes an invalid scenario (located message).
    """
    data = scenario.model_dump(mode="json")
    scenarios = [scenario_from_dict(apply_overrides(data, {parameter_path: v}),
                                    source=f"{parameter_path} = {v!r}") for v in values]
    vehicle_reusable = parameter_path.split(".")[0] not in _VEHICLE_PATHS
    return sweep_scenarios(scenarios, parameter_path, list(values), points, track,
                           strict=strict, reuse=reuse, sources=sources,
                           share_vehicle=vehicle_reusable, linearisation=linearisation)


def sweep_scenarios(scenarios: Sequence[Scenario], parameter: str, values: list[Any],
                    points: Sequence[str] | None = None, track: TrackModel = "condensed", *,
                    strict: bool = True, reuse: bool = True,
                    sources: MeasuredSources = LIBRARY,
                    share_vehicle: bool = False,
                    linearisation: LinearisationMethod = DEFAULT_LINEARISATION) -> SweepResult:
    """The comfort estimates of ``scenarios`` (validated, one per value of ``parameter``), in
    order; a refused value gives None and its reason.

    Parameters
    ----------
    scenarios : sequence of Scenario
        The scenarios, one per value.
    parameter : str
        Dotted path of the swept field (for the result).
    values : list
        Its values (for the result).
    points, track, strict, reuse, sources, linearisation :
        See :func:`sweep`.
    share_vehicle : bool
        The scenarios have the same vehicle (built once when it has flexible bodies).
    """
    t0 = time.perf_counter()
    vehicle = _shared_vehicle(scenarios[0]) if share_vehicle and scenarios else None
    rebuilder = ModelRebuilder(track, strict, sources, linearisation) if reuse else None
    tables: list[ComfortTable | None] = []
    errors: list[str | None] = []
    reasons: list[str | None] = []
    with small_dense_problems():
        for sc in scenarios:
            try:
                if rebuilder is None:
                    tables.append(estimate(sc, points, track, strict=strict, vehicle=vehicle,
                                           sources=sources,
                                           linearisation=linearisation).comfort)
                else:
                    tables.append(comfort(response(rebuilder.model(sc, vehicle),
                                                   points=points)))
                errors.append(None)
                reasons.append(None)
            except (FlexrideError, np.linalg.LinAlgError) as err:
                tables.append(None)
                errors.append(str(err) if isinstance(err, FlexrideError) else
                              f"the linearised system is singular ({err})")
                reasons.append(getattr(err, "reason", type(err).__name__))
    stats = dict(rebuilder.stats) if rebuilder is not None else {}
    return SweepResult(parameter, values, tables, errors, reasons, time.perf_counter() - t0,
                       stats)


def _shared_vehicle(scenario: Scenario) -> VehicleModel | None:
    """The vehicle of ``scenario`` when it has flexible bodies (worth building once)."""
    elastic = any(getattr(scenario.bodies, b).elastic for b in ("carbody", "frames"))
    return vehicle_for(scenario) if elastic else None

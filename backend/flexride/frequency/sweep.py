"""``sweep(scenario, parameter_path, values)``: the comfort estimate over values of one
scenario field (dotted path, as ``--set`` takes it: ``speed_kmh``,
``vehicle.secondary.kz``…). Per value the scenario is re-validated and the linear model
rebuilt (assembly, steady state, Jacobians, condensation, modes); a vehicle with flexible
bodies is reused unless the path changes the vehicle, its bodies or its output points.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from flexride.errors import FlexrideError
from flexride.frequency.comfort import ComfortTable
from flexride.frequency.estimate import estimate
from flexride.frequency.reduce import TrackModel
from flexride.scenario.scenario import Scenario, apply_overrides, scenario_from_dict
from flexride.solver.assemble import vehicle_for

__all__ = ["SweepResult", "sweep"]

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
    seconds : float
        Wall time of the whole sweep (s).
    """

    parameter: str
    values: list[Any]
    tables: list[ComfortTable | None]
    errors: list[str | None] = field(default_factory=list)
    seconds: float = 0.0

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
                "errors": list(self.errors), "seconds": self.seconds}


def sweep(scenario: Scenario, parameter_path: str, values: Sequence[Any],
          points: Sequence[str] | None = None, track: TrackModel = "condensed") -> SweepResult:
    """Estimate the comfort of ``scenario`` with ``parameter_path`` set to each of ``values``.

    Raises
    ------
    ScenarioError
        The path or a value makes an invalid scenario (located message).
    """
    t0 = time.perf_counter()
    data = scenario.model_dump(mode="json")
    reuse = parameter_path.split(".")[0] not in _VEHICLE_PATHS
    flexible = any(getattr(scenario.bodies, b).model == "flexible" for b in ("carbody", "frames"))
    vehicle = vehicle_for(scenario) if reuse and flexible else None
    tables: list[ComfortTable | None] = []
    errors: list[str | None] = []
    for v in values:
        sc = scenario_from_dict(apply_overrides(data, {parameter_path: v}),
                                source=f"{parameter_path} = {v!r}")
        try:
            tables.append(estimate(sc, points, track, vehicle=vehicle).comfort)
            errors.append(None)
        except FlexrideError as err:
            tables.append(None)
            errors.append(str(err))
    return SweepResult(parameter_path, list(values), tables, errors, time.perf_counter() - t0)

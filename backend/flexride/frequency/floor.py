"""Whole-floor comfort maps from the estimate: the comfort indices at every point of the car
body's floor grid, the grid the time-domain runs record for their comfort maps
(``output.floor_grid_spacing_m``, points ``F<i>_<j>`` of
:func:`flexride.vehicle.topology.floor_grid`).

The grid's points are outputs of the same linear model as the paper's points (adding outputs
does not change the system), so a grid point's indices are those of the same point asked for
by itself.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from flexride.errors import ScenarioError
from flexride.frequency.comfort import ComfortTable, comfort
from flexride.frequency.model import LinearModel
from flexride.frequency.response import response
from flexride.scenario.scenario import Scenario, scenario_from_dict
from flexride.vehicle.topology import RecordedPoint, carbody_output_points

__all__ = ["FloorMap", "floor_map", "floor_scenario"]

#: Where a floor-grid problem points in a scenario.
SPACING_PATH = ("output", "floor_grid_spacing_m")


@dataclass
class FloorMap:
    """Comfort indices over the car body's floor grid.

    Attributes
    ----------
    spacing_m : float
        Grid spacing (m).
    x_m : numpy.ndarray
        (n_x,) positions along the body from its centre, forward positive (m).
    y_m : numpy.ndarray
        (n_y,) positions across, left positive (m).
    names : list of list of str
        [n_y][n_x] point names (``F<i>_<j>``).
    table : ComfortTable
        The comfort table of the grid's points.
    marked : list of RecordedPoint
        The other floor points of the vehicle (the paper's, the user's), for reference.
    """

    spacing_m: float
    x_m: np.ndarray
    y_m: np.ndarray
    names: list[list[str]]
    table: ComfortTable
    marked: list[RecordedPoint]

    def values(self, key: str, direction: str) -> np.ndarray:
        """(n_y, n_x) one index over the grid: ``rms``, ``sperling``, ``sperling_filter``,
        ``a_p95``, ``peak`` (m/s² but the Sperling indices) or an ISO weighting (``Wb``,
        ``Wk`` for z, ``Wd`` for y; m/s²), in ``direction`` ``"y"`` or ``"z"``.
        """
        def one(name: str) -> float:
            d = self.table.point(name).directions[direction]
            return float(d.iso[key] if key in d.iso else getattr(d, key))

        return np.array([[one(n) for n in row] for row in self.names])

    def nmv(self) -> np.ndarray:
        """(n_y, n_x) EN 12299 mean comfort N_MV over the grid (-)."""
        return np.array([[self.table.point(n).nmv for n in row] for row in self.names],
                        dtype=float)

    def to_dict(self) -> dict[str, Any]:
        """JSON form: axes, names and per direction the rms, ISO 2631 weighted rms (Wb z, Wd
        y) and Sperling index as [n_y][n_x] arrays, N_MV, the marked points.
        """
        iso = self.table.settings["iso"]
        out: dict[str, Any] = {
            "spacing_m": self.spacing_m, "x_m": self.x_m.tolist(), "y_m": self.y_m.tolist(),
            "names": self.names, "layout": "[y index][x index]",
            "weightings": {d: iso[d][0] for d in ("z", "y")},
            "indices": {}, "nmv": self.nmv().tolist(),
            "units": {"rms": "m/s^2", "iso2631": "m/s^2", "sperling": "-", "nmv": "-"},
            "points": [{"name": p.name, "description": p.description, "x": p.x, "y": p.y}
                       for p in self.marked]}
        for d in ("z", "y"):
            out["indices"][d] = {"rms": self.values("rms", d).tolist(),
                                 "iso2631": self.values(iso[d][0], d).tolist(),
                                 "sperling": self.values("sperling", d).tolist()}
        return out


def floor_scenario(scenario: Scenario, spacing_m: float) -> Scenario:
    """``scenario`` recording the floor grid of spacing ``spacing_m`` (m), validated as a
    scenario is.

    Raises
    ------
    ScenarioError
        The spacing is out of the scenario field's range, or a grid point's name is taken by a
        user point; located at ``output.floor_grid_spacing_m``.
    """
    data = scenario.model_dump(mode="json")
    data["output"]["floor_grid_spacing_m"] = spacing_m
    out = scenario_from_dict(data)
    try:
        carbody_output_points(out.vehicle, out.output)
    except ValueError as err:
        raise ScenarioError.at(SPACING_PATH, str(err)) from None
    return out


def floor_map(model: LinearModel) -> FloorMap:
    """The comfort map over the floor grid of ``model``'s scenario.

    Parameters
    ----------
    model : LinearModel
        The linear model of a scenario with a floor grid (:func:`floor_scenario`).

    Returns
    -------
    FloorMap

    Raises
    ------
    ScenarioError
        The scenario records no floor grid.
    """
    grid = [p for p in model.points if p.body == "carbody" and p.kind == "grid"]
    if not grid:
        raise ScenarioError.at(SPACING_PATH, "the scenario records no floor grid: set "
                               "output.floor_grid_spacing_m (floor_scenario)")
    xs = np.unique([p.x for p in grid])
    ys = np.unique([p.y for p in grid])
    names = [[""] * xs.size for _ in ys]
    for p in grid:
        names[int(np.searchsorted(ys, p.y))][int(np.searchsorted(xs, p.x))] = p.name
    table = comfort(response(model, points=[p.name for p in grid]))
    marked = [p for p in model.points
              if p.body == "carbody" and p.on_floor and p.kind != "grid"]
    spacing = model.scenario.output.floor_grid_spacing_m
    return FloorMap(float(spacing or 0.0), xs, ys, names, table, marked)

"""The paper's element-size pre-calculation (§2.1, Fig. 4) in the report: the runs of
:func:`flexride.paper.plan.mesh_plan` read as a mesh-convergence study
(:func:`flexride.study.mesh_convergence.mesh_convergence_tables`, the service's tables), Fig. 4's
counterpart (the air-spring forces against element size with their extrapolated values) and the
claim that the force grows as the element grows and that 0.2 m is adequate.
"""

from __future__ import annotations

from typing import Any

from flexride.paper.data import NotComparable, StudyData
from flexride.scenario.presets import SMOOTH_CONDITION
from flexride.study.mesh_convergence import CARBODY_MESH_AXIS, mesh_convergence_tables

__all__ = ["fig4_panels", "mesh_tables", "smooth_table"]

_SHOWN = ((".z.max_abs", "largest value (static + dynamic)"),
          (".z.rms_dynamic", "rms of the dynamic part"))


def mesh_tables(data: StudyData) -> list[dict[str, Any]]:
    """The pre-calculation's tables, one per track (smooth first), from the study's records.

    Raises
    ------
    NotComparable
        The study has no pre-calculation runs on at least two meshes.
    """
    jobs = []
    for rec in data.mesh_records:
        spec, run = rec["spec"], rec.get("run") or {}
        jobs.append({"axes": {"condition": spec["condition"], "speed_kmh": spec["speed_kmh"],
                              CARBODY_MESH_AXIS: spec["element_size_m"]},
                     "summary": rec.get("summary"),
                     "run_meta": {"flexible_bodies": run.get("flexible_bodies") or {}}})
    tables = mesh_convergence_tables(jobs)
    if not tables:
        raise NotComparable("no element-size pre-calculation in this study (mesh sizes: none)")
    return sorted(tables, key=lambda t: t["group"].get("condition") != SMOOTH_CONDITION)


def smooth_table(data: StudyData) -> dict[str, Any]:
    """The smooth track's table (the paper's pre-calculation); NotComparable without it."""
    table = mesh_tables(data)[0]
    if table["group"].get("condition") != SMOOTH_CONDITION:
        raise NotComparable("the smooth-track runs of the pre-calculation are missing")
    return table


def _force_traces(table: dict[str, Any], suffix: str) -> list[dict[str, Any]]:
    sizes = table["sizes_m"]
    traces = []
    for row in (r for r in table["rows"] if r["key"].endswith(suffix)):
        name = row["key"].split(".")[1]
        traces.append({"type": "scatter", "mode": "lines+markers", "x": sizes,
                       "y": row["values"], "name": f"air spring {name}"})
        best = (row["estimate"] or {}).get("converged")
        if best is not None and not row.get("negligible"):
            traces.append({"type": "scatter", "mode": "lines", "x": [0.0, sizes[-1]],
                           "y": [best, best], "name": f"{name} converged estimate",
                           "line": {"dash": "dot", "width": 1}, "showlegend": False})
    return traces


def fig4_panels(data: StudyData) -> list[dict[str, Any]]:
    """Fig. 4's counterpart: per track, the air springs' vertical force against the car body's
    element size — its largest value (static + dynamic: the paper's "suspension force") and the
    rms of its dynamic part — each with its converged estimate (dotted) where it is above the
    resolution (:mod:`flexride.study.mesh_verdict`).
    """
    panels = []
    for table in mesh_tables(data):
        cond = table["group"].get("condition")
        for suffix, what in _SHOWN:
            panels.append({
                "title": f"{cond}: air-spring vertical force, {what}",
                "data": _force_traces(table, suffix),
                "layout": {"xaxis": {"title": {"text": "car-body element size (m)"},
                                     "rangemode": "tozero"},
                           "yaxis": {"title": {"text": f"{what} (N)"}},
                           "margin": {"t": 30}}})
    return panels

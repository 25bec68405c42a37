"""Study results as tables ready to plot, from the stored job summaries.

The summaries are those of :meth:`flexride.analysis.Summary.to_dict`:

* ``sperling_vs_speed`` — Sperling index (default form) against speed, per group of the other
  axes (condition, body model, parameters), point and direction;
* ``peak_vs_speed`` — largest |acceleration| against speed with its least-squares line and R²
  (the paper's Fig. 21);
* ``flexible_vs_rigid`` — per case, point and direction: Sperling index, ISO weighted rms,
  rms and peak of the flexible and the rigid model, their difference and ratio (Table 2).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from flexride.analysis import linear_regression
from flexride.errors import AnalysisError

_FIRST_WEIGHTING = {"z": "Wb", "y": "Wd", "x": "Wd"}
_UNITS = {"sperling": "-", "peak": "m/s^2", "rms": "m/s^2", "a_w": "m/s^2"}
_COMPARED = ("sperling", "a_w", "rms", "peak")


def summary_value(summary: dict[str, Any] | None, point: str, direction: str,
                  quantity: str) -> float | None:
    """One number of a summary dict: ``sperling``, ``peak`` (max |a|), ``rms`` or ``a_w``
    (ISO 2631 weighted rms, Wb for z, Wd for y); None when absent.
    """
    try:
        d = summary["points"][point]["directions"][direction]  # type: ignore[index]
        if quantity == "sperling":
            v = d["sperling"]["value"] if d.get("sperling") else None
        elif quantity == "peak":
            v = d["peaks"]["max_abs"]
        elif quantity == "rms":
            v = d["peaks"]["rms"]
        elif quantity == "a_w":
            v = d["iso2631"][_FIRST_WEIGHTING[direction]]["a_w"]
        else:
            raise ValueError(f"unknown quantity {quantity!r}")
    except (KeyError, TypeError):
        return None
    if v is None:
        return None
    v = float(v)
    return v if math.isfinite(v) else None


def _points(summaries: Sequence[dict[str, Any]]) -> list[tuple[str, str]]:
    seen: dict[tuple[str, str], None] = {}
    for s in summaries:
        for p, ps in (s.get("points") or {}).items():
            for d in ps.get("directions") or {}:
                seen[(p, d)] = None
    return list(seen)


def _group_key(axes: dict[str, Any], drop: str) -> tuple:
    return tuple((k, v) for k, v in axes.items() if k != drop)


def _fit(x: list[float], y: list[float | None], unit: str) -> dict[str, Any] | None:
    pts = [(a, b) for a, b in zip(x, y, strict=True) if b is not None]
    if len({a for a, _ in pts}) < 2:
        return None
    try:
        f = linear_regression([a for a, _ in pts], [b for _, b in pts], x_unit="km/h",
                              y_unit=unit)
    except AnalysisError:
        return None

    def num(v: float) -> float | None:
        return v if math.isfinite(v) else None

    return {"slope": num(f.slope), "intercept": num(f.intercept), "r_squared": num(f.r_squared),
            "n": f.n, "stderr_slope": num(f.stderr_slope),
            "stderr_intercept": num(f.stderr_intercept), "x_unit": "km/h", "y_unit": unit}


def _speed_series(jobs: Sequence[dict[str, Any]], quantity: str,
                  with_fit: bool) -> list[dict[str, Any]]:
    groups: dict[tuple, list[dict[str, Any]]] = {}
    for j in jobs:
        groups.setdefault(_group_key(j["axes"], "speed_kmh"), []).append(j)
    out = []
    for key, members in groups.items():
        members = sorted(members, key=lambda j: j["speed_kmh"])
        for point, direction in _points([m["summary"] for m in members]):
            if quantity == "sperling" and direction == "x":
                continue
            values = [summary_value(m["summary"], point, direction, quantity) for m in members]
            if all(v is None for v in values):
                continue
            speeds = [float(m["speed_kmh"]) for m in members]
            row = {"group": dict(key), "point": point, "direction": direction,
                   "quantity": quantity, "unit": _UNITS[quantity], "speed_kmh": speeds,
                   "value": values, "job_ids": [m["id"] for m in members], "fit": None}
            if with_fit:
                row["fit"] = _fit(speeds, values, _UNITS[quantity])
            out.append(row)
    return out


def _flex_rigid(jobs: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    pairs: dict[tuple, dict[str, dict[str, Any]]] = {}
    for j in jobs:
        model = j["axes"].get("body_model")
        if model in ("rigid", "flexible"):
            pairs.setdefault(_group_key(j["axes"], "body_model"), {})[model] = j
    rows = []
    for key, pair in pairs.items():
        if set(pair) != {"rigid", "flexible"}:
            continue
        r, f = pair["rigid"], pair["flexible"]
        for point, direction in _points([r["summary"], f["summary"]]):
            for q in _COMPARED:
                if q == "sperling" and direction == "x":
                    continue
                a = summary_value(r["summary"], point, direction, q)
                b = summary_value(f["summary"], point, direction, q)
                if a is None and b is None:
                    continue
                diff = b - a if a is not None and b is not None else None
                rel = diff / a if diff is not None and a not in (None, 0.0) else None
                rows.append({"group": dict(key), "speed_kmh": r["speed_kmh"], "point": point,
                             "direction": direction, "quantity": q, "rigid": a, "flexible": b,
                             "difference": diff, "relative": rel, "rigid_job": r["id"],
                             "flexible_job": f["id"]})
    return rows


def study_tables(jobs: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Tables of a study from its jobs.

    Parameters
    ----------
    jobs : sequence of dict
        One per job: ``id``, ``axes`` (axis name → value), ``speed_kmh``, ``status`` and
        ``summary`` (the analysis summary dict, or None). Jobs that did not succeed or have no
        usable summary are left out (named in ``notes``).

    Returns
    -------
    dict
        ``sperling_vs_speed``, ``peak_vs_speed``, ``flexible_vs_rigid`` and ``notes``.
    """
    usable, notes = [], []
    for j in jobs:
        s = j.get("summary")
        if j.get("status") != "succeeded":
            continue
        if not s or "points" not in s:
            notes.append(f"job {j['id']}: no analysis summary ({(s or {}).get('error', '')})")
            continue
        if j.get("speed_kmh") is None:
            notes.append(f"job {j['id']}: no speed")
            continue
        usable.append(j)
    pending = sum(1 for j in jobs if j.get("status") in ("queued", "running"))
    if pending:
        notes.append(f"{pending} job(s) not finished yet: tables are partial")
    if any(j.get("summary") and not summary_value(j["summary"], "PC", "z", "sperling")
           for j in usable):
        notes.append("Sperling indices need at least 5 s of simulated time")
    return {
        "sperling_vs_speed": _speed_series(usable, "sperling", with_fit=False),
        "peak_vs_speed": _speed_series(usable, "peak", with_fit=True),
        "flexible_vs_rigid": _flex_rigid(usable),
        "notes": notes,
    }

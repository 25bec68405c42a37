"""Study results as tables ready to plot, from the stored job summaries.

The summaries are those of :meth:`flexride.analysis.Summary.to_dict`:

* ``sperling_vs_speed`` — Sperling index (default form) against speed, per group of the other
  axes (condition, body model, parameters), point and direction;
* ``peak_vs_speed`` — largest |acceleration| against speed with its least-squares line and R²
  (the paper's Fig. 21);
* ``flexible_vs_rigid`` — per case, point and direction: Sperling index, ISO weighted rms,
  rms and peak of the flexible and the rigid model, their difference and ratio (Table 2);
* ``mesh_convergence`` — for a study with an element-size axis: each quantity (air-spring
  forces, elastic frequencies, comfort indices) against element size with its convergence
  estimate and the paper's Fig. 4 claim judged (:mod:`flexride.study.mesh_convergence`).

Each job's indices are those of its evaluated section (``summary["section"]``,
:mod:`flexride.study.sections`) where it has one, else of the whole run; every row states it
(``sections`` per speed, ``section`` of a flexible/rigid row).

With a ``seed`` axis (irregularity realisations) every value is the mean over the
realisations with the half width of its 95 % confidence interval (``ci95``, Student t:
:func:`flexride.paper.measures.mean_ci`, the paper report's; None for one realisation) and the
number of realisations ``n``; the fit is made on the means, the flexible/rigid difference and
ratio realisation by realisation (same track) and then averaged.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from flexride.analysis import linear_regression
from flexride.errors import AnalysisError
from flexride.study.mesh_convergence import mesh_convergence_tables
from flexride.study.seeds import SEED_AXIS
from flexride.study.summary_values import summary_value

_UNITS = {"sperling": "-", "peak": "m/s^2", "rms": "m/s^2", "a_w": "m/s^2"}
_COMPARED = ("sperling", "a_w", "rms", "peak")


def _points(summaries: Sequence[dict[str, Any]]) -> list[tuple[str, str]]:
    seen: dict[tuple[str, str], None] = {}
    for s in summaries:
        for p, ps in (s.get("points") or {}).items():
            for d in ps.get("directions") or {}:
                seen[(p, d)] = None
    return list(seen)


def _group_key(axes: dict[str, Any], drop: str) -> tuple:
    return tuple((k, v) for k, v in axes.items() if k not in (drop, SEED_AXIS))


def _estimate(values: Sequence[float | None]) -> tuple[float | None, float | None, int]:
    """Mean, 95 % CI half width (None for fewer than two values) and count of the values
    that are not None (None, None, 0 when there are none).
    """
    # imported here: flexride.paper imports flexride.study (plan: the seeds' rule)
    from flexride.paper.measures import mean_ci

    present = [v for v in values if v is not None]
    if not present:
        return None, None, 0
    e = mean_ci(present)
    ci = e.ci95 if e.ci95 is not None and math.isfinite(e.ci95) else None
    return e.mean, ci, e.n


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
        by_speed: dict[float, list[dict[str, Any]]] = {}
        for m in sorted(members, key=lambda j: (j["speed_kmh"], j["axes"].get(SEED_AXIS, 0))):
            by_speed.setdefault(float(m["speed_kmh"]), []).append(m)
        for point, direction in _points([m["summary"] for m in members]):
            if quantity == "sperling" and direction == "x":
                continue
            row = _series_row(dict(key), point, direction, quantity, by_speed)
            if row is None:
                continue
            if with_fit:
                row["fit"] = _fit(row["speed_kmh"], row["value"], _UNITS[quantity])
            out.append(row)
    return out


def _series_row(group: dict[str, Any], point: str, direction: str, quantity: str,
                by_speed: dict[float, list[dict[str, Any]]]) -> dict[str, Any] | None:
    """One series: per speed the mean, CI and count over the realisations, the first job
    (``job_ids``), every job (``jobs``) and each job's own value (``job_values``).
    """
    job_values = {m["id"]: summary_value(m["summary"], point, direction, quantity)
                  for ms in by_speed.values() for m in ms}
    if all(v is None for v in job_values.values()):
        return None
    est = [_estimate([job_values[m["id"]] for m in ms]) for ms in by_speed.values()]
    return {"group": group, "point": point, "direction": direction, "quantity": quantity,
            "unit": _UNITS[quantity], "speed_kmh": list(by_speed),
            "value": [e[0] for e in est], "ci95": [e[1] for e in est], "n": [e[2] for e in est],
            "sections": [ms[0]["section"] for ms in by_speed.values()],
            "job_ids": [ms[0]["id"] for ms in by_speed.values()],
            "jobs": [[m["id"] for m in ms] for ms in by_speed.values()],
            "job_values": job_values, "fit": None}


def _flex_rigid(jobs: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    pairs: dict[tuple, dict[str, dict[str, Any]]] = {}
    for j in jobs:
        model = j["axes"].get("body_model")
        if model in ("rigid", "flexible"):
            key = tuple((k, v) for k, v in j["axes"].items() if k != "body_model")
            pairs.setdefault(key, {})[model] = j
    cases: dict[tuple, list[dict[str, dict[str, Any]]]] = {}
    for key, pair in sorted(pairs.items(), key=lambda kv: dict(kv[0]).get(SEED_AXIS) or 0):
        if set(pair) == {"rigid", "flexible"}:
            case = tuple((k, v) for k, v in key if k != SEED_AXIS)
            cases.setdefault(case, []).append(pair)
    rows = []
    for case, seeds in cases.items():
        summaries = [p[m]["summary"] for p in seeds for m in ("rigid", "flexible")]
        for point, direction in _points(summaries):
            for q in _COMPARED:
                if q == "sperling" and direction == "x":
                    continue
                row = _flex_rigid_row(dict(case), seeds, point, direction, q)
                if row is not None:
                    rows.append(row)
    return rows


def _flex_rigid_row(group: dict[str, Any], seeds: list[dict[str, dict[str, Any]]], point: str,
                    direction: str, q: str) -> dict[str, Any] | None:
    """Flexible against rigid over the realisations of one case: means ± CI of both values,
    of their difference and of their ratio − 1 (each realisation on its own track).
    """
    a = [summary_value(p["rigid"]["summary"], point, direction, q) for p in seeds]
    b = [summary_value(p["flexible"]["summary"], point, direction, q) for p in seeds]
    if all(v is None for v in a + b):
        return None
    diff = [y - x if x is not None and y is not None else None for x, y in zip(a, b, strict=True)]
    rel = [d / x if d is not None and x not in (None, 0.0) else None
           for d, x in zip(diff, a, strict=True)]
    (ra, ra_ci, _), (fb, fb_ci, _) = _estimate(a), _estimate(b)
    (dm, d_ci, n), (rm, r_ci, _) = _estimate(diff), _estimate(rel)
    first = seeds[0]
    return {"group": group, "speed_kmh": first["rigid"]["speed_kmh"], "point": point,
            "direction": direction, "quantity": q, "rigid": ra, "flexible": fb,
            "difference": dm, "relative": rm, "rigid_ci95": ra_ci, "flexible_ci95": fb_ci,
            "difference_ci95": d_ci, "relative_ci95": r_ci, "n": n,
            "section": first["flexible"]["section"],
            "rigid_job": first["rigid"]["id"], "flexible_job": first["flexible"]["id"]}


def _evaluated(job: dict[str, Any]) -> dict[str, Any]:
    """The job with the summary of its evaluated section and the section's label."""
    sec = job["summary"].get("section") or {}
    if isinstance(sec.get("summary"), dict) and "points" in sec["summary"]:
        return {**job, "summary": sec["summary"], "section": sec.get("label", "section")}
    why = f" (section not analysed: {sec['error']})" if sec.get("error") else ""
    return {**job, "section": f"whole run{why}"}


def study_tables(jobs: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Tables of a study from its jobs.

    Parameters
    ----------
    jobs : sequence of dict
        One per job: ``id``, ``axes`` (axis name → value), ``speed_kmh``, ``status`` and
        ``summary`` (the analysis summary dict, or None), and ``run_meta`` (the run's
        metadata, optional: the mesh tables read the flexible bodies' frequencies from it).
        Jobs that did not succeed or have no usable summary are left out (named in ``notes``).

    Returns
    -------
    dict
        ``sperling_vs_speed``, ``peak_vs_speed``, ``flexible_vs_rigid``, ``mesh_convergence``
        (:func:`flexride.study.mesh_convergence.mesh_convergence_tables`: studies with an
        element-size axis) and ``notes``.
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
        usable.append(_evaluated(j))
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
        "mesh_convergence": mesh_convergence_tables(usable),
        "notes": notes,
    }

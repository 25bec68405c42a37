"""The response of the flexible vehicle against element size: the paper's element-size
pre-calculation (§2.1, Fig. 4) with a convergence verdict.

The paper runs the flexible vehicle on a smooth track with several car-body element sizes,
watches the secondary suspension force grow as the elements get coarser and chooses 0.2 m.
Here a study whose jobs differ in a body's element size (an axis
``bodies.carbody.element_size_m`` or ``bodies.frames.element_size_m``: the study preset
``mesh-convergence`` or any study with such a parameter axis) is read as such a pre-calculation:
for every group of jobs that differ only in that element size (and in the irregularity
realisation, averaged), and for every quantity —

* the air springs' forces (``summary["suspension"]``: the rms and the largest value of the
  dynamic part and the largest value of the whole force, vertical and lateral, per air spring),
* the body's lowest elastic frequencies by rank (``run_meta["flexible_bodies"]``),
* the comfort indices at the floor centre, above the front bogie and at the rear end (vertical
  and lateral Sperling index, vertical rms),

— the value on each mesh, and from the three finest meshes the observed order, the
Richardson-extrapolated value and the finest mesh's grid convergence index
(:func:`flexride.fem.convergence.three_mesh_estimate`; two meshes: the elements' order and
Roache's safety factor 3), the best estimate of the converged value (the extrapolated one where
the meshes converge monotonically at a usable order, else the finest mesh's value, with the
spread of the fine meshes as its band: :func:`size_estimate`) and the distance of each mesh's
value from it — so the study says "0.2 m is within x % of the converged value". The paper's
claim (the force grows as the element grows; 0.2 m is adequate) is judged from these rows in
:func:`flexride.study.mesh_verdict.paper_claim`.

Frequencies are taken by rank: on meshes that are not refinements of each other two close modes
can swap (``flexride fe convergence`` follows them by type; here the rank is what the run used).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from flexride.errors import FEModelError
from flexride.fem.convergence import ELEMENT_ORDER, three_mesh_estimate, two_mesh_estimate
from flexride.study.mesh_verdict import REFERENCE_SIZE_M, mark_negligible, paper_claim
from flexride.study.seeds import SEED_AXIS
from flexride.study.summary_values import summary_value

__all__ = ["CARBODY_MESH_AXIS", "MESH_AXES", "mesh_convergence_tables", "size_estimate",
           "study_request"]

CARBODY_MESH_AXIS = "bodies.carbody.element_size_m"
"""The study axis of the car body's element size."""
MESH_AXES: dict[str, str] = {CARBODY_MESH_AXIS: "carbody",
                             "bodies.frames.element_size_m": "frames"}
"""Study axes that are an element size, and the body each refines."""

N_FREQUENCIES = 3
"""Lowest elastic frequencies followed (by rank)."""

COMFORT_POINTS: tuple[str, ...] = ("PC", "PFB", "PR")
"""Points whose comfort indices are followed: floor centre, above the front bogie, rear end."""

_FORCE_DIRECTIONS: tuple[str, ...] = ("z", "y")
_FORCE_MEASURES: dict[str, str] = {"rms_dynamic": "rms of the dynamic part",
                                   "peak_dynamic": "largest dynamic value",
                                   "max_abs": "largest value (static + dynamic)"}
MIN_RELIABLE_ORDER = 0.5
"""Observed orders below this (-) make a Richardson extrapolation unreliable: the differences
between meshes hardly shrink, and the extrapolation runs far beyond the data (Eça and Hoekstra,
J. Comput. Phys. 262 (2014) 104, fall back to the data range there; so does
:func:`size_estimate`)."""

Getter = Callable[[dict[str, Any]], float | None]


@dataclass(frozen=True)
class Quantity:
    """One quantity followed against element size.

    Attributes
    ----------
    key : str
        Stable identifier (e.g. ``secondary.1L.z.rms_dynamic``, ``frequency.1``,
        ``PC.z.sperling``).
    group : {"force", "frequency", "comfort"}
        What it is.
    label : str
        Human-readable name.
    unit : str
        Unit of its values.
    value : callable
        ``value(job) -> float | None`` from a job dict (``summary``, ``run_meta``).
    """

    key: str
    group: str
    label: str
    unit: str
    value: Getter


def _finite(v: Any) -> float | None:
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if math.isfinite(f) else None


def _force(element: str, direction: str, measure: str) -> Getter:
    def get(job: dict[str, Any]) -> float | None:
        try:
            return _finite(job["summary"]["suspension"][element][direction][measure])
        except (KeyError, TypeError):
            return None
    return get


def _frequency(body: str, rank: int) -> Getter:
    def get(job: dict[str, Any]) -> float | None:
        bodies = (job.get("run_meta") or {}).get("flexible_bodies") or {}
        info = bodies.get(body)
        if info is None and body == "frames":  # per frame: the first one stands for both
            info = next((v for k, v in sorted(bodies.items()) if k.startswith("frame")), None)
        try:
            return _finite(info["elastic_frequencies_hz"][rank])  # type: ignore[index]
        except (IndexError, KeyError, TypeError):
            return None
    return get


def _comfort(point: str, direction: str, quantity: str) -> Getter:
    def get(job: dict[str, Any]) -> float | None:
        return summary_value(job.get("summary"), point, direction, quantity)
    return get


def quantities(jobs: Sequence[dict[str, Any]], body: str) -> list[Quantity]:
    """The quantities followed for ``body`` (module docs), those the jobs record."""
    elements = sorted({e for j in jobs for e in ((j.get("summary") or {}).get("suspension")
                                                 or {}) if e.startswith("secondary.")})
    out = [Quantity(f"{e}.{d}.{m}", "force",
                    f"air spring {e.split('.', 1)[1]} {d}: {_FORCE_MEASURES[m]}", "N",
                    _force(e, d, m))
           for e in elements for d in _FORCE_DIRECTIONS for m in _FORCE_MEASURES]
    out += [Quantity(f"frequency.{k + 1}", "frequency", f"{body}: elastic mode {k + 1}", "Hz",
                     _frequency(body, k)) for k in range(N_FREQUENCIES)]
    for p in COMFORT_POINTS:
        out += [Quantity(f"{p}.z.sperling", "comfort", f"{p} vertical Sperling index", "-",
                         _comfort(p, "z", "sperling")),
                Quantity(f"{p}.y.sperling", "comfort", f"{p} lateral Sperling index", "-",
                         _comfort(p, "y", "sperling")),
                Quantity(f"{p}.z.rms", "comfort", f"{p} vertical rms", "m/s^2",
                         _comfort(p, "z", "rms"))]
    return out


def size_estimate(sizes: Sequence[float], values: Sequence[float | None]
                  ) -> dict[str, Any] | None:
    """The discretisation estimate of one quantity over element sizes.

    Parameters
    ----------
    sizes : sequence of float
        Element sizes (m), any order, distinct.
    values : sequence of float or None
        The quantity on each (None: not available, left out).

    Returns
    -------
    dict or None
        :meth:`~flexride.fem.convergence.ConvergenceEstimate.to_dict` of the three finest
        meshes with a value (two: the elements' order assumed), and

        * ``reliable``: the extrapolation can be used — two meshes (the elements' order and
          Roache's factor 3), or three converging monotonically at an observed order of at
          least :data:`MIN_RELIABLE_ORDER`;
        * ``converged``: the best estimate of the converged value: the extrapolated one where
          reliable, else the finest mesh's;
        * ``band``: its relative uncertainty (-): the finest mesh's GCI where reliable, else
          the spread (largest − smallest) of the fine meshes over the finest value;
        * ``deviation``: each mesh's relative distance from ``converged`` (-,
          ``[[size, deviation], …]`` fine to coarse; None where it is zero).

        None with fewer than two values.
    """
    pairs = sorted((float(h), float(v)) for h, v in zip(sizes, values, strict=True)
                   if v is not None and math.isfinite(v))
    if len(pairs) < 2:
        return None
    fine = pairs[:3]
    hs, vs = [p[0] for p in fine], [p[1] for p in fine]
    try:
        est = (three_mesh_estimate(hs, vs) if len(fine) == 3
               else two_mesh_estimate(hs, vs, ELEMENT_ORDER))
    except FEModelError:
        return None
    out = est.to_dict()
    reliable = est.order_assumed or (not est.oscillatory and math.isfinite(est.order)
                                     and est.order >= MIN_RELIABLE_ORDER)
    best = est.extrapolated if reliable and math.isfinite(est.extrapolated) else vs[0]
    spread = (max(vs) - min(vs)) / abs(vs[0]) if vs[0] else math.inf
    band = est.gci_fine if reliable else spread
    out.update(reliable=reliable, converged=best,
               band=band if math.isfinite(band) else None,
               deviation=[[h, (v - best) / abs(best) if best else None] for h, v in pairs])
    return out


def _deviation_at(estimate: dict[str, Any] | None, size: float) -> float | None:
    for h, dev in (estimate or {}).get("deviation") or []:
        if math.isclose(h, size, rel_tol=1e-9):
            return dev
    return None


def _group(axes: dict[str, Any], axis: str) -> dict[str, Any]:
    """The other axes' values (the realisation left out: averaged)."""
    return {k: v for k, v in axes.items() if k not in (axis, SEED_AXIS)}


def _mean(values: list[float | None]) -> float | None:
    got = [v for v in values if v is not None]
    return sum(got) / len(got) if got else None


def _rows(jobs_by_size: dict[float, list[dict[str, Any]]], body: str) -> list[dict[str, Any]]:
    sizes = sorted(jobs_by_size)
    every = [j for js in jobs_by_size.values() for j in js]
    rows = []
    for q in quantities(every, body):
        values = [_mean([q.value(j) for j in jobs_by_size[h]]) for h in sizes]
        if all(v is None for v in values):
            continue
        est = size_estimate(sizes, values)
        rows.append({"key": q.key, "group": q.group, "label": q.label, "unit": q.unit,
                     "values": values, "estimate": est,
                     "at_reference": _deviation_at(est, REFERENCE_SIZE_M)})
    return rows


def mesh_convergence_tables(jobs: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """The element-size tables of a study's succeeded jobs (module docs).

    Parameters
    ----------
    jobs : sequence of dict
        One per usable job: ``axes`` (axis name → value), ``summary`` (the evaluated
        section's analysis summary) and ``run_meta`` (the run's metadata).

    Returns
    -------
    list of dict
        One per element-size axis and group of the other axes: ``body``, ``axis``,
        ``group`` (the other axes' values), ``sizes_m`` (fine to coarse), ``realisations``
        (jobs per size), ``reference_size_m``, ``rows`` (per quantity: ``key``, ``group``,
        ``label``, ``unit``, ``values`` per size — the mean over realisations —,
        ``estimate`` (:func:`size_estimate`), ``at_reference``: the reference mesh's
        relative distance from the converged estimate, and ``negligible``: why the row is
        too small to judge, or None: :func:`~flexride.study.mesh_verdict.mark_negligible`)
        and ``claim`` (:func:`~flexride.study.mesh_verdict.paper_claim`).
        Groups with fewer than two sizes are left out.
    """
    tables = []
    for axis, body in MESH_AXES.items():
        groups: dict[str, tuple[dict[str, Any], dict[float, list[dict[str, Any]]]]] = {}
        for j in jobs:
            size = _finite((j.get("axes") or {}).get(axis))
            if size is None:
                continue
            group = _group(j["axes"], axis)
            key = json.dumps(group, sort_keys=True, default=str)
            groups.setdefault(key, (group, {}))[1].setdefault(size, []).append(j)
        for group, by_size in groups.values():
            if len(by_size) < 2:
                continue
            rows = mark_negligible(_rows(by_size, body))
            sizes = sorted(by_size)
            tables.append({"body": body, "axis": axis, "group": group, "sizes_m": sizes,
                           "realisations": [len(by_size[h]) for h in sizes],
                           "reference_size_m": REFERENCE_SIZE_M, "rows": rows,
                           "claim": paper_claim(sizes, rows)})
    return tables


def study_request(body: str, sizes: list[float], conditions: list[str] | None = None,
                  speed_kmh: float | None = None) -> dict[str, Any]:
    """The ``mesh-convergence`` study preset's request with its element sizes (m) applied to
    ``body`` (``carbody`` or ``frames``), and optionally other conditions (names of
    :data:`flexride.scenario.presets.STUDY_CONDITIONS`) and speed (km/h).

    Raises
    ------
    ScenarioError
        Unknown body or condition name (the message lists the choices).
    """
    from flexride.errors import ScenarioError
    from flexride.study.presets import study_preset

    request = study_preset("mesh-convergence")
    axes = {b: a for a, b in MESH_AXES.items()}
    if body not in axes:
        raise ScenarioError(f"body: {body!r} is not one of {', '.join(axes)}")
    request["parameters"] = [{"path": axes[body], "values": [float(h) for h in sizes]}]
    if conditions is not None:
        request["conditions"] = list(conditions)
    if speed_kmh is not None:
        request["speeds_kmh"] = [float(speed_kmh)]
    return request

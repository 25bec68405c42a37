"""Frequency-domain estimates over the API (``POST /estimates``): the answer of
``flexride estimate --json`` for a scenario, or the series of every comfort index over the
values of one field (:func:`flexride.frequency.sweep`).

The scenario is read as ``POST /jobs`` reads it
(:func:`~flexride.scenario.loading.resolve_scenario`: a full scenario or a preset with
overrides; a sweep value is one more override), and passes the checks of a job that matter
for an estimate (:mod:`flexride.study.admission`: measured data and profiles from uploads or
inline only, FE bodies and recorded points within the service's limits; a run's length and
result size do not matter here). Bounded work:

* a flexible body must already be in the FE cache (409 otherwise: the API never builds an FE
  model; a job or ``GET /fe/{kind}`` builds it); a calibrated car body
  (``bodies.carbody.calibration``) likewise: its calibration's outcome and the body of the
  calibrated values (409 otherwise, naming ``GET /fe/carbody?calibration_targets=…``: a
  calibration takes minutes and runs only in a job worker);
* at most :data:`MAX_CONCURRENT` estimates compute at once per process (503 with
  ``Retry-After`` beyond), in the threadpool of the synchronous route;
* an answer is a pure function of the scenario and the options, so rendered answers are kept
  in a :class:`~flexride.store.lru.ByteLRU` keyed by the canonical scenario hash, its name
  and the options (concurrent requests for the same answer compute it once).

A rigid vehicle's estimate takes about 0.3 s, a sweep about 0.3 s plus 30 ms per value
(flexible car body: about 1 s, plus 0.5 s per value).
"""

from __future__ import annotations

import json
import math
import threading
from typing import Any
from urllib.parse import quote

import numpy as np
from fastapi import Request, Response

from flexride.api.deps import Services
from flexride.api.errors import Conflict, SafeJSONResponse
from flexride.api.schemas.estimates import EstimateCreate
from flexride.api.services.result_cache import Rendered, accepts_gzip, gzip_settings, render
from flexride.errors import ErrorItem, ScenarioError
from flexride.frequency import LinearisationError, estimate
from flexride.frequency.floor import floor_scenario
from flexride.frequency.sweep import SweepResult, sweep_scenarios
from flexride.scenario.loading import resolve_scenario
from flexride.scenario.scenario import Scenario, located_error
from flexride.settings import API_PREFIX
from flexride.store.lru import ByteLRU
from flexride.study.scenarios import canonical_json, scenario_hash

__all__ = ["MAX_CONCURRENT", "estimate_answer", "missing_fe_bodies", "refusal"]

MAX_CONCURRENT = 2
"""Estimates computed at once per process (the machine's cores): more wait with 503."""
RETRY_AFTER_S = 5
"""Seconds a client is asked to wait when every slot is taken."""
ANSWER_CACHE_BYTES = 32 * 1024 * 1024
"""Bytes of rendered answers kept (an estimate of the six paper points is about 30 kB, a sweep
of 100 values over them 0.35 MB)."""
DIRECTION_INDICES = ("rms", "sperling", "sperling_filter", "a_p95", "peak")
"""Indices of a sweep's series besides the ISO weightings."""
#: Where a refusal points in the request, by reason.
REASON_LOC: dict[str, list[str | int]] = {
    "flange_contact": ["strict"], "contact_loss": ["strict"], "excitation": ["excitation"],
    "track": ["track"], "unstable": [], "equilibrium": [], "quasi_linear": ["linearisation"],
    "linearisation": ["linearisation"]}
#: What to do about a refusal, by reason.
ADVICE = {
    "flange_contact": "run the time-domain simulation of the scenario (POST "
    f"{API_PREFIX}/jobs), which models flange contact, or ask again with \"strict\": false for "
    "an estimate flagged as doubtful",
    "contact_loss": f"run the time-domain simulation of the scenario (POST {API_PREFIX}/jobs), "
    "or ask again with \"strict\": false for an estimate flagged as doubtful",
    "excitation": "the estimate takes random irregularities only: run the time-domain "
    f"simulation (POST {API_PREFIX}/jobs) for transient or periodic excitations, or ask again "
    "with \"strict\": false to estimate the random part alone",
    "unstable": "no stationary response exists (the vehicle hunts): run the time-domain "
    f"simulation (POST {API_PREFIX}/jobs) to see the motion, or lower speed_kmh",
    "equilibrium": "there is no steady state to linearise about: run the time-domain "
    f"simulation (POST {API_PREFIX}/jobs)",
    "quasi_linear": "the wheelsets' lateral motion did not settle in the quasi-linearisation "
    f"of the contact: run the time-domain simulation (POST {API_PREFIX}/jobs), ask again with "
    "\"strict\": false for an estimate flagged as doubtful, or with \"linearisation\": "
    "\"local\"",
}
_BODY_FIELDS = (("carbody", "carbody", "car body"), ("frames", "frame", "bogie frames"))

_SLOTS = threading.BoundedSemaphore(MAX_CONCURRENT)
_ANSWERS = ByteLRU(ANSWER_CACHE_BYTES, max_entries=256)


def refusal(err: LinearisationError, as_answer: bool = False) -> Response:
    """The answer for a scenario the linear estimate does not hold for: ``loc`` where it
    points in the request, the reason in ``ctx`` and what to do in the message; 422, or with
    ``as_answer`` (``refusal: "answer"``) 200 with ``applicable: false`` and the same content.
    """
    advice = ADVICE.get(err.reason, f"run the time-domain simulation (POST {API_PREFIX}/jobs)")
    item = {"loc": REASON_LOC.get(err.reason, []), "msg": str(err), "type": "LinearisationError",
            "ctx": {"reason": err.reason}}
    message = f"{err}. What to do: {advice}"
    if as_answer:
        return SafeJSONResponse(status_code=200, content={
            "applicable": False, "reason": err.reason, "message": message, "reasons": [item]})
    return SafeJSONResponse(status_code=422, content={
        "detail": [item], "message": message, "reason": err.reason})


def busy() -> Response:
    """The 503 answer when every estimate slot of the process is taken."""
    msg = (f"{MAX_CONCURRENT} estimates are being computed; ask again in {RETRY_AFTER_S} s")
    return SafeJSONResponse(status_code=503, headers={"Retry-After": str(RETRY_AFTER_S)},
                            content={"detail": msg, "message": msg})


# -- checks ----------------------------------------------------------------------------------


def missing_fe_bodies(scenario: Scenario) -> list[tuple[str, str, str]]:
    """The flexible bodies of ``scenario`` whose reduced FE model is not in the FE cache:
    ``(bodies field, kind, label)``. An entry counts only when it loads (what the assembly
    would do before building one); a calibrated car body (``bodies.carbody.calibration``)
    needs its calibration's outcome and the body of the calibrated values, both looked up
    by content key (milliseconds: no calibration runs here).
    """
    from flexride.fem import cache
    from flexride.fem.body_cache import vehicle_body_inputs
    from flexride.fem.calibrated_body import cached_calibration
    from flexride.fem.carbody import CarBodyParams

    out = []
    for fld, kind, label in _BODY_FIELDS:
        b = getattr(scenario.bodies, fld)
        if b.model != "flexible":
            continue
        params: CarBodyParams | None = None
        if b.calibration is not None:
            done = cached_calibration(scenario.vehicle, b.calibration, b.element_size_m)
            if done is None:
                out.append((fld, kind, label))
                continue
            params = done.params
        inputs = vehicle_body_inputs(kind, scenario.vehicle, b.reduction, b.cutoff_hz,
                                     b.element_size_m, None, params)
        if cache.load(cache.content_hash(inputs)) is None:
            out.append((fld, kind, label))
    return out


def _check_fe(scenario: Scenario) -> None:
    """Conflict (409) naming the first flexible body that is not built yet."""
    missing = missing_fe_bodies(scenario)
    if not missing:
        return
    fld, kind, label = missing[0]
    b = getattr(scenario.bodies, fld)
    query = (f"reduction={b.reduction}&cutoff_hz={b.cutoff_hz:g}"
             f"&element_size_m={b.element_size_m:g}")
    what = f"flexible {label}"
    if b.calibration is not None:
        cal = b.calibration
        what = f"calibrated {label} (bodies.{fld}.calibration: {cal.targets_spelling()})"
        query += (f"&calibration_targets={quote(cal.targets_spelling())}"
                  f"&calibration_max_evaluations={cal.max_evaluations}")
        if cal.variables is not None:
            query += f"&calibration_variables={','.join(cal.variables)}"
        if cal.n_modes is not None:
            query += f"&calibration_n_modes={cal.n_modes}"
    raise Conflict(
        f"the {what} (bodies.{fld}: {b.reduction}, cut-off {b.cutoff_hz:g} Hz, "
        f"elements {b.element_size_m:g} m) is not in the FE cache and estimates never build FE "
        f"models (nor calibrate them): build it first — run a job of the scenario (POST "
        f"{API_PREFIX}/jobs), or ask GET {API_PREFIX}/fe/{kind}?{query} for a preset's vehicle "
        "— then ask again")


def _admit(svc: Services, scenario: Scenario, parts: frozenset[str]) -> None:
    """The admission checks of a job that matter for an estimate (module docstring), those
    named in ``parts`` (``excitation``, ``contact``, ``bodies``, ``output``).
    """
    from flexride.solver.estimate import count_output_points
    from flexride.study.admission import check_bodies, check_measured, check_profiles

    sources, limits = svc.uploads.sources, svc.submitter.limits
    if "excitation" in parts:
        check_measured(scenario, sources)
    if "contact" in parts:
        check_profiles(scenario, sources)
    if "bodies" in parts:
        check_bodies(scenario, limits)
    points = count_output_points(scenario) if "output" in parts else 0
    if points > limits.max_output_points:
        where = ("output", "points") if scenario.output.points else (
            "output", "floor_grid_spacing_m")
        raise located_error([ErrorItem(where, (
            f"{points} recorded car-body points exceed the service's limit of "
            f"{limits.max_output_points} (FLEXRIDE_MAX_OUTPUT_POINTS)"))], "scenario")


#: Admission checks a sweep value repeats, by the top-level key of the swept field.
_VALUE_CHECKS = {"excitation": {"excitation"}, "contact": {"contact"},
                 "bodies": {"bodies"}, "vehicle": {"bodies", "output"}, "output": {"output"}}
_ALL_CHECKS = frozenset({"excitation", "contact", "bodies", "output"})


def _check_points(scenario: Scenario, points: list[str]) -> None:
    """422 at ``points`` for a point the vehicle does not record."""
    from flexride.vehicle.topology import build_vehicle

    veh = build_vehicle(scenario.vehicle, scenario.output)
    known = {f"{p.body}.{p.name}" for p in veh.recorded}
    bad = [(i, p) for i, p in enumerate(points)
           if (p if "." in p else f"carbody.{p}") not in known]
    if bad:
        names = sorted(k.removeprefix("carbody.") for k in known)
        raise located_error([ErrorItem(("points", i), f"unknown output point {p!r}; known: "
                                       f"{', '.join(names)}") for i, p in bad], "request")


def _value_scenarios(body: EstimateCreate, base: Scenario) -> list[Scenario]:
    """The scenario of every sweep value; every invalid one a 422 item at
    ``["sweep", "values", i]`` (a path that is no field of the scenario: at
    ``["sweep", "parameter"]``).
    """
    assert body.sweep is not None
    path = body.sweep.parameter
    _check_path(base, path)
    scenarios, items = [], []
    for i, value in enumerate(body.sweep.values):
        try:
            scenarios.append(resolve_scenario(body.scenario, body.preset,
                                              {**body.overrides, path: value}))
        except ScenarioError as err:
            items += _at_value(i, path, value, err)
    if items:
        raise located_error(items, "request")
    return scenarios


def _at_value(i: int, path: str, value: Any, err: ScenarioError) -> list[ErrorItem]:
    """The problems of ``err`` located at ``["sweep", "values", i]``, each message naming the
    swept field and the value (and the field with the problem when it is another one).
    """
    out = []
    for item in err.items or (ErrorItem((), str(err)),):
        where = "" if item.path in ("(root)", path) else f" ({item.path})"
        text = f"{path} = {json.dumps(value, default=str)[:80]}{where}: {item.msg}"
        out.append(ErrorItem(("sweep", "values", i), text))
    return out


def _check_path(base: Scenario, path: str) -> None:
    """422 at ``["sweep", "parameter"]`` for a dotted path that names no field of ``base``."""
    node: Any = base.model_dump(mode="json")
    for part in path.split("."):
        if isinstance(node, dict) and part in node:
            node = node[part]
        elif isinstance(node, list) and part.isdigit() and int(part) < len(node):
            node = node[int(part)]
        else:
            raise ScenarioError.at(("sweep", "parameter"), f"{path!r} is not a field of the "
                                   "scenario (a dotted path like vehicle.secondary.kz)",
                                   "request")


#: Where a floor map's problems point in the request.
FLOOR_LOC: tuple[str, ...] = ("floor_map", "spacing_m")


def _check_floor(svc: Services, base: Scenario, spacing: float) -> None:
    """422 at ``["floor_map", "spacing_m"]`` for a spacing the scenario refuses or a grid
    beyond the service's limit of recorded points (with the smallest spacing that fits).
    """
    from flexride.solver.estimate import count_output_points

    try:
        sc = floor_scenario(base, spacing)
    except ScenarioError as err:
        msgs = [f"{i.msg} (output.floor_grid_spacing_m)" for i in err.items] or [str(err)]
        raise located_error([ErrorItem(FLOOR_LOC, m) for m in msgs], "request") from None
    limit = svc.submitter.limits.max_output_points
    n = count_output_points(sc)
    if n > limit:
        fits = next((s / 20 for s in range(math.ceil(spacing * 20), 101)
                     if count_output_points(floor_scenario(base, s / 20)) <= limit), None)
        hint = f"; {fits:g} m fits" if fits is not None else ""
        raise ScenarioError.at(FLOOR_LOC, f"the floor grid at {spacing:g} m makes {n} recorded "
                               f"car-body points, more than the service's limit of {limit} "
                               f"(FLEXRIDE_MAX_OUTPUT_POINTS): choose a larger spacing{hint}",
                               "request")


def _checked(svc: Services, body: EstimateCreate) -> tuple[Scenario, list[Scenario] | None]:
    """The scenario (and the sweep's), validated and admitted (422/409 otherwise)."""
    base = resolve_scenario(body.scenario, body.preset, body.overrides)
    _admit(svc, base, _ALL_CHECKS)
    if body.floor_map is not None:
        _check_floor(svc, base, body.floor_map.spacing_m)
    values = _value_scenarios(body, base) if body.sweep is not None else None
    _check_fe(base)
    if values is not None and body.sweep is not None:
        top = body.sweep.parameter.split(".")[0]
        parts = frozenset(_VALUE_CHECKS.get(top, set()))
        for i, (sc, value) in enumerate(zip(values, body.sweep.values, strict=True)):
            try:
                if parts:
                    _admit(svc, sc, parts)
            except ScenarioError as err:
                raise located_error(_at_value(i, body.sweep.parameter, value, err),
                                    "request") from None
            if top in ("vehicle", "bodies"):
                _check_fe(sc)
    _check_points(base, body.points)
    return base, values


# -- answers ---------------------------------------------------------------------------------


def sweep_content(res: SweepResult, points: list[str], body: EstimateCreate) -> dict[str, Any]:
    """The JSON of a sweep: per point, direction and index the series over the values."""
    series: dict[str, dict[str, dict[str, list[float | None]]]] = {}
    nmv: dict[str, list[float | None]] = {}
    tables = res.tables
    names = next((t.points for t in tables if t is not None), [])
    for p in names:
        dirs = series.setdefault(p.name, {})
        for d, dc in p.directions.items():
            keys = [*DIRECTION_INDICES, *dc.iso]
            dirs[d] = {k: res.series(p.name, d, k) for k in keys}
        if p.nmv is not None:
            nmv[p.name] = [t.point(p.name).nmv if t is not None else None for t in tables]
    refused = [{"index": i, "value": v, "reason": r or "", "message": e or ""}
               for i, (v, e, r) in enumerate(zip(res.values, res.errors, res.reasons,
                                                 strict=True)) if e is not None]
    return {"parameter": res.parameter, "values": res.values, "points": points,
            "track": body.track, "strict": body.strict, "linearisation": body.linearisation,
            "series": series, "nmv": nmv,
            "flags": [list(t.flags) if t is not None else [] for t in tables],
            "refused": refused, "reuse": res.reuse, "seconds": res.seconds}


def _content(svc: Services, body: EstimateCreate, base: Scenario,
             values: list[Scenario] | None) -> dict[str, Any]:
    """The answer's JSON content (raises :class:`LinearisationError` for a refused estimate)."""
    sources = svc.uploads.sources
    if values is None or body.sweep is None:
        est = estimate(base, body.points, body.track, strict=body.strict, sources=sources,
                       floor_grid_m=body.floor_map.spacing_m if body.floor_map else None,
                       linearisation=body.linearisation)
        return est.to_dict(arrays=body.spectra)
    top = body.sweep.parameter.split(".")[0]
    res = sweep_scenarios(values, body.sweep.parameter, list(body.sweep.values), body.points,
                          body.track, strict=body.strict, sources=sources,
                          share_vehicle=top not in ("vehicle", "bodies", "output"),
                          linearisation=body.linearisation)
    return sweep_content(res, body.points, body)


def _key(svc: Services, body: EstimateCreate, scenarios: list[Scenario],
         gzip_min: int | None) -> str:
    """Cache key: the canonical hash and the name of every scenario computed, the options and
    where uploads are read from.
    """
    options = body.model_dump(mode="json", include={"points", "track", "strict", "sweep",
                                                     "spectra", "floor_map", "linearisation"})
    return canonical_json({"scenarios": [(scenario_hash(sc), sc.name) for sc in scenarios],
                           "options": options, "uploads": str(svc.uploads.sources.upload_dir),
                           "gzip": gzip_min})


def estimate_answer(request: Request, svc: Services, body: EstimateCreate) -> Response:
    """The HTTP answer of ``POST /estimates`` (module docstring): 200 with the estimate or the
    sweep, 422 for an invalid request or a refused estimate (200 with ``applicable: false``
    for a refused one with ``refusal: "answer"``), 409 for an FE body not built, 503 when
    busy.
    """
    base, values = _checked(svc, body)
    gz = gzip_settings(request.app)
    gzip_min = None if gz is None else gz[0]
    key = _key(svc, body, [base] if values is None else values, gzip_min)
    hit: Rendered | None = _ANSWERS.get(key)
    if hit is None:
        if not _SLOTS.acquire(blocking=False):
            return busy()
        try:
            hit = _ANSWERS.get_or_make(key, lambda: _make(svc, body, base, values, gzip_min))
        except LinearisationError as err:
            return refusal(err, body.refusal == "answer")
        except np.linalg.LinAlgError as err:  # a degenerate system: no linear model either
            return refusal(LinearisationError(
                f"the linearised system is singular ({err})", "equilibrium"),
                body.refusal == "answer")
        finally:
            _SLOTS.release()
    assert hit is not None
    return hit.response(accepts_gzip(request))


def _make(svc: Services, body: EstimateCreate, base: Scenario, values: list[Scenario] | None,
          gzip_min: int | None) -> tuple[Rendered, int]:
    """Compute and render an answer for the cache."""
    r = render(_content(svc, body, base, values), gzip_min)
    return r, r.nbytes

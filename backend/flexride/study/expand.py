"""Expand a study request into its job matrix: the product of its axes applied to the base
scenario, each job validated on its own.

Axes, in this order: line/excitation ``conditions`` (the paper's by name, or custom sets of
dotted-path values), ``speeds_kmh``, ``body_models`` (rigid/flexible car body and frames),
``parameters`` (any field by dotted path) and ``seeds`` (irregularity realisations 1 … N,
:mod:`flexride.study.seeds`). ``overrides`` apply to every job, before the realisation's
seeds; a job without a random irregularity has one realisation only. Each job is evaluated
over the section of its ``section`` rule (:mod:`flexride.study.sections`). A flexible body
keeps the modes its job's excitation drives (``cutoff: follow``, the default:
:func:`flexride.scenario.fidelity.required_cutoffs`; ``as_given`` keeps the scenario's).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from typing import Any

from flexride.errors import ScenarioError
from flexride.scenario.fidelity import DEFAULT_CUTOFF_RULE, required_cutoffs, with_cutoffs
from flexride.scenario.loading import safe_overrides
from flexride.scenario.presets import STUDY_CONDITIONS, preset_dict
from flexride.scenario.scenario import Scenario, resolve_preset_base, scenario_from_dict
from flexride.study.presets import study_preset
from flexride.study.sections import DEFAULT_SECTION_RULE, job_section
from flexride.study.seeds import SEED_AXIS, is_random, realisations, seed_overrides


class StudyTooLarge(ScenarioError):
    """The product of a study's axes exceeds the configured number of jobs."""


@dataclass
class Level:
    """One value of an axis: its label and the dotted-path values it sets."""

    label: Any
    values: dict[str, Any]


@dataclass
class Axis:
    """A study axis: its name and levels."""

    name: str
    levels: list[Level]

    def describe(self) -> dict[str, Any]:
        """JSON description: name and level labels."""
        return {"name": self.name, "values": [lv.label for lv in self.levels]}


@dataclass
class PlannedJob:
    """One job of the matrix; ``section`` the stretch its indices are evaluated on
    (:func:`flexride.study.sections.job_section`; None: the whole run).
    """

    index: int
    name: str
    axes: dict[str, Any]
    scenario: Scenario
    section: dict[str, Any] | None = None


@dataclass
class StudyPlan:
    """A study ready to be submitted."""

    name: str
    description: str
    preset: str | None
    reuse: bool
    axes: list[Axis]
    jobs: list[PlannedJob] = field(default_factory=list)
    request: dict[str, Any] = field(default_factory=dict)


def merge_with_preset(request: dict[str, Any]) -> dict[str, Any]:
    """The request with its study preset's fields filled in (request fields win)."""
    name = request.get("preset")
    if not name:
        return dict(request)
    merged = study_preset(name)
    for key, value in request.items():
        if key == "preset" or value is None:
            continue
        if isinstance(value, str | list | dict) and not value:
            continue
        merged[key] = value
    merged["preset"] = name
    return merged


def _condition_level(i: int, cond: Any) -> Level:
    if isinstance(cond, str):
        if cond not in STUDY_CONDITIONS:
            raise ScenarioError(
                f"conditions.{i}: unknown condition {cond!r}; paper conditions: "
                f"{', '.join(STUDY_CONDITIONS)} (or give {{name, set}})"
            )
        _, line, exc, distance = STUDY_CONDITIONS[cond]
        return Level(cond, {"line": line, "excitation": exc, "distance_m": distance,
                            "duration_s": None})
    return Level(cond["name"], dict(cond.get("set") or {}))


def build_axes(req: dict[str, Any]) -> list[Axis]:
    """The axes of a (preset-merged) request, in matrix order."""
    axes: list[Axis] = []
    if req.get("conditions"):
        names = [c if isinstance(c, str) else c["name"] for c in req["conditions"]]
        if len(set(names)) != len(names):
            raise ScenarioError.at(("conditions",), "names must be unique", "study")
        axes.append(Axis("condition", [_condition_level(i, c)
                                       for i, c in enumerate(req["conditions"])]))
    if req.get("speeds_kmh"):
        speeds = [float(v) for v in req["speeds_kmh"]]
        if len(set(speeds)) != len(speeds):
            raise ScenarioError.at(("speeds_kmh",), "values must be unique", "study")
        axes.append(Axis("speed_kmh", [Level(v, {"speed_kmh": v}) for v in speeds]))
    if req.get("body_models"):
        models = list(req["body_models"])
        if len(set(models)) != len(models):
            raise ScenarioError.at(("body_models",), "values must be unique", "study")
        axes.append(Axis("body_model", [
            Level(m, {"bodies.carbody.model": m, "bodies.frames.model": m}) for m in models]))
    seen = {"speed_kmh"}
    for i, p in enumerate(req.get("parameters") or []):
        path = p["path"]
        if path in seen:
            raise ScenarioError.at(("parameters", i, "path"), f"{path!r} is already an axis",
                                   "study")
        seen.add(path)
        axes.append(Axis(path, [Level(v, {path: v}) for v in p["values"]]))
    if req.get("seeds"):
        # the seeds depend on the job's excitation: set in _job_data, after the other axes
        axes.append(Axis(SEED_AXIS, [Level(k, {}) for k in realisations(int(req["seeds"]))]))
    return axes


def _base_data(base: dict[str, Any]) -> dict[str, Any]:
    if (base.get("scenario") is None) == (base.get("preset") is None):
        raise ScenarioError.at(("base",), "give either 'scenario' or 'preset' (not both)",
                               "study")
    if base.get("preset") is not None:
        data = preset_dict(base["preset"])
    else:
        scen = base["scenario"]
        if not isinstance(scen, dict):
            raise ScenarioError.at(("base", "scenario"), "must be a mapping", "study")
        data = resolve_preset_base(scen) if "preset" in scen else scen
    return safe_overrides(data, base.get("overrides"), source="base.overrides",
                          loc=("base", "overrides"))


def _label(value: Any) -> str:
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return str(value)


def expand_study(request: dict[str, Any], max_jobs: int) -> StudyPlan:
    """Expand a study request (``StudyCreate`` as a dict) into validated jobs.

    Raises
    ------
    StudyTooLarge
        More than ``max_jobs`` combinations.
    ScenarioError
        An unknown preset or condition, a bad path, or a job whose scenario is invalid (the
        message names the job's axis values and the field).
    """
    req = merge_with_preset(request)
    from flexride.study.report import REPORT_PRESET, expand_report  # study.report imports us

    if req.get("preset") == REPORT_PRESET:
        return expand_report(req, max_jobs)
    if req.get("quick") is not None:
        raise ScenarioError.at(("quick",), "only for the paper-report preset", "study")
    if req.get("base") is None:
        raise ScenarioError.at(("base",), "a study needs a base scenario (or a study preset)",
                               "study")
    axes = build_axes(req)
    n = 1
    for ax in axes:
        n *= len(ax.levels)
    if n > max_jobs:
        raise StudyTooLarge(
            f"study: the axes make {n} jobs; at most {max_jobs} are allowed "
            "(FLEXRIDE_MAX_STUDY_JOBS)"
        )
    base = _base_data(req["base"])
    name = req.get("name") or req.get("preset") or "study"
    plan = StudyPlan(name=name, description=req.get("description") or "",
                     preset=req.get("preset"), reuse=bool(req.get("reuse", True)), axes=axes,
                     request=req)
    for combo in itertools.product(*(ax.levels for ax in axes)):
        labels = {ax.name: lv.label for ax, lv in zip(axes, combo, strict=True)}
        index = len(plan.jobs)
        data = _job_data(base, combo, labels, req.get("overrides"), index)
        if data is None:
            continue
        job_name = " ".join([name, *(_label(v) for v in labels.values())])[:80]
        data = {**data, "name": job_name}
        where = ", ".join(f"{k}={_label(v)}" for k, v in labels.items()) or "base"
        scenario = scenario_from_dict(data, source=f"study job {index} ({where})")
        section = job_section(scenario, req.get("section") or DEFAULT_SECTION_RULE)
        plan.jobs.append(PlannedJob(index=index, name=job_name, axes=labels, scenario=scenario,
                                    section=section))
    if req.get("cutoff", DEFAULT_CUTOFF_RULE) == "follow":
        _follow_excitation(plan.jobs)
    return plan


def _follow_excitation(jobs: list[PlannedJob]) -> None:
    """Raise each flexible body's cut-off to the rule of its excitation
    (:func:`~flexride.scenario.fidelity.required_cutoffs`), one value per condition: the
    highest its jobs need, so that a condition's jobs share one FE reduction.
    """
    need: dict[Any, dict[str, float]] = {}
    for job in jobs:
        cond = need.setdefault(job.axes.get("condition"), {})
        for part, hz in required_cutoffs(job.scenario).items():
            cond[part] = max(cond.get(part, 0.0), hz)
    for job in jobs:
        job.scenario = with_cutoffs(job.scenario, need[job.axes.get("condition")])


def _job_data(base: dict[str, Any], combo: tuple[Level, ...], labels: dict[str, Any],
              overrides: dict[str, Any] | None, index: int) -> dict[str, Any] | None:
    """Scenario mapping of one combination of levels; None for a realisation > 1 of a job
    without a random irregularity (it would repeat realisation 1).
    """
    where = ", ".join(f"{k}={_label(v)}" for k, v in labels.items()) or "base"
    data = base
    for lv in combo:
        data = safe_overrides(data, lv.values, source=f"study job {index} ({where})",
                              loc=("parameters",))
    data = safe_overrides(data, overrides, source="overrides")
    k = labels.get(SEED_AXIS)
    if k is None:
        return data
    excitation = data.get("excitation") or []
    if not is_random(excitation):
        return data if k == 1 else None
    return safe_overrides(data, seed_overrides(excitation, int(k)),
                          source=f"study job {index} ({where})", loc=("seeds",))

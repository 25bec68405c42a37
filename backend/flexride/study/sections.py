"""The section of a run a study job's indices are evaluated on, by the rules of the paper
report (:func:`flexride.paper.plan.section_of`): on a curve the circular arc (or the whole
curve), on straight track with an excitation from 30 m on, a settlement from the start to the
end; the whole run when the section would hold less than 6 s of it (``paper.plan.MIN_EVAL_S``).

The section goes with the job (``run_meta["section"]``); the worker analyses the section as
well as the whole run (``summary["section"]``) and the study's tables use the section's
indices, stating it with every index.
"""

from __future__ import annotations

from typing import Any, Literal

from flexride.scenario.scenario import Scenario

__all__ = ["DEFAULT_SECTION_RULE", "SECTION_RULE_LABELS", "SectionRule", "job_section",
           "job_summary"]

SectionRule = Literal["paper", "curve", "run"]
"""``paper``: the report's sections (the arc on a curve); ``curve``: the same but the whole
curve with its transitions; ``run``: the whole run."""
DEFAULT_SECTION_RULE: SectionRule = "paper"
SECTION_RULE_LABELS: dict[SectionRule, str] = {
    "paper": "the paper report's sections (the arc of a curve)",
    "curve": "the whole curve, transitions included",
    "run": "the whole run",
}
"""A short label of every rule, for choices (the API schema's ``x-enum-labels``)."""



def job_section(scenario: Scenario, rule: str = DEFAULT_SECTION_RULE) -> dict[str, Any] | None:
    """The section of one job, or None for the whole run.

    Returns
    -------
    dict or None
        ``{"rule", "start_m", "end_m", "label"}`` (m along the line, vehicle centre), or
        None when ``rule`` is ``run``, the section is the whole run or it would be shorter
        than the report's shortest evaluated stretch (``paper.plan.MIN_EVAL_S``, 6 s: one 5 s
        Sperling segment and a margin) within the run.
    """
    # imported here: flexride.paper's report reads the study tables' summary_value
    from flexride.paper.plan import MIN_EVAL_S, section_of

    if rule == "run":
        return None
    data = scenario.model_dump(mode="json")
    length = scenario.duration * scenario.speed_mps
    g = scenario.vehicle.geometry
    half = g.bogie_centre_spacing / 2.0 + g.wheelbase / 2.0
    sec = section_of(data["line"], data["excitation"], length, half,
                     curve="curve" if rule == "curve" else "arc")
    start, end = max(sec.start_m, 0.0), min(sec.end_m, length)
    if sec.rule == "run" or (start <= 0.0 and end >= length):
        return None
    if end - start < MIN_EVAL_S * scenario.speed_mps:
        return None
    return {"rule": sec.rule, "start_m": start, "end_m": end,
            "label": type(sec)(start, end, start, sec.rule).label()}


def job_summary(results: Any, section: dict[str, Any] | None) -> dict[str, Any]:
    """The summary a study job stores: the whole run's analysis
    (:meth:`flexride.analysis.Summary.to_dict`) with, given a ``section``
    (:func:`job_section`), that section's own analysis as ``summary["section"]``
    (``{**section, "summary"}``), cut as the paper report cuts its runs.

    An analysis that fails on input (:class:`~flexride.errors.FlexrideError`) is stated, not
    raised: ``{"error": "<type>: <text>"}`` for the whole run, ``{**section, "error"}`` for the
    section (the whole run's indices stand; the tables use them).
    """
    from flexride.analysis import analyze
    from flexride.errors import FlexrideError
    from flexride.paper.record import window_results

    try:
        summary: dict[str, Any] = analyze(results).to_dict()
    except FlexrideError as exc:
        return {"error": f"{type(exc).__name__}: {exc}"}
    if section:
        try:
            part = window_results(results, (float(section["start_m"]), float(section["end_m"])))
            summary["section"] = {**section, "summary": analyze(part).to_dict()}
        except FlexrideError as exc:
            summary["section"] = {**section, "error": f"{type(exc).__name__}: {exc}"}
    return summary

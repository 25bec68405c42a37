"""Whether a scenario's flexible bodies keep the elastic modes its excitation drives.

A modal body keeps its elastic modes up to ``cutoff_hz``. An excitation of wavelength λ at the
speed V drives the vehicle at f = V/λ (corrugation of 0.5 m at 80 km/h: 44 Hz); modes above the
cut-off that this frequency excites are missing from the response, and the car body's
acceleration can be far off (flexible PC at 80 km/h on 0.5 m corrugation: rms 0.135 m/s² with
a 40 Hz cut-off, 0.908 m/s² with 100 Hz; docs/paper.md). The rule, here only: keep modes up to at
least :data:`CUTOFF_FACTOR` times the highest excitation frequency, rounded up to
:data:`CUTOFF_STEP_HZ`. The paper report applies it to its runs; a run whose bodies miss it
says so in the notes of its summary, with the cut-off that would do.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any, Literal

from flexride.scenario.scenario import Scenario

__all__ = ["BODY_PARTS", "CUTOFF_FACTOR", "CUTOFF_RULE_LABELS", "CUTOFF_STEP_HZ",
           "DEFAULT_CUTOFF_RULE", "CutoffRule", "cutoff_notes", "excitation_frequency_hz",
           "required_cutoffs", "shortest_wavelength", "sufficient_cutoff_hz", "with_cutoffs"]

CutoffRule = Literal["follow", "as_given"]
"""What a study does with its flexible bodies' cut-off: raise it to the rule, or keep it."""
DEFAULT_CUTOFF_RULE: CutoffRule = "follow"
CUTOFF_RULE_LABELS: dict[CutoffRule, str] = {
    "follow": "follow the excitation (at least 1.5 × V/λ_min)",
    "as_given": "as the base scenario gives it",
}
"""A short label of every rule, for choices (the API schema's ``x-enum-labels``)."""

BODY_PARTS = ("carbody", "frames")
"""The scenario's body-model entries that can be flexible."""

CUTOFF_FACTOR = 1.5
"""Lowest ratio of a flexible body's cut-off to the highest excitation frequency (-)."""
CUTOFF_STEP_HZ = 10.0
"""A sufficient cut-off is rounded up to a multiple of this (Hz), so that the runs of a study
share few FE reductions."""


def shortest_wavelength(excitations: Iterable[Mapping[str, Any]]) -> float:
    """Shortest wavelength (m) of random irregularities (``wavelength_min_m``) and
    corrugation (``wavelength_m``) among ``excitations`` (their dictionaries); infinity when
    there is none (settlement and measured profiles are not counted: a settlement is a long
    wave, a measured profile's content is in its data).
    """
    lam = math.inf
    for exc in excitations:
        lam = min(lam, float(exc.get("wavelength_min_m") or exc.get("wavelength_m") or math.inf))
    return lam


def excitation_frequency_hz(scenario: Scenario) -> float | None:
    """Highest excitation frequency V/λ_min of ``scenario`` (Hz), or None without a random or
    periodic excitation.
    """
    lam = shortest_wavelength(e.model_dump() for e in scenario.excitation)
    return scenario.speed_mps / lam if math.isfinite(lam) else None


def sufficient_cutoff_hz(f_excitation_hz: float, base_hz: float) -> float:
    """max(``base_hz``, :data:`CUTOFF_FACTOR` · f rounded up to :data:`CUTOFF_STEP_HZ`) (Hz)."""
    step = CUTOFF_STEP_HZ
    return max(base_hz, math.ceil(CUTOFF_FACTOR * f_excitation_hz / step) * step)


def required_cutoffs(scenario: Scenario) -> dict[str, float]:
    """The cut-off (Hz) each flexible body (``carbody``, ``frames``) needs by the rule, for
    those that keep less; empty when every body keeps what its excitation drives.
    """
    f_exc = excitation_frequency_hz(scenario)
    if f_exc is None:
        return {}
    need = {}
    for part in BODY_PARTS:
        body = getattr(scenario.bodies, part)
        hz = sufficient_cutoff_hz(f_exc, body.cutoff_hz)
        if body.elastic and hz > body.cutoff_hz:
            need[part] = hz
    return need


def with_cutoffs(scenario: Scenario, cutoffs: Mapping[str, float]) -> Scenario:
    """``scenario`` with the flexible bodies of ``cutoffs`` (part → Hz) keeping modes up to
    at least that frequency (a body already keeping more is unchanged).
    """
    bodies = scenario.bodies
    for part, hz in cutoffs.items():
        body = getattr(bodies, part)
        if body.elastic and hz > body.cutoff_hz:
            bodies = bodies.model_copy(update={part: body.model_copy(update={"cutoff_hz": hz})})
    return scenario.model_copy(update={"bodies": bodies})


def cutoff_notes(scenario: Scenario) -> list[str]:
    """One line per flexible body (car body, frames) whose cut-off is below the rule, naming
    the excitation frequency and the field's value that would do; empty when all keep it.
    """
    f_exc = excitation_frequency_hz(scenario)
    return [f"bodies.{part}.cutoff_hz = {getattr(scenario.bodies, part).cutoff_hz:g} Hz keeps "
            f"fewer elastic modes than the excitation drives: its highest frequency is "
            f"{f_exc:.1f} Hz (V/λ_min at {scenario.speed_kmh:g} km/h), and {CUTOFF_FACTOR:g} "
            f"times that needs bodies.{part}.cutoff_hz ≥ {hz:g} Hz"
            for part, hz in required_cutoffs(scenario).items()]

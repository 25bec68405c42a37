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
from typing import Any

from flexride.scenario.scenario import Scenario

__all__ = ["BODY_PARTS", "CUTOFF_FACTOR", "CUTOFF_STEP_HZ", "cutoff_notes",
           "excitation_frequency_hz", "shortest_wavelength", "sufficient_cutoff_hz",
           "with_sufficient_cutoff"]

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


def cutoff_notes(scenario: Scenario) -> list[str]:
    """One line per flexible body (car body, frames) whose cut-off is below the rule, naming
    the excitation frequency and the field's value that would do; empty when all keep it.
    """
    f_exc = excitation_frequency_hz(scenario)
    if f_exc is None:
        return []
    notes = []
    for part in BODY_PARTS:
        body = getattr(scenario.bodies, part)
        need = sufficient_cutoff_hz(f_exc, body.cutoff_hz)
        if body.model == "flexible" and need > body.cutoff_hz:
            notes.append(
                f"bodies.{part}.cutoff_hz = {body.cutoff_hz:g} Hz keeps fewer elastic modes "
                f"than the excitation drives: its highest frequency is {f_exc:.1f} Hz "
                f"(V/λ_min at {scenario.speed_kmh:g} km/h), and {CUTOFF_FACTOR:g} times that "
                f"needs bodies.{part}.cutoff_hz ≥ {need:g} Hz")
    return notes


def with_sufficient_cutoff(scenario: Scenario) -> Scenario:
    """``scenario`` with every flexible body's cut-off raised to the rule where it is below
    (unchanged otherwise): what a study does by default (``cutoff: follow``).
    """
    f_exc = excitation_frequency_hz(scenario)
    if f_exc is None:
        return scenario
    bodies = scenario.bodies
    for part in BODY_PARTS:
        body = getattr(bodies, part)
        need = sufficient_cutoff_hz(f_exc, body.cutoff_hz)
        if body.model == "flexible" and need > body.cutoff_hz:
            bodies = bodies.model_copy(update={part: body.model_copy(update={"cutoff_hz": need})})
    return scenario.model_copy(update={"bodies": bodies})

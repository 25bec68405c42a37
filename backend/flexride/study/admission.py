"""Admission of a scenario to the service: what every job must pass before it is recorded.

* **Data, never a server path.** A measured irregularity over the API gives its data inline
  (``columns`` + ``rows``) or as an upload id; ``path`` is refused, located at the field. The
  data are loaded and checked now (bounded by the upload and body size limits), so a bad
  table fails the submission, not the run.
* **Bounded work.** The run's size (:func:`flexride.solver.estimate.estimate_run`) and any FE
  body it builds (:func:`flexride.fem.size.estimated_dofs`) are compared with the service's
  limits (:class:`Limits`); beyond them the answer names the field, the estimate and the limit.

Every refusal is a :class:`~flexride.errors.ScenarioError` whose items carry the field path.
"""

from __future__ import annotations

from dataclasses import dataclass

from flexride.contact.scenario_table import load_profile
from flexride.errors import ErrorItem, ScenarioError
from flexride.scenario.excitation import MeasuredIrregularity
from flexride.scenario.scenario import Scenario, located_error
from flexride.scenario.vehicle import Vehicle
from flexride.settings import Settings
from flexride.solver.estimate import (
    RunEstimate,
    check_steps,
    count_output_points,
    estimate_run,
    known_step,
    length_field,
)
from flexride.track.measured import MeasuredSources, load_measured


@dataclass(frozen=True)
class Limits:
    """The service's bounds on one job (settings ``FLEXRIDE_MAX_*``).

    Attributes
    ----------
    max_steps : int
        Time steps.
    max_output_points : int
        Recorded car-body points.
    max_result_mb : float
        Recorded values × 8 bytes, in MB.
    max_fe_dofs : int
        Degrees of freedom of an FE body to build.
    max_fe_cutoff_hz : float
        Modal cut-off of an FE body to build (Hz).
    """

    max_steps: int
    max_output_points: int
    max_result_mb: float
    max_fe_dofs: int
    max_fe_cutoff_hz: float

    @classmethod
    def from_settings(cls, settings: Settings) -> Limits:
        """The limits configured in ``settings``."""
        return cls(max_steps=settings.max_steps, max_output_points=settings.max_output_points,
                   max_result_mb=settings.max_result_mb, max_fe_dofs=settings.max_fe_dofs,
                   max_fe_cutoff_hz=settings.max_fe_cutoff_hz)


def _refuse(items: list[ErrorItem]) -> None:
    if items:
        raise located_error(items, "scenario")


def check_measured(scenario: Scenario, sources: MeasuredSources) -> None:
    """Refuse file paths and load every measured irregularity from ``sources`` (checked)."""
    items: list[ErrorItem] = []
    for i, exc in enumerate(scenario.excitation):
        if not isinstance(exc, MeasuredIrregularity):
            continue
        try:
            load_measured(exc, sources)
        except ScenarioError as err:
            items.extend(ErrorItem(("excitation", i, *it.loc), it.msg) for it in err.items)
    _refuse(items)


def check_profiles(scenario: Scenario, sources: MeasuredSources) -> None:
    """Refuse profile file paths and load uploaded profiles from ``sources`` (checked)."""
    c = scenario.contact
    if c.geometry != "profiles":
        return
    items: list[ErrorItem] = []
    for name, src in (("wheel", c.wheel), ("rail", c.rail)):
        try:
            load_profile(src, name, sources)
        except ScenarioError as err:
            items.extend(ErrorItem(("contact", name, *it.loc), it.msg) for it in err.items)
    _refuse(items)


def check_run_size(scenario: Scenario, limits: Limits) -> RunEstimate:
    """Refuse a run beyond ``limits`` (steps, recorded points, result size); return its size.
    With ``solver.dt: auto`` the steps are bounded after the set-up (:func:`check_auto_steps`
    at submission when the check ran, the worker before it runs).
    """
    points = count_output_points(scenario)
    if points > limits.max_output_points:
        where = ("output", "points") if scenario.output.points else (
            "output", "floor_grid_spacing_m")
        _refuse([ErrorItem(where, f"{points} recorded car-body points (the paper's six, user "
                           f"points and the floor grid) exceed the service's limit of "
                           f"{limits.max_output_points} (FLEXRIDE_MAX_OUTPUT_POINTS)")])
    step = known_step(scenario)
    if step is not None:  # auto: checked once the set-up has chosen the step
        check_steps(scenario, step, limits.max_steps)
    est = estimate_run(scenario)
    if est.result_mb > limits.max_result_mb:
        _refuse([ErrorItem((length_field(scenario),),
                           f"estimated results of {est.result_mb:,.0f} MB ({est.channels} "
                           f"channels × {est.samples:,} samples × 8 bytes) exceed the "
                           f"service's limit of {limits.max_result_mb:g} MB "
                           "(FLEXRIDE_MAX_RESULT_MB); record fewer points, a lower "
                           "output.rate_hz or a shorter run")])
    return est


def check_auto_steps(scenario: Scenario, preflight: dict | None, limits: Limits) -> None:
    """Bound the steps of a ``solver.dt: auto`` scenario by the step its submission check
    chose (``preflight["stability"]["dt"]``), when the check ran.
    """
    stab = (preflight or {}).get("stability") or {}
    if isinstance(scenario.solver.dt, str) and stab.get("dt"):
        check_steps(scenario, float(stab["dt"]), limits.max_steps)


def check_fe_build(kind: str, vehicle: Vehicle, element_size_m: float, cutoff_hz: float,
                   limits: Limits, loc: tuple[str | int, ...]) -> None:
    """Refuse an FE body of ``kind`` beyond ``limits`` (cut-off, estimated degrees of freedom);
    ``loc`` is the path of the body's settings in the request.
    """
    from flexride.fem.size import estimated_dofs, smallest_element_size

    if cutoff_hz > limits.max_fe_cutoff_hz:
        _refuse([ErrorItem((*loc, "cutoff_hz"),
                           f"cut-off {cutoff_hz:g} Hz exceeds the service's limit of "
                           f"{limits.max_fe_cutoff_hz:g} Hz (FLEXRIDE_MAX_FE_CUTOFF_HZ)")])
    dofs = estimated_dofs(kind, vehicle, element_size_m)
    if dofs > limits.max_fe_dofs:
        smallest = smallest_element_size(kind, vehicle, limits.max_fe_dofs)
        larger = f" of at least {smallest:g} m" if smallest is not None else ""
        _refuse([ErrorItem((*loc, "element_size_m"),
                           f"element size {element_size_m:g} m gives about {dofs:,} degrees of "
                           f"freedom, beyond the service's limit of {limits.max_fe_dofs:,} "
                           f"(FLEXRIDE_MAX_FE_DOFS); use a larger element size{larger}")])


def check_bodies(scenario: Scenario, limits: Limits) -> None:
    """Refuse flexible bodies whose FE build is beyond ``limits``."""
    for name, kind in (("carbody", "carbody"), ("frames", "frame")):
        body = getattr(scenario.bodies, name)
        if body.finite_elements:
            check_fe_build(kind, scenario.vehicle, body.element_size_m, body.cutoff_hz, limits,
                           ("bodies", name))


def admit(scenario: Scenario, limits: Limits, sources: MeasuredSources) -> RunEstimate:
    """Everything a scenario must pass to become a job of the service (module docs).

    Returns
    -------
    RunEstimate
        The run's size.

    Raises
    ------
    ScenarioError
        A file path, unusable measured data, or a run or FE body beyond the limits; items
        located at the field.
    """
    check_measured(scenario, sources)
    check_profiles(scenario, sources)
    est = check_run_size(scenario, limits)
    check_bodies(scenario, limits)
    return est

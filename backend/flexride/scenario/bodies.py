"""Per-body modelling choice: rigid, flexible from a reduced finite-element model, or (the car
body) a free–free beam; and the typed calibration of the flexible car body.

The names of mode types come from :mod:`flexride.fem.mode_types` and those of the calibration
variables from :mod:`flexride.fem.calibration_variables`: two vocabulary modules without FE
code (they import nothing but :mod:`flexride.errors`), so the schema and the calibration can
never disagree about what a target or a variable may be called.
"""

from __future__ import annotations

from typing import Any, Literal

from pydantic import Field, field_validator, model_validator

from flexride.fem.calibration_variables import (
    BOUNDS,
    DEFAULT_BODY_VARIABLES,
    least_budget,
)
from flexride.fem.mode_types import (
    MODE_TYPES,
    ORDERED_TYPES,
    SECTION_DEFORMATION,
    ModeType,
    parse_mode_type,
)
from flexride.scenario.base import Schema, quantity

#: Largest evaluation budget of a scenario's calibration (FE evaluations). One evaluation of
#: the 0.2 m car body (mesh, eigenmodes, classification, pairing) took 5.4 s of wall time
#: (3.2 s CPU) on this project's 2-core machine for six targets (18 modes, 8 variables: 18
#: evaluations in 98 s while other tests ran), so 60 evaluations are about 5–6 minutes, plus
#: the body's build (about a minute); at 0.5 m about 0.4 s each.
MAX_CALIBRATION_EVALUATIONS = 60
#: Most targets of a scenario's calibration.
MAX_CALIBRATION_TARGETS = 12
#: Most elastic modes computed and classified per evaluation.
MAX_CALIBRATION_MODES = 40


def _car_body_type_names() -> list[str]:
    """Canonical spellings of the types a car-body target may ask for: every type of
    :data:`~flexride.fem.mode_types.MODE_TYPES` the car body's classifier can name (not
    ``cross-section deformation``, the name for models without named regions), and the
    beam-like ones with the orders first to fourth.
    """
    names = [t for t in MODE_TYPES if t != SECTION_DEFORMATION]
    for base in MODE_TYPES:
        if base in ORDERED_TYPES:
            names += [str(ModeType(base, order)) for order in range(1, 5)]
    return list(dict.fromkeys(names))


#: The mode types a car-body calibration target may name (canonical spellings).
CARBODY_TARGET_TYPES: tuple[str, ...] = tuple(_car_body_type_names())


class CalibrationTarget(Schema):
    """One target of the car body's calibration: a natural frequency and, optionally, the type
    of the mode that should have it.
    """

    frequency_hz: float = quantity(
        ..., gt=0.0, le=100.0, unit="Hz",
        description="Target natural frequency of an elastic mode of the car body")
    mode_type: str | None = Field(
        None,
        description="Type of the mode (the classifier's names, fem/mode_types.py; case, spaces "
        "and '-' for '–' are forgiven, beam-like types may carry an order beyond fourth: 5th "
        "…): the target pairs only with a model mode of this type; null: with the nearest "
        "free mode in frequency",
        json_schema_extra={"enum": [*CARBODY_TARGET_TYPES, None]},
    )

    @field_validator("mode_type")
    @classmethod
    def _known_type(cls, value: str | None) -> str | None:
        if value is None:
            return None
        if not value.strip():
            raise ValueError("a mode type must follow ':' (or give the frequency alone)")
        try:
            wanted = parse_mode_type(value)
        except ValueError as exc:  # FEModelError is a ValueError
            raise ValueError(str(exc)) from None
        if wanted.base == SECTION_DEFORMATION:
            raise ValueError(
                f"{SECTION_DEFORMATION!r} names modes of imported models without named "
                "regions; the car body's classifier never gives it: use one of "
                + ", ".join(repr(t) for t in CARBODY_TARGET_TYPES))
        return str(wanted)

    def spelling(self) -> str:
        """The command-line spelling ``frequency[:type]`` (``6.11:rhombic``)."""
        f = f"{self.frequency_hz:g}"
        return f if self.mode_type is None else f"{f}:{self.mode_type}"


def _target_items(value: Any) -> Any:
    """Targets given in the command-line spelling (``"5.03:torsion,6.11"``, as ``flexride fe
    calibrate --targets`` and ``GET /fe/carbody?targets=``), whole or item by item, as dicts;
    anything else unchanged for the schema to check.
    """
    if isinstance(value, str):
        value = [v for v in value.replace(";", ",").split(",") if v.strip()]
    if not isinstance(value, list):
        return value
    return [_target_item(v) if isinstance(v, str) else v for v in value]


def _target_item(text: str) -> dict[str, Any] | str:
    """``"6.11:rhombic"`` → ``{"frequency_hz": "6.11", "mode_type": "rhombic"}`` (the schema
    checks both); ``"6.11"`` → without a type.
    """
    freq, sep, kind = text.partition(":")
    item: dict[str, Any] = {"frequency_hz": freq.strip()}
    if sep:
        item["mode_type"] = kind.strip()
    return item


class CarBodyCalibration(Schema):
    """Typed calibration of the flexible car body: model updating of its panel sections and
    mass split so that the model modes *paired* with the targets (by type, then frequency)
    have the targets' frequencies, run when the body is built (``flexride fe calibrate``'s
    code) and cached by content with the FE bodies.
    """

    targets: list[CalibrationTarget] = Field(
        ..., min_length=1, max_length=MAX_CALIBRATION_TARGETS,
        description="Targets in any order: a list of {frequency_hz, mode_type}, or the "
        "command-line spelling 'FREQ[:TYPE],…' (Hz), e.g. '5.03:torsion,6.11:rhombic,8.84:first "
        "vertical bending'")
    variables: list[Literal[tuple(BOUNDS)]] | None = Field(  # type: ignore[valid-type]
        None, min_length=1, max_length=len(BOUNDS),
        description="Calibration variables updated (null: those of the default body's "
        "calibration, fem/defaults.py: " + ", ".join(DEFAULT_BODY_VARIABLES) + ")")
    max_evaluations: int = quantity(
        30, ge=least_budget(1), le=MAX_CALIBRATION_EVALUATIONS, unit="-",
        description="Budget of FE evaluations of the calibration, at least 2 × (variables + "
        "1) (18 with the default variables), at most "
        f"{MAX_CALIBRATION_EVALUATIONS}: one evaluation takes about 5 s at 0.2 m elements "
        "on 2 cores (60: about 5–6 min), 0.4 s at 0.5 m; run once per distinct input (FE "
        "cache)")
    n_modes: int | None = quantity(
        None, ge=1, le=MAX_CALIBRATION_MODES, unit="-",
        description="Elastic modes computed and classified per evaluation, the ones targets "
        "can pair with (null: 3 × targets, at least targets + 6)")

    @field_validator("targets", mode="before")
    @classmethod
    def _spelled_targets(cls, value: Any) -> Any:
        return _target_items(value)

    @model_validator(mode="after")
    def _budget_and_modes(self) -> CarBodyCalibration:
        n_var = len(self.variables or DEFAULT_BODY_VARIABLES)
        least = least_budget(n_var)
        if self.max_evaluations < least:
            raise ValueError(
                f"max_evaluations {self.max_evaluations} is too small for {n_var} variables: "
                f"allowed {least}–{MAX_CALIBRATION_EVALUATIONS} (2 × (variables + 1): two "
                "least-squares steps)")
        if self.variables is not None and len(set(self.variables)) != len(self.variables):
            raise ValueError("variables: a variable is named twice")
        if self.n_modes is not None and self.n_modes < len(self.targets):
            raise ValueError(f"n_modes {self.n_modes} cannot pair {len(self.targets)} targets: "
                             f"allowed {len(self.targets)}–{MAX_CALIBRATION_MODES}")
        return self

    @property
    def variable_names(self) -> tuple[str, ...]:
        """The variables updated (the default body's when none are named)."""
        return tuple(self.variables or DEFAULT_BODY_VARIABLES)

    def targets_spelling(self) -> str:
        """The targets in the command-line spelling (``5.03:torsion,6.11``)."""
        return ",".join(t.spelling() for t in self.targets)


class BodyModel(Schema):
    """How one body (or both bogie frames) is modelled."""

    model: Literal["rigid", "flexible", "beam"] = Field(
        "rigid",
        description="Rigid, flexible (from the FE model) or beam (the car body only: a "
        "free–free Euler–Bernoulli beam bending first at first_bending_hz)")
    reduction: Literal["modal", "guyan", "craig-bampton"] = Field(
        "modal",
        description="Reduction of the FE model (free-interface modal truncation, Guyan, "
        "Craig–Bampton)",
    )
    cutoff_hz: float = quantity(
        40.0, gt=1.0, le=500.0, description="Highest elastic mode frequency kept", unit="Hz"
    )
    damping_ratio: float = quantity(
        0.02,
        ge=0.0,
        le=0.5,
        unit="-",
        description="Damping ratio of the elastic modes: "
        "of every mode (modal), or of the first two (rayleigh)",
    )
    damping_model: Literal["modal", "rayleigh"] = Field(
        "modal",
        description="Damping of the elastic modes: modal (the same ratio for every "
        "mode) or rayleigh (C = αM + βK through the first two elastic modes, paper Eqs. 2–4; "
        "the ratio grows with frequency above them)",
    )
    element_size_m: float = quantity(
        0.2, ge=0.05, le=1.0, description="Finite-element size of the generated mesh", unit="m"
    )
    first_bending_hz: float = quantity(
        10.0, ge=2.0, le=50.0, unit="Hz",
        description="First vertical bending frequency of the beam car body (model: beam)",
    )
    beam_mass: Literal["pitch_inertia", "uniform"] = Field(
        "pitch_inertia",
        description="Mass distribution of the beam car body (model: beam): pitch_inertia (a "
        "uniform beam plus point masses at its ends, or its centre, carrying the vehicle's mass "
        "and pitch inertia) or uniform (mass spread evenly, the classical beam of the "
        "literature, whose pitch inertia mL²/12 is not the vehicle's)",
    )

    calibration: CarBodyCalibration | None = Field(
        None,
        description="The car body only (model: flexible): calibrate the FE model to typed "
        "target modes when it is built (null: the default body, calibrated to paper Table 1 "
        "once and stored in fem/defaults.py); ignored for the rigid and beam car bodies",
    )

    @property
    def elastic(self) -> bool:
        """Whether the body has elastic modes (kept up to ``cutoff_hz``)."""
        return self.model != "rigid"

    @property
    def finite_elements(self) -> bool:
        """Whether the body is built from its finite-element model."""
        return self.model == "flexible"


class BodyModels(Schema):
    """Modelling choice for the car body and the bogie frames (wheelsets are always rigid)."""

    carbody: BodyModel = Field(
        default_factory=BodyModel, description="Car body: rigid, or flexible from its FE model"
    )
    frames: BodyModel = Field(
        default_factory=BodyModel,
        description="Both bogie frames: rigid, or flexible from their FE model",
    )

    @field_validator("frames")
    @classmethod
    def _frames_are_no_beams(cls, frames: BodyModel) -> BodyModel:
        if frames.model == "beam":
            raise ValueError("model beam is a car-body model; the frames are rigid or "
                             "flexible")
        if frames.calibration is not None:
            raise ValueError("calibration is the car body's (its mode types); the frames have "
                             "none: remove bodies.frames.calibration")
        return frames

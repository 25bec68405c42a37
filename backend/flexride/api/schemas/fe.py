"""Bodies of the FE mesh and mode-shape routes."""

from __future__ import annotations

from typing import Any, Literal

from pydantic import (
    BaseModel,
    Field,
)

# -- FE meshes and mode shapes ---------------------------------------------------------------


class FEMode(BaseModel):
    """One elastic mode shape of an FE export."""

    index: int = Field(description="Mode number (1 = lowest elastic mode)")
    frequency_hz: float = Field(description="Natural frequency (Hz)")
    classification: str = Field(description="Kind of mode (bending, torsion...) or empty")
    scale_m: float = Field(description="Largest nodal translation of the mass-normalised "
                           "shape (m); the displacements are divided by it")
    displacements: list[list[float]] = Field(
        description="Per node [dx, dy, dz], scaled to a largest translation of 1")


class FEModeEstimate(BaseModel):
    """One mode's discretisation estimate (two meshes, assumed order)."""

    index: int = Field(description="Mode number (1 = lowest elastic mode)")
    type: str = Field(description="Its classification")
    frequency_hz: float | None = Field(description="Frequency on the built mesh (Hz)")
    companion_hz: float | None = Field(description="The same mode on the coarser companion "
                                       "mesh (Hz); null where none was found")
    renamed: bool = Field(description="The companion's mode has another classification")
    gci: float | None = Field(description="Grid convergence index (-, relative): the converged "
                              "frequency is expected within ± gci of the built one")


class FEDiscretisation(BaseModel):
    """How far the built model's frequencies are expected to be from converged: the build and
    a coarser companion mesh, Richardson's extrapolation at the elements' order, Roache's GCI
    with safety factor 3 (docs/fem.md, "Mesh convergence").
    """

    element_size_m: float = Field(description="The model's element size (m): the car body's "
                                  "shells or the frame's beams")
    companion_element_size_m: float = Field(description="The companion's element size (m)")
    assumed_order: float = Field(description="Order of convergence assumed (-)")
    modes: list[FEModeEstimate]


class FEPair(BaseModel):
    """One calibration target and the model mode paired with it (``flexride fe calibrate``'s
    rules: by type, then frequency; an optimal assignment over all targets).
    """

    target_hz: float = Field(description="Target frequency (Hz)")
    target_type: str | None = Field(description="Wanted mode type; null: any")
    label: str = Field(description="The target's name, or empty")
    mode: int | None = Field(description="Paired elastic mode (1 = lowest); null: unpaired")
    model_hz: float | None = Field(description="The paired mode's frequency (Hz)")
    error: float | None = Field(description="Relative frequency error model/target − 1 (-)")
    model_type: str | None = Field(description="The paired mode's type (the classifier's)")
    mac: float | None = Field(description="MAC with the target's shape (none here: null)")
    message: str = Field(description="Why the target is unpaired; empty when paired")


class FECalibration(BaseModel):
    """How a car body was calibrated to typed targets when it was built
    (``bodies.carbody.calibration``, ``calibration_targets``).
    """

    targets: str = Field(description="The targets, FREQ[:TYPE],… (Hz)")
    values: dict[str, float] = Field(description="Calibrated variables (SI: m, or -)")
    initial: dict[str, float] = Field(description="Their starting values (the default body's)")
    at_bound: list[str] = Field(description="Variables that ended on a bound")
    pairs: list[FEPair] = Field(description="Each target with its paired mode at the "
                                "calibrated values (among the calibration's computed modes)")
    initial_frequencies_hz: list[float | None] = Field(
        description="Frequency of each target's paired mode at the starting values (Hz)")
    errors: list[float | None] = Field(description="Relative error of each pair (-)")
    success: bool = Field(description="Every target paired and within the tolerance")
    tolerance: float = Field(description="Relative error accepted (-)")
    n_evaluations: int = Field(description="FE evaluations the calibration took")
    max_evaluations: int = Field(description="Its budget")
    seconds: float = Field(description="Wall time of the calibration when it ran (s)")
    element_size_m: float = Field(description="Element size it ran at (m)")
    key: str = Field(description="Content key of the calibration in the FE cache")
    from_cache: bool = Field(description="Loaded from the FE cache (no calibration ran)")


class FEModelInfo(BaseModel):
    """What an FE export was built from."""

    kind: Literal["carbody", "frame"]
    reduction: str
    cutoff_hz: float = Field(description="Highest elastic mode frequency kept (Hz)")
    element_size_m: float = Field(description="Car-body shell element size (m)")
    max_modes: int = Field(description="Mode shapes exported at most")
    key: str = Field(description="Content key of the export")
    n_nodes: int
    n_elastic_modes: int = Field(description="Elastic modes retained below the cut-off")
    frequencies_hz: list[float] = Field(description="Frequencies of all retained modes (Hz)")
    from_cache: bool = Field(description="The reduced body came from the FE cache")
    build_seconds: float = Field(description="Time to build or load the body (s)")
    discretisation: FEDiscretisation | None = Field(
        None, description="The frequencies' expected discretisation error")
    calibration: FECalibration | None = Field(
        None, description="A car body calibrated at build time (calibration_targets): the "
        "targets, the calibrated values and the pairing; absent for the default body")


class FEExport(BaseModel):
    """FE mesh and mode shapes (the JSON of ``flexride fe export``, plus ``model``)."""

    units: dict[str, str]
    nodes: list[list[float]] = Field(description="Node coordinates [x, y, z] (m): x from the "
                                     "body centre forward, y left, z above top of rail")
    quads: list[list[int]] = Field(description="Shell elements (four node indices)")
    beams: list[list[int]] = Field(description="Beam elements (two node indices)")
    named_nodes: dict[str, int] = Field(description="Attachment and output nodes by name")
    regions: dict[str, Any] | None = Field(None, description="Region names and each node's")
    modes: list[FEMode]
    model: FEModelInfo


class FEBuildStatus(BaseModel):
    """An FE export that is not ready yet (202)."""

    status: Literal["queued", "building"] = Field(
        description="queued: the build job waits for a worker; building: it runs")
    key: str = Field(description="Content key of the export")
    parameters: dict[str, Any] = Field(description="kind, reduction, cutoff_hz, "
                                       "element_size_m, max_modes; calibration (its "
                                       "targets, variables, budget) for a calibrated car body")
    job_id: str | None = Field(None, description="The build job (kind fe_export): GET "
                               "/jobs/{id} follows it, POST /jobs/{id}/cancel cancels it")
    progress: float = Field(0.0, description="Fraction of the build done (0–1)")
    elapsed_s: float = Field(description="Seconds since the build was requested")
    retry_after_s: int = Field(description="Ask again after this many seconds "
                               "(also the Retry-After header)")
    message: str


class FEPairing(BaseModel):
    """The pairing of an FE body's lowest modes with calibration targets."""

    pairs: list[FEPair] = Field(description="One per target, in the targets' order")
    modes_considered: int = Field(description="Lowest elastic modes the pairing chose from "
                                  "(those of the export: max_modes)")
    model: FEModelInfo

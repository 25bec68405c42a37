"""Browser exports of flexible bodies: the FE mesh and mode shapes in a form a browser can draw.

:func:`export_mesh` turns nodes, elements and mode shapes into plain lists (the JSON that
``flexride fe export`` writes, :meth:`FlexibleBody.export
<flexride.fem.flexible_body.FlexibleBody.export>`: ``units``, ``nodes``, ``quads``, ``beams``,
``named_nodes``, ``regions``, ``modes``).

The service's export adds a ``model`` block that says what was built, and is determined by an
:class:`ExportSpec`: body kind, vehicle parameters (inertia targets and suspension geometry) and
the body-model settings of a scenario (``bodies.carbody`` / ``bodies.frames``: reduction,
cut-off, element size) plus the number of modes exported; it is keyed by content and written to
a file atomically (:func:`write_export`, :func:`export_path`). The service builds exports as
jobs of kind ``fe_export`` (:mod:`flexride.study.run_job`, in the job runner's worker processes)
through the FE cache (:mod:`flexride.fem.cache`), so a body that a job already built is
exported in a fraction of a second; the API only serves the files
(``flexride.api.services.fe``).
"""

from __future__ import annotations

import hashlib
import json
import os
from collections.abc import Callable, Mapping
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from flexride.errors import FEModelError
from flexride.fileio import write_bytes_atomic
from flexride.scenario.bodies import BodyModel, CarBodyCalibration
from flexride.scenario.vehicle import Vehicle

#: Body kinds with an FE model, and the field of ``scenario.bodies`` that configures each.
BODY_FIELDS: dict[str, str] = {"carbody": "carbody", "frame": "frames"}
#: Bump when the content of an export file changes.
EXPORT_FORMAT = 2  # 2: the model block's discretisation estimate
#: Default number of exported modes (as ``flexride fe export --n-modes``).
DEFAULT_MAX_MODES = 12
#: What a body kind is called in messages.
BODY_LABELS: dict[str, str] = {"carbody": "car body", "frame": "bogie frame"}

Progress = Callable[[float, str], None]
"""``progress(fraction, message)`` of a build."""


def export_mesh(
    nodes: np.ndarray,
    quads: np.ndarray,
    beams: np.ndarray,
    frequencies: np.ndarray | None = None,
    shapes: np.ndarray | None = None,
    classification: list[str] | None = None,
    max_modes: int = 12,
    named_nodes: dict[str, int] | None = None,
    node_region: np.ndarray | None = None,
    region_names: list[str] | None = None,
    digits: int = 4,
) -> dict:
    """Nodes, elements and mode shapes as plain lists.

    Parameters
    ----------
    nodes : numpy.ndarray
        (n, 3) coordinates (m).
    quads, beams : numpy.ndarray
        (nq, 4) and (nb, 2) node indices.
    frequencies : numpy.ndarray, optional
        Elastic frequencies (Hz).
    shapes : numpy.ndarray, optional
        (n, 6, n_modes) elastic shapes; the translations are exported, each mode scaled so its
        largest nodal translation is 1 (``scale`` gives the factor back to unit modal mass).
    classification : list of str, optional
        Name of each mode.
    max_modes : int
        Number of modes exported.
    named_nodes, node_region, region_names : optional
        Extra annotations.
    digits : int
        Decimals kept.

    Returns
    -------
    dict
        ``{"units", "nodes", "quads", "beams", "named_nodes", "regions", "modes"}``, where each
        mode is ``{"index", "frequency_hz", "classification", "scale_m", "displacements"}``.
    """
    out: dict = {
        "units": {"length": "m", "frequency": "Hz"},
        "nodes": np.round(np.asarray(nodes, float), digits).tolist(),
        "quads": np.asarray(quads, dtype=int).tolist(),
        "beams": np.asarray(beams, dtype=int).tolist(),
        "named_nodes": dict(named_nodes or {}),
        "modes": [],
    }
    if node_region is not None and region_names:
        out["regions"] = {
            "names": list(region_names),
            "node_region": np.asarray(node_region).tolist(),
        }
    if frequencies is not None and shapes is not None:
        for k in range(min(max_modes, len(frequencies))):
            u = shapes[:, :3, k]
            s = float(np.max(np.abs(u))) or 1.0
            out["modes"].append(
                {
                    "index": k + 1,
                    "frequency_hz": float(frequencies[k]),
                    "classification": classification[k] if classification else "",
                    "scale_m": s,
                    "displacements": np.round(u / s, digits).tolist(),
                }
            )
    return out


@dataclass(frozen=True)
class ExportSpec:
    """Everything that determines an export.

    Attributes
    ----------
    kind : {"carbody", "frame"}
        Which FE model.
    vehicle : dict
        Vehicle parameters (JSON form of :class:`~flexride.scenario.vehicle.Vehicle`).
    reduction : {"modal", "guyan", "craig-bampton"}
        Reduction of the FE model.
    cutoff_hz : float
        Highest elastic mode frequency kept (Hz).
    element_size_m : float
        Car-body shell element size (m); the frame uses ``min(element_size_m / 2, 0.1)``.
    max_modes : int
        Number of mode shapes exported (the lowest ones).
    calibration : dict or None
        The car body only: the JSON form of a
        :class:`~flexride.scenario.bodies.CarBodyCalibration` (``bodies.carbody.calibration``:
        typed targets, variables, evaluation budget) to calibrate the model to before it is
        reduced; None: the default body. Not part of the content key when None, so the
        default body's exports keep theirs.
    """

    kind: str
    vehicle: dict[str, Any]
    reduction: str
    cutoff_hz: float
    element_size_m: float
    max_modes: int
    calibration: dict[str, Any] | None = None

    @classmethod
    def create(cls, kind: str, vehicle: Vehicle, body: BodyModel,
               max_modes: int = DEFAULT_MAX_MODES) -> ExportSpec:
        """The spec of body ``kind`` of ``vehicle`` modelled as ``body``.

        Parameters
        ----------
        kind : {"carbody", "frame"}
            Which FE model.
        vehicle : Vehicle
            Validated vehicle parameters.
        body : BodyModel
            Reduction, cut-off (Hz), element size (m) and, for the car body, calibration
            (``scenario.bodies.*``).
        max_modes : int
            Number of mode shapes exported.

        Raises
        ------
        ValueError
            For an unknown kind, or a calibration of the frame.
        """
        if kind not in BODY_FIELDS:
            raise ValueError(f"unknown body kind {kind!r}: use carbody or frame")
        if kind != "carbody" and body.calibration is not None:
            raise ValueError("a calibration is the car body's: the frame has none")
        cal = None if body.calibration is None else body.calibration.model_dump(mode="json")
        return cls(kind=kind, vehicle=vehicle.model_dump(mode="json"),
                   reduction=body.reduction, cutoff_hz=float(body.cutoff_hz),
                   element_size_m=float(body.element_size_m), max_modes=int(max_modes),
                   calibration=cal)

    @property
    def key(self) -> str:
        """Content key: SHA-256 (32 hex digits) of the spec, the flexride version and the
        export format.
        """
        from flexride import __version__

        spec = asdict(self)
        if spec["calibration"] is None:  # the default body's keys as before the field
            del spec["calibration"]
        payload = {"spec": spec, "flexride": __version__, "format": EXPORT_FORMAT}
        text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()[:32]

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> ExportSpec:
        """The spec stored as ``asdict(spec)`` (an FE export job's ``scenario``).

        Raises
        ------
        FEModelError
            When ``data`` is not such a spec.
        """
        fields = {"kind", "vehicle", "reduction", "cutoff_hz", "element_size_m", "max_modes"}
        try:
            if set(data) - {"calibration"} != fields or data["kind"] not in BODY_FIELDS:
                raise ValueError(f"fields {sorted(data)}")
            cal = data.get("calibration")
            return cls(kind=str(data["kind"]), vehicle=dict(data["vehicle"]),
                       reduction=str(data["reduction"]), cutoff_hz=float(data["cutoff_hz"]),
                       element_size_m=float(data["element_size_m"]),
                       max_modes=int(data["max_modes"]),
                       calibration=None if cal is None else dict(cal))
        except (TypeError, ValueError, KeyError) as exc:
            raise FEModelError(f"not an FE export spec: {exc}") from None

    def parameters(self) -> dict[str, Any]:
        """The body-model parameters (names and units of the scenario's ``bodies`` schema),
        with ``calibration`` (its JSON form) for a calibrated car body.
        """
        out: dict[str, Any] = {"kind": self.kind, "reduction": self.reduction,
                               "cutoff_hz": self.cutoff_hz,
                               "element_size_m": self.element_size_m,
                               "max_modes": self.max_modes}
        if self.calibration is not None:
            out["calibration"] = self.calibration
        return out

    def body_calibration(self) -> CarBodyCalibration | None:
        """The calibration, validated (None for the default body).

        Raises
        ------
        FEModelError
            When the stored calibration is not a valid one.
        """
        if self.calibration is None:
            return None
        try:
            return CarBodyCalibration.model_validate(self.calibration)
        except ValueError as exc:
            raise FEModelError(f"not a car-body calibration: {exc}") from None


def export_path(cache_dir: str | os.PathLike[str], key: str) -> Path:
    """Where the service keeps the export of content key ``key``:
    ``<cache_dir>/fe-export-<version>/<key>.json``.
    """
    from flexride import __version__

    return Path(cache_dir) / f"fe-export-{__version__}" / f"{key}.json"


def _no_progress(_fraction: float, _message: str) -> None:
    pass


def build_export(spec: ExportSpec, progress: Progress = _no_progress) -> dict[str, Any]:
    """Build (or load from the FE cache) the body of ``spec`` and export it.

    Parameters
    ----------
    spec : ExportSpec
        What to build.
    progress : callable, optional
        ``progress(fraction, message)``, told when the build and the export start.

    Returns
    -------
    dict
        The ``flexride fe export`` JSON (nodes in m, frequencies in Hz, each mode scaled to a
        largest nodal translation of 1 with ``scale_m`` back to unit modal mass) plus ``model``:
        the parameters, ``n_nodes``, ``n_elastic_modes`` retained below the cut-off,
        ``frequencies_hz`` of all of them, ``from_cache`` and ``build_seconds`` (s); for a
        calibrated car body ``calibration`` (the targets, calibrated values and pairing:
        :meth:`flexride.fem.calibrated_body.CalibratedCarBody.summary`).

    Raises
    ------
    FlexrideError
        If the FE model cannot be built with these parameters.
    """
    from flexride.fem.flexible import build_flexible_body
    from flexride.fem.mesh_study import build_estimate

    vehicle = Vehicle.model_validate(spec.vehicle)
    calibration = spec.body_calibration()
    label = BODY_LABELS[spec.kind]
    if calibration is not None:
        budget = calibration.max_evaluations
        progress(0.02, f"building the FE model of the {label}: calibrating it to "
                 f"{calibration.targets_spelling()} (at most {budget} FE evaluations; "
                 f"loaded from the FE cache when done before), then mesh, eigenmodes, "
                 f"{spec.reduction} reduction")

        def calibrating(n: int, freqs: np.ndarray) -> None:
            hz = ", ".join("-" if np.isnan(f) else f"{f:.2f}" for f in freqs)
            progress(0.02 + 0.6 * min(n, budget) / budget,
                     f"building the FE model of the {label}: calibration evaluation {n} of at "
                     f"most {budget} (paired modes {hz} Hz)")
    else:
        progress(0.05, f"building the FE model of the {label} (mesh, eigenmodes, "
                 f"{spec.reduction} reduction; loaded from the FE cache when a job built it)")
    fb = build_flexible_body(spec.kind, vehicle, method=spec.reduction,  # type: ignore[arg-type]
                             cutoff_hz=spec.cutoff_hz, element_size=spec.element_size_m,
                             name=spec.kind, calibration=calibration,
                             calibration_progress=None if calibration is None else calibrating)
    progress(0.9, f"exporting the mesh and {spec.max_modes} mode shapes")
    data = fb.export(max_modes=spec.max_modes)
    freqs = [float(f) for f in fb.body.elastic_frequencies]
    progress(0.95, "estimating the discretisation error from a coarser companion mesh")
    data["model"] = {
        **spec.parameters(),
        "key": spec.key,
        "n_nodes": len(data["nodes"]),
        "n_elastic_modes": len(freqs),
        "frequencies_hz": freqs,
        "from_cache": bool(fb.from_cache),
        "build_seconds": float(fb.build_seconds),
        "discretisation": build_estimate(
            spec.kind, vehicle, model_element_size(spec),
            max(1, min(spec.max_modes, DEFAULT_MAX_MODES)),
            None if calibration is None else params_of(fb)),
    }
    if fb.calibration is not None:
        data["model"]["calibration"] = fb.calibration
    return data


def params_of(fb: Any) -> Any:
    """The car-body parameters a calibrated :class:`~flexride.fem.flexible_body.FlexibleBody`
    was built from (its calibrated values on the defaults).
    """
    from flexride.fem.carbody import CarBodyParams
    from flexride.fem.defaults import default_carbody_params

    base: CarBodyParams = default_carbody_params()
    return base.with_values(**fb.calibration["values"])


def model_element_size(spec: ExportSpec) -> float:
    """The element size (m) the FE model of ``spec`` is built with: the car body's shells,
    or the frame's beams (half the car body's size, at most 0.1 m).
    """
    from flexride.fem.vehicle_models import frame_element_size

    size = spec.element_size_m
    return size if spec.kind == "carbody" else frame_element_size(size)


def write_export(spec: ExportSpec, dest: str | os.PathLike[str],
                 progress: Progress = _no_progress) -> dict[str, Any]:
    """Build the export of ``spec`` and write it to ``dest`` atomically (temporary file in the
    same directory, then rename).

    Parameters
    ----------
    spec : ExportSpec
        What to build.
    dest : path-like
        The JSON file to write; parent directories are created.
    progress : callable, optional
        ``progress(fraction, message)`` (see :func:`build_export`).

    Returns
    -------
    dict
        The export's ``model`` block.
    """
    data = build_export(spec, progress)
    write_json_atomic(dest, data)
    return data["model"]


def write_json_atomic(dest: str | os.PathLike[str], data: dict[str, Any]) -> None:
    """Write an export (compact JSON, no NaN) to ``dest`` atomically."""
    text = json.dumps(data, separators=(",", ":"), allow_nan=False)
    write_bytes_atomic(dest, text.encode("utf-8"))

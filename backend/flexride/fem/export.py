"""Browser exports of flexible bodies: the FE mesh and mode shapes in a form a browser can draw.

:func:`export_mesh` turns nodes, elements and mode shapes into plain lists (the JSON that
``flexride fe export`` writes, :meth:`FlexibleBody.export
<flexride.fem.flexible_body.FlexibleBody.export>`: ``units``, ``nodes``, ``quads``, ``beams``,
``named_nodes``, ``regions``, ``modes``).

The service's export adds a ``model`` block that says what was built, and is determined by an
:class:`ExportSpec`: body kind, vehicle parameters (inertia targets and suspension geometry) and
the body-model settings of a scenario (``bodies.carbody`` / ``bodies.frames``: reduction,
cut-off, element size) plus the number of modes exported; it is keyed by content and written to
a file atomically. The API builds exports in a separate process (:func:`run_export_job`) through
the FE cache (:mod:`flexride.fem.cache`), so a body that a job already built is exported in a
fraction of a second, and serves the files (``flexride.api.services.fe``).
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from flexride.errors import FlexrideError
from flexride.fileio import write_bytes_atomic
from flexride.model.bodies import BodyModel
from flexride.model.vehicle import Vehicle

#: Body kinds with an FE model, and the field of ``scenario.bodies`` that configures each.
BODY_FIELDS: dict[str, str] = {"carbody": "carbody", "frame": "frames"}
#: Bump when the content of an export file changes.
EXPORT_FORMAT = 1
#: Default number of exported modes (as ``flexride fe export --n-modes``).
DEFAULT_MAX_MODES = 12


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
        Vehicle parameters (JSON form of :class:`~flexride.model.vehicle.Vehicle`).
    reduction : {"modal", "guyan", "craig-bampton"}
        Reduction of the FE model.
    cutoff_hz : float
        Highest elastic mode frequency kept (Hz).
    element_size_m : float
        Car-body shell element size (m); the frame uses ``min(element_size_m / 2, 0.1)``.
    max_modes : int
        Number of mode shapes exported (the lowest ones).
    """

    kind: str
    vehicle: dict[str, Any]
    reduction: str
    cutoff_hz: float
    element_size_m: float
    max_modes: int

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
            Reduction, cut-off (Hz) and element size (m) (``scenario.bodies.*``).
        max_modes : int
            Number of mode shapes exported.
        """
        if kind not in BODY_FIELDS:
            raise ValueError(f"unknown body kind {kind!r}: use carbody or frame")
        return cls(kind=kind, vehicle=vehicle.model_dump(mode="json"),
                   reduction=body.reduction, cutoff_hz=float(body.cutoff_hz),
                   element_size_m=float(body.element_size_m), max_modes=int(max_modes))

    @property
    def key(self) -> str:
        """Content key: SHA-256 (32 hex digits) of the spec, the flexride version and the
        export format."""
        from flexride import __version__

        payload = {"spec": asdict(self), "flexride": __version__, "format": EXPORT_FORMAT}
        text = json.dumps(payload, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()[:32]

    def parameters(self) -> dict[str, Any]:
        """The body-model parameters (names and units of the scenario's ``bodies`` schema)."""
        return {"kind": self.kind, "reduction": self.reduction, "cutoff_hz": self.cutoff_hz,
                "element_size_m": self.element_size_m, "max_modes": self.max_modes}


def build_export(spec: ExportSpec) -> dict[str, Any]:
    """Build (or load from the FE cache) the body of ``spec`` and export it.

    Parameters
    ----------
    spec : ExportSpec
        What to build.

    Returns
    -------
    dict
        The ``flexride fe export`` JSON (nodes in m, frequencies in Hz, each mode scaled to a
        largest nodal translation of 1 with ``scale_m`` back to unit modal mass) plus ``model``:
        the parameters, ``n_nodes``, ``n_elastic_modes`` retained below the cut-off,
        ``frequencies_hz`` of all of them, ``from_cache`` and ``build_seconds`` (s).

    Raises
    ------
    FlexrideError
        If the FE model cannot be built with these parameters.
    """
    from flexride.fem.flexible import build_flexible_body

    vehicle = Vehicle.model_validate(spec.vehicle)
    fb = build_flexible_body(spec.kind, vehicle, method=spec.reduction,  # type: ignore[arg-type]
                             cutoff_hz=spec.cutoff_hz, element_size=spec.element_size_m,
                             name=spec.kind)
    data = fb.export(max_modes=spec.max_modes)
    freqs = [float(f) for f in fb.body.elastic_frequencies]
    data["model"] = {
        **spec.parameters(),
        "key": spec.key,
        "n_nodes": len(data["nodes"]),
        "n_elastic_modes": len(freqs),
        "frequencies_hz": freqs,
        "from_cache": bool(fb.from_cache),
        "build_seconds": float(fb.build_seconds),
    }
    return data


def write_export(spec: ExportSpec, dest: str | os.PathLike[str]) -> dict[str, Any]:
    """Build the export of ``spec`` and write it to ``dest`` atomically (temporary file in the
    same directory, then rename).

    Parameters
    ----------
    spec : ExportSpec
        What to build.
    dest : path-like
        The JSON file to write; parent directories are created.

    Returns
    -------
    dict
        The export's ``model`` block.
    """
    data = build_export(spec)
    text = json.dumps(data, separators=(",", ":"), allow_nan=False)
    write_bytes_atomic(dest, text.encode("utf-8"))
    return data["model"]


def init_build_process(cache_dir: str) -> None:
    """Initialiser of a build process: the FE cache under ``cache_dir`` (the service's
    ``FLEXRIDE_CACHE_DIR``) and one BLAS thread (the process shares the machine with the API
    and the job workers)."""
    os.environ["FLEXRIDE_CACHE_DIR"] = str(cache_dir)
    from flexride.jobs.warmup import limit_blas_threads, single_threaded_env

    single_threaded_env()
    limit_blas_threads(1)


def run_export_job(spec: ExportSpec, dest: str) -> dict[str, Any]:
    """Build and write one export (the function a build process runs).

    Parameters
    ----------
    spec : ExportSpec
        What to build.
    dest : str
        The JSON file to write.

    Returns
    -------
    dict
        ``{"ok": True, "model": {...}, "seconds": s}``, or ``{"ok": False, "error": message,
        "type": exception class}`` when the parameters do not give an FE model
        (:class:`~flexride.errors.FlexrideError`). Other exceptions propagate.
    """
    t0 = time.perf_counter()
    try:
        model = write_export(spec, dest)
    except FlexrideError as exc:
        return {"ok": False, "error": str(exc), "type": type(exc).__name__}
    return {"ok": True, "model": model, "seconds": time.perf_counter() - t0}

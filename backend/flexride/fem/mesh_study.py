"""Convergence of a body's natural frequencies under mesh refinement.

The body (car body or bogie frame, mass-matched to the vehicle) is built at each element size;
its lowest elastic modes are computed and classified, and each mode of the finest mesh is
followed to the coarser meshes: the same classification, the nearest frequency, in one optimal
assignment per mesh (so that two modes whose order swaps between meshes are not confused).
For every followed mode, the three finest meshes give the observed order, the extrapolated
frequency and the fine mesh's grid convergence index (:mod:`flexride.fem.convergence`).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linear_sum_assignment

from flexride.errors import FEModelError
from flexride.fem.classify import classify_mode, classify_plane_frame_mode
from flexride.fem.convergence import (
    ELEMENT_ORDER,
    ConvergenceEstimate,
    three_mesh_estimate,
    two_mesh_estimate,
)
from flexride.fem.eigen import free_free_modes
from flexride.fem.frame import build_frame
from flexride.fem.model import FEModel
from flexride.fem.rigid import rigid_body_vectors
from flexride.fem.vehicle_models import build_fe_model, frame_params_for, frame_target

#: Element size of a build's coarser companion, relative to the build's.
COMPANION_RATIO = 1.5

#: Extra cost of following a mode to one of another classification (in |ln f ratio| units:
#: a name change weighs like a factor e² in frequency, so it happens only when no mode of the
#: same name is left).
_RENAMED_COST = 2.0

Progress = Callable[[int, int, float], None]
"""``progress(done, total, element_size)`` after each mesh."""


@dataclass(frozen=True)
class MeshModes:
    """The lowest elastic modes of the body on one mesh.

    Attributes
    ----------
    element_size : float
        Element size (m).
    n_dof : int
        Degrees of freedom of the model.
    frequencies_hz : tuple of float
        Elastic frequencies (Hz), ascending.
    types : tuple of str
        Classification of each mode.
    seconds : float
        Time to build and solve (s).
    """

    element_size: float
    n_dof: int
    frequencies_hz: tuple[float, ...]
    types: tuple[str, ...]
    seconds: float


@dataclass(frozen=True)
class FollowedMode:
    """One mode of the finest mesh followed through the meshes.

    Attributes
    ----------
    index : int
        Mode number on the finest mesh (1 = lowest elastic mode).
    type : str
        Its classification on the finest mesh.
    frequencies_hz : tuple of float or None
        Its frequency on each mesh (the study's order of sizes); None where it was not found.
    renamed : tuple of bool
        Whether the mode followed on each mesh had another classification.
    estimate : ConvergenceEstimate or None
        From the three finest meshes where it was found on all three.
    """

    index: int
    type: str
    frequencies_hz: tuple[float | None, ...]
    renamed: tuple[bool, ...]
    estimate: ConvergenceEstimate | None


@dataclass(frozen=True)
class FrequencyConvergence:
    """The study's result (see the module docs).

    Attributes
    ----------
    kind : {"carbody", "frame"}
        The body.
    meshes : tuple of MeshModes
        One per element size, coarse to fine.
    modes : tuple of FollowedMode
        The finest mesh's modes, followed.
    """

    kind: str
    meshes: tuple[MeshModes, ...]
    modes: tuple[FollowedMode, ...]

    @property
    def sizes(self) -> tuple[float, ...]:
        """Element sizes (m), coarse to fine."""
        return tuple(m.element_size for m in self.meshes)

    def to_dict(self) -> dict:
        """JSON-able dict."""
        return {
            "kind": self.kind,
            "element_sizes_m": list(self.sizes),
            "meshes": [{"element_size_m": m.element_size, "n_dof": m.n_dof,
                        "frequencies_hz": list(m.frequencies_hz), "types": list(m.types),
                        "seconds": m.seconds} for m in self.meshes],
            "modes": [{"index": f.index, "type": f.type,
                       "frequencies_hz": list(f.frequencies_hz), "renamed": list(f.renamed),
                       "estimate": None if f.estimate is None else f.estimate.to_dict()}
                      for f in self.modes],
        }

    def table(self) -> str:
        """A readable table: each mode's frequency per mesh, order, extrapolation, GCI."""
        head = " ".join(f"{s:>8g} m" for s in self.sizes)
        lines = [f"{'mode':>4}  {'type':<34} {head}   {'order':>5} {'f_ext Hz':>9} "
                 f"{'GCI %':>6}  finest vs f_ext"]
        for f in self.modes:
            cells = " ".join("       –  " if v is None else f"{v:9.3f}{'*' if r else ' '}"
                             for v, r in zip(f.frequencies_hz, f.renamed, strict=True))
            lines.append(f"{f.index:4d}  {f.type[:34]:<34} {cells}   {_estimate_cells(f)}")
        lines.append("* followed to a mode of another classification on that mesh")
        return "\n".join(lines)


def _estimate_cells(f: FollowedMode) -> str:
    """Order, extrapolated frequency, GCI and the finest mesh's error of one mode."""
    e = f.estimate
    if e is None:
        return "(not on the three finest meshes)"
    osc = " oscillating" if e.oscillatory else ""
    return (f"{e.order:5.2f} {e.extrapolated:9.3f} {100 * e.gci_fine:6.2f}  "
            f"{100 * (e.values[0] / e.extrapolated - 1):+.2f} %{osc}")


def frequency_convergence(kind: str, vehicle, sizes: Sequence[float], n_modes: int = 8,
                          progress: Progress | None = None) -> FrequencyConvergence:
    """Natural frequencies of ``kind`` for ``vehicle`` at the element ``sizes`` (m), followed
    mode by mode from the finest mesh, with three-mesh estimates.

    Parameters
    ----------
    kind : {"carbody", "frame"}
        The body.
    vehicle : flexride.scenario.vehicle.Vehicle
        The vehicle the body is mass-matched to.
    sizes : sequence of float
        At least three distinct element sizes (m): the car body's shells, the frame's beams.
    n_modes : int
        Elastic modes of the finest mesh to follow; the coarser meshes compute twice as many
        (a mode may lie higher there).
    progress : callable, optional
        Called after each mesh.

    Raises
    ------
    FEModelError
        Fewer than three distinct sizes, or a size the body's builder refuses.
    """
    ordered = sorted({float(s) for s in sizes}, reverse=True)
    if len(ordered) < 3:
        raise FEModelError(f"a convergence study needs at least three distinct element sizes, "
                           f"got {list(sizes)}")
    meshes: list[MeshModes] = []
    for k, size in enumerate(ordered):
        wanted = n_modes if k == len(ordered) - 1 else 2 * n_modes
        meshes.append(mesh_modes(kind, vehicle, size, wanted))
        if progress is not None:
            progress(k + 1, len(ordered), size)
    return FrequencyConvergence(kind, tuple(meshes), _follow(meshes))


def mesh_modes(kind: str, vehicle, size: float, n_modes: int, params=None) -> MeshModes:
    """The lowest ``n_modes`` elastic modes of ``kind`` at element size ``size`` (m), with
    the car body's ``params`` (e.g. calibrated values) instead of the defaults.
    """
    t0 = time.perf_counter()
    model = fe_model_at(kind, vehicle, size, params)
    K, M = model.assemble()
    modes = free_free_modes(K, M, rigid_body_vectors(model.nodes), n_elastic=n_modes)
    shapes = modes.shapes[:, 6:6 + n_modes]
    if kind == "frame":
        types = [classify_plane_frame_mode(shapes[:, j], M, model.nodes)
                 for j in range(shapes.shape[1])]
    else:
        types = [classify_mode(shapes[:, j], M, model.nodes, model.node_region,
                               model.region_names) for j in range(shapes.shape[1])]
    freqs = tuple(float(v) for v in modes.frequencies[6:6 + n_modes])
    return MeshModes(size, int(model.n_dof), freqs, tuple(types), time.perf_counter() - t0)


def fe_model_at(kind: str, vehicle, size: float, params=None) -> FEModel:
    """The mass-matched FE model of ``kind`` with elements of ``size`` (m): the car body's
    shells, or the frame's beams (not the frame's default of half the car body's size); the
    car body with ``params`` instead of the calibrated defaults when given.
    """
    if kind == "frame":
        if not 0.01 <= size <= 0.5:
            raise FEModelError(f"frame element size must be 0.01–0.5 m, got {size}")
        return build_frame(frame_params_for(vehicle), frame_target(vehicle), size)
    model, _target = build_fe_model(kind, vehicle, size, params)  # type: ignore[arg-type]
    return model


def _follow(meshes: Sequence[MeshModes]) -> tuple[FollowedMode, ...]:
    """Each mode of the finest mesh (the last) followed on every mesh."""
    finest = meshes[-1]
    n = len(finest.frequencies_hz)
    per_mesh = [_assign(finest, m) for m in meshes]  # per mesh: (mode index or None, renamed)
    out = []
    for j in range(n):
        freqs = tuple(_frequency(m, a[j][0]) for m, a in zip(meshes, per_mesh, strict=True))
        renamed = tuple(bool(a[j][1]) for a in per_mesh)
        out.append(FollowedMode(j + 1, finest.types[j], freqs, renamed,
                                _estimate([m.element_size for m in meshes], freqs)))
    return tuple(out)


def _frequency(mesh: MeshModes, index: int | None) -> float | None:
    """Frequency (Hz) of mode ``index`` of ``mesh``, None for no mode."""
    return None if index is None else mesh.frequencies_hz[index]


def _assign(finest: MeshModes, other: MeshModes) -> list[tuple[int | None, bool]]:
    """For each mode of ``finest``: the mode of ``other`` that follows it (optimal assignment
    on |ln f ratio| plus :data:`_RENAMED_COST` for another classification) and whether it was
    renamed.
    """
    f_fine = np.asarray(finest.frequencies_hz)
    f_other = np.asarray(other.frequencies_hz)
    cost = np.abs(np.log(f_other[None, :] / f_fine[:, None]))
    renamed = np.array([[a != b for b in other.types] for a in finest.types])
    cost = cost + _RENAMED_COST * renamed
    rows, cols = linear_sum_assignment(cost)
    chosen = dict(zip(rows.tolist(), cols.tolist(), strict=True))
    return [(chosen.get(j), bool(renamed[j, chosen[j]]) if j in chosen else False)
            for j in range(f_fine.size)]


def _estimate(sizes: Sequence[float], freqs: Sequence[float | None]
              ) -> ConvergenceEstimate | None:
    """Three-mesh estimate from the three finest meshes (the last three), or with two meshes
    the two-mesh one at :data:`ELEMENT_ORDER`; None if the mode is missing on one of them.
    """
    last = list(zip(sizes, freqs, strict=True))[-3:]
    if any(f is None for _, f in last):
        return None
    hs, fs = [s for s, _ in last], [float(f) for _, f in last if f is not None]
    return three_mesh_estimate(hs, fs) if len(last) == 3 else two_mesh_estimate(
        hs, fs, ELEMENT_ORDER)


def build_estimate(kind: str, vehicle, size: float, n_modes: int, params=None) -> dict:
    """A build's own discretisation estimate: its lowest ``n_modes`` elastic modes and those
    of a companion mesh :data:`COMPANION_RATIO` times coarser (capped by the builder's range),
    followed as in the study, and per mode the two-mesh GCI at :data:`ELEMENT_ORDER`.

    Parameters
    ----------
    kind : {"carbody", "frame"}
        The body.
    vehicle : flexride.scenario.vehicle.Vehicle
        The vehicle the body is mass-matched to.
    size : float
        The build's element size (m): the car body's shells or the frame's beams.
    n_modes : int
        Modes to estimate.
    params : CarBodyParams, optional
        The car body's parameters (e.g. calibrated values; both meshes use them) instead of
        the defaults.

    Returns
    -------
    dict
        ``element_size_m``, ``companion_element_size_m``, ``assumed_order`` and ``modes``:
        per mode ``index``, ``type``, ``frequency_hz``, ``companion_hz`` (None if not found),
        ``gci`` (-, None without a companion mode) and ``renamed``.
    """
    cap = 0.5 if kind == "frame" else 1.0
    companion = min(size * COMPANION_RATIO, cap)
    if companion <= size:
        raise FEModelError(f"no coarser companion for element size {size} m (largest {cap} m)")
    meshes = [mesh_modes(kind, vehicle, companion, 2 * n_modes, params),
              mesh_modes(kind, vehicle, size, n_modes, params)]
    modes = []
    for f in _follow(meshes):
        e = f.estimate
        modes.append({"index": f.index, "type": f.type, "frequency_hz": f.frequencies_hz[1],
                      "companion_hz": f.frequencies_hz[0], "renamed": f.renamed[0],
                      "gci": None if e is None else e.to_dict()["gci_fine"]})
    return {"element_size_m": size, "companion_element_size_m": companion,
            "assumed_order": ELEMENT_ORDER, "modes": modes}

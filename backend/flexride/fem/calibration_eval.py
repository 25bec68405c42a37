"""One evaluation of the car body for the calibration: build, solve, classify, pair.

At given values of the calibration variables the mass-matched car body is built, its first
elastic modes are solved and classified, taken at the sensor DOFs, and paired with the targets
(:mod:`flexride.fem.pairing`). Evaluations are remembered by their variable values; the full
mode shapes (needed to follow a mode from one point to the next) only for the last few.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from flexride.errors import FEModelError
from flexride.fem.carbody import CarBodyParams, build_carbody
from flexride.fem.classify import classify_mode
from flexride.fem.eigen import free_free_modes
from flexride.fem.mac import mac
from flexride.fem.massmatch import InertiaTarget
from flexride.fem.modal_test import SensorNodes, Sensors, sensor_nodes
from flexride.fem.pairing import ModelModes, TargetPair, pair_targets
from flexride.fem.rigid import rigid_body_vectors
from flexride.fem.targets import ModeTarget

#: Evaluations whose full mode shapes are kept (the base point of a Jacobian and its steps).
KEEP_SHAPES = 12


@dataclass(frozen=True, eq=False)
class ModelPoint:
    """The car body at one set of variable values.

    Attributes
    ----------
    modes : ModelModes
        Elastic frequencies (Hz), types and shapes at the sensor DOFs.
    pairs : list of TargetPair
        The targets paired with these modes.
    shapes : numpy.ndarray
        (n_dof, n_modes) mass-normalised elastic shapes.
    mass : sparse matrix
        The model's mass matrix (for mass-weighted MAC).
    """

    modes: ModelModes
    pairs: list[TargetPair]
    shapes: np.ndarray
    mass: Any

    def follow(self, mode: int, other: ModelPoint) -> int:
        """The mode of ``other`` (index) most like ``mode`` of this point (mass-weighted MAC
        on all DOFs): the same mode after a small change of the variables.
        """
        return int(np.argmax(mac(self.shapes[:, mode], other.shapes, self.mass)[0]))


@dataclass(frozen=True)
class CalibrationSetup:
    """What every evaluation shares.

    Attributes
    ----------
    base : CarBodyParams
        Parameters other than the variables.
    names : tuple of str
        Calibration variables.
    inertia : InertiaTarget
        Mass, CG and inertias matched at every evaluation.
    element_size : float
        Element size (m).
    n_modes : int
        Elastic modes computed per evaluation.
    targets : tuple of ModeTarget
        The targets.
    sensors : Sensors or None
        Sensor DOFs of the targets' shapes.
    max_sensor_distance : float
        Largest sensor-to-node distance accepted (m).
    min_mac : float
        Least MAC of a pair (-).
    """

    base: CarBodyParams
    names: tuple[str, ...]
    inertia: InertiaTarget
    element_size: float
    n_modes: int
    targets: tuple[ModeTarget, ...]
    sensors: Sensors | None
    max_sensor_distance: float
    min_mac: float


class Evaluations:
    """The car body evaluated at the log-values ``z`` of the variables, each point once
    (remembered at 12 decimals of ``z``).

    Attributes
    ----------
    history : list of dict
        Every FE evaluation: ``values`` (SI), ``frequencies`` (Hz of each target's paired
        mode, None if unpaired) and ``modes`` (Hz of all computed modes).
    sensor_nodes : SensorNodes or None
        The nodes standing for the sensors (set at the first evaluation).
    """

    def __init__(self, setup: CalibrationSetup,
                 progress: Callable[[int, np.ndarray], None] | None = None) -> None:
        self.setup, self.progress = setup, progress
        self.history: list[dict] = []
        self.sensor_nodes: SensorNodes | None = None
        self._memo: OrderedDict[tuple, ModelPoint] = OrderedDict()

    def __call__(self, z: np.ndarray) -> ModelPoint:
        """The point at log-values ``z`` (solved when not yet known)."""
        key = tuple(np.round(z, 12))
        if key in self._memo:
            self._memo.move_to_end(key)
            return self._memo[key]
        point = self._solve(np.exp(z))
        self._memo[key] = point
        if len(self._memo) > KEEP_SHAPES:
            self._memo.popitem(last=False)
        self._record(np.exp(z), point)
        return point

    def params(self, x: np.ndarray) -> CarBodyParams:
        """The parameters with the variables at values ``x`` (SI)."""
        s = self.setup
        return s.base.with_values(**dict(zip(s.names, map(float, x), strict=True)))

    def _solve(self, x: np.ndarray) -> ModelPoint:
        s = self.setup
        model = build_carbody(self.params(x), s.inertia, s.element_size)
        K, M = model.assemble()
        sol = free_free_modes(K, M, rigid_body_vectors(model.nodes), n_elastic=s.n_modes,
                              tol=1e-8)
        shapes = sol.shapes[:, 6:6 + s.n_modes]
        types = [classify_mode(shapes[:, k], M, model.nodes, model.node_region,
                               model.region_names) for k in range(shapes.shape[1])]
        modes = ModelModes(sol.frequencies[6:6 + s.n_modes], types,
                           self._at_sensors(model.nodes, shapes))
        return ModelPoint(modes, pair_targets(s.targets, modes, s.min_mac), shapes, M)

    def _at_sensors(self, nodes: np.ndarray, shapes: np.ndarray) -> np.ndarray | None:
        """The shapes at the sensor DOFs (nearest nodes, found once: the mesh is fixed)."""
        s = self.setup
        if s.sensors is None:
            return None
        if self.sensor_nodes is None:
            self.sensor_nodes = sensor_nodes(nodes, s.sensors, s.max_sensor_distance)
        if int(self.sensor_nodes.nodes.max()) >= nodes.shape[0]:
            raise FEModelError("the car-body mesh changed between evaluations")
        return shapes[self.sensor_nodes.dofs]

    def _record(self, x: np.ndarray, point: ModelPoint) -> None:
        paired = [p.frequency_hz for p in point.pairs]
        self.history.append({
            "values": dict(zip(self.setup.names, map(float, x), strict=True)),
            "frequencies": paired,
            "modes": [float(f) for f in point.modes.frequencies_hz],
        })
        if self.progress is not None:
            self.progress(len(self.history),
                          np.array([np.nan if f is None else f for f in paired]))


def paired_residuals(pairs: Sequence[TargetPair]) -> np.ndarray:
    """Relative error of each target's paired mode (-); 0 for unpaired targets (they are
    reported, not fitted).
    """
    return np.array([0.0 if p.error is None else p.error for p in pairs])

"""ModalBody: the one representation of a body the solver knows (DESIGN §3.1).

A body has six rigid-body coordinates (x, y, z translations of the centre of gravity and roll,
pitch, yaw rotations, small angles, in the body's track-following reference frame) followed by
zero or more elastic modal coordinates (mass-normalised modes, orthogonal to the rigid modes,
with modal damping). Its *markers* are points where suspension elements attach or where outputs
are recorded; each marker has a 6 × n_dof matrix mapping the body coordinates to the marker's
three translations and three rotations. A rigid body is a ModalBody with no elastic modes, so the
rigid and flexible vehicle models share one code path.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

#: Index of each rigid-body coordinate inside a body's coordinate vector.
X, Y, Z, ROLL, PITCH, YAW = range(6)


def rigid_marker_matrix(position: np.ndarray, n_dof: int, lock_pitch: bool = False) -> np.ndarray:
    """Map of a rigid body's coordinates to a marker's translations and rotations.

    Small rotations: ``u = u_cg + θ × r``.

    Parameters
    ----------
    position : array of 3 floats
        Marker position relative to the centre of gravity, body axes (m).
    n_dof : int
        Total number of body coordinates (6 + elastic modes).
    lock_pitch : bool
        Zero the pitch column: used for the axle boxes of a wheelset, whose pitch coordinate is
        the spin perturbation of the wheels and does not turn the axle boxes.

    Returns
    -------
    numpy.ndarray
        Array of shape (6, n_dof): rows ux, uy, uz (m per unit coordinate), rx, ry, rz (rad).
    """
    rx, ry, rz = (float(v) for v in position)
    phi = np.zeros((6, n_dof))
    phi[0, X] = phi[1, Y] = phi[2, Z] = 1.0
    # ux = x + θy rz − θz ry ; uy = y + θz rx − θx rz ; uz = z + θx ry − θy rx
    phi[0, PITCH], phi[0, YAW] = rz, -ry
    phi[1, ROLL], phi[1, YAW] = -rz, rx
    phi[2, ROLL], phi[2, PITCH] = ry, -rx
    phi[3, ROLL] = phi[4, PITCH] = phi[5, YAW] = 1.0
    if lock_pitch:
        phi[:, PITCH] = 0.0
    return phi


@dataclass
class ModalBody:
    """A rigid or flexible body in modal coordinates.

    Attributes
    ----------
    name : str
        Body name used in channel names (``carbody``, ``frame1``, ``wheelset3``...).
    mass : float
        Mass (kg).
    inertia : numpy.ndarray
        Principal moments of inertia about the CG, (Ixx, Iyy, Izz) (kg·m²).
    x_ref : float
        Longitudinal position of the body's reference frame from the vehicle centre (m).
    cg_height : float
        Nominal height of the centre of gravity above top of rail (m).
    elastic_frequencies : numpy.ndarray
        Natural frequencies of the elastic modes (Hz); empty for a rigid body.
    elastic_damping : numpy.ndarray
        Modal damping ratios of the elastic modes (-).
    markers : dict of str to numpy.ndarray
        Marker name -> (6, n_dof) map from coordinates to marker translations and rotations.
    marker_positions : dict of str to numpy.ndarray
        Marker name -> position relative to the CG, body axes (m).
    is_wheelset : bool
        Wheelsets carry wheel-rail contact and spin gyroscopics; their pitch coordinate is the
        spin perturbation.
    shape_at : callable, optional
        For flexible bodies: position relative to the CG (m) → (6, n_elastic) elastic mode
        shapes there; used for markers added without explicit shapes.
    info : dict
        What the body's build reports about how it was made, JSON-able (no effect on the
        dynamics): e.g. ``calibration`` for a car body calibrated to typed target modes
        (:attr:`flexride.fem.flexible_body.FlexibleBody.calibration`).
    """

    name: str
    mass: float
    inertia: np.ndarray
    x_ref: float
    cg_height: float
    elastic_frequencies: np.ndarray = field(default_factory=lambda: np.zeros(0))
    elastic_damping: np.ndarray = field(default_factory=lambda: np.zeros(0))
    elastic_shapes: dict[str, np.ndarray] = field(default_factory=dict)
    markers: dict[str, np.ndarray] = field(default_factory=dict)
    marker_positions: dict[str, np.ndarray] = field(default_factory=dict)
    is_wheelset: bool = False
    shape_at: Callable[[np.ndarray], np.ndarray] | None = None
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def n_elastic(self) -> int:
        """Number of elastic modes."""
        return int(self.elastic_frequencies.size)

    @property
    def n_dof(self) -> int:
        """Number of coordinates: 6 rigid + elastic modes."""
        return 6 + self.n_elastic

    def mass_diagonal(self) -> np.ndarray:
        """Diagonal generalised mass: m, m, m, Ixx, Iyy, Izz, then 1 per mass-normalised mode."""
        return np.concatenate([[self.mass] * 3, self.inertia, np.ones(self.n_elastic)])

    def modal_stiffness(self) -> np.ndarray:
        """Diagonal generalised stiffness (zero for rigid coordinates), ω² per elastic mode."""
        w = 2.0 * np.pi * self.elastic_frequencies
        return np.concatenate([np.zeros(6), w**2])

    def modal_damping(self) -> np.ndarray:
        """Diagonal generalised damping (zero for rigid coordinates), 2ζω per elastic mode."""
        w = 2.0 * np.pi * self.elastic_frequencies
        return np.concatenate([np.zeros(6), 2.0 * self.elastic_damping * w])

    def with_modes(self, modes: Sequence[int]) -> ModalBody:
        """A copy of the body with its rigid coordinates and only the elastic ``modes``.

        Parameters
        ----------
        modes : sequence of int
            Indices into :attr:`elastic_frequencies`, kept in the order given.

        Returns
        -------
        ModalBody
            Frequencies (Hz), damping ratios, shapes (m and rad per unit modal coordinate),
            markers and :attr:`shape_at` restricted to those modes: e.g. the rigid body and
            one mode of a finite-element body, to compare with a beam's first bending.

        Raises
        ------
        ValueError
            If an index is out of range.
        """
        idx = np.asarray(modes, dtype=np.int64).reshape(-1)
        if idx.size and (idx.min() < 0 or idx.max() >= self.n_elastic):
            raise ValueError(f"body {self.name!r} has {self.n_elastic} elastic modes; "
                             f"modes {idx.tolist()} are out of range")
        columns = np.concatenate([np.arange(6), 6 + idx])
        return ModalBody(
            name=self.name, mass=self.mass, inertia=self.inertia.copy(), x_ref=self.x_ref,
            cg_height=self.cg_height, elastic_frequencies=self.elastic_frequencies[idx].copy(),
            elastic_damping=self.elastic_damping[idx].copy(),
            elastic_shapes={k: v[:, idx].copy() for k, v in self.elastic_shapes.items()},
            markers={k: v[:, columns].copy() for k, v in self.markers.items()},
            marker_positions={k: v.copy() for k, v in self.marker_positions.items()},
            is_wheelset=self.is_wheelset,
            shape_at=None if self.shape_at is None else _columns_of(self.shape_at, idx),
            info=dict(self.info))

    def add_marker(
        self,
        name: str,
        position: tuple[float, float, float] | np.ndarray,
        elastic: np.ndarray | None = None,
        lock_pitch: bool = False,
    ) -> None:
        """Add a marker at ``position`` (m, relative to the CG, body axes).

        Parameters
        ----------
        name : str
            Marker name, unique on this body.
        position : array of 3 floats
            Position relative to the CG (m).
        elastic : numpy.ndarray, optional
            (6, n_elastic) elastic mode shapes at the marker (translations m, rotations rad per
            unit modal coordinate); zero when omitted (rigid body).
        lock_pitch : bool
            See :func:`rigid_marker_matrix`.
        """
        if name in self.markers:
            raise ValueError(f"marker {name!r} already exists on body {self.name!r}")
        pos = np.asarray(position, dtype=float)
        phi = rigid_marker_matrix(pos, self.n_dof, lock_pitch=lock_pitch)
        if elastic is None and self.n_elastic > 0 and name in self.elastic_shapes:
            elastic = self.elastic_shapes[name]
        if elastic is None and self.n_elastic > 0:
            if self.shape_at is None:
                raise ValueError(f"flexible body {self.name!r} needs shapes for marker {name!r}")
            elastic = np.asarray(self.shape_at(pos), dtype=float)
        if elastic is not None:
            if elastic.shape != (6, self.n_elastic):
                raise ValueError(
                    f"elastic shape of marker {name!r} must be (6, {self.n_elastic}), "
                    f"got {elastic.shape}"
                )
            phi[:, 6:] = elastic
        self.markers[name] = phi
        self.marker_positions[name] = pos


def _columns_of(shape_at: Callable[[np.ndarray], np.ndarray], idx: np.ndarray
                ) -> Callable[[np.ndarray], np.ndarray]:
    """``shape_at`` with only the elastic columns ``idx`` of its (6, n_elastic) shapes."""
    def restricted(position: np.ndarray) -> np.ndarray:
        return np.asarray(shape_at(position))[:, idx]

    return restricted


def rigid_body(
    name: str,
    mass: float,
    inertia: tuple[float, float, float],
    x_ref: float,
    cg_height: float,
    is_wheelset: bool = False,
) -> ModalBody:
    """A rigid :class:`ModalBody` (six rigid modes, no elastic modes)."""
    return ModalBody(
        name=name,
        mass=float(mass),
        inertia=np.asarray(inertia, dtype=float),
        x_ref=float(x_ref),
        cg_height=float(cg_height),
        is_wheelset=is_wheelset,
    )

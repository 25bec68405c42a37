"""Modal model of the two rails on discrete fasteners inside a window that follows the vehicle.

Each rail is an Euler–Bernoulli beam in vertical bending, lateral bending and torsion (paper
Eqs. 13–16) on a window of length L = N·d (d the fastener spacing), pinned at its ends, with
fasteners at the N − 1 interior grid points. With sine modes sin(kπx/L), k = 1 … N − 1, the
fasteners couple the modes *diagonally* (discrete orthogonality,
Σ_j sin(kπj/N)·sin(lπj/N) = N/2·δ_kl), so the fastener forces cost O(N) per step and a fastener
acts on each mode like a foundation of stiffness k_f/d. The generalised equations per mode are

    m q̈_z + (c_z/d) q̇_z + (E·I_y·κ⁴ + k_z/d) q_z = (2/L) Σ_w P_w sin(κ x_w)
    m q̈_y + (c_y/d)(q̇_y + h_f q̇_t) + E·I_z·κ⁴ q_y + (k_y/d)(q_y + h_f q_t)
          = (2/L) Σ_w Q_w sin(κ x_w)
    ρI₀ q̈_t + G·J·κ² q_t + (k_r/d) q_t + h_f (k_y/d)(q_y + h_f q_t) + … = (2/L) Σ_w M_w sin(κ x_w)

with κ = kπ/L, q_y the lateral displacement of the shear centre and h_f the height of the
shear centre above the foot where the fastener's lateral force acts.

The window moves with the vehicle in whole fastener bays (DESIGN §3.3): the rail state is
converted to displacements at the fasteners (a discrete sine transform, exact on this modal
space), shifted by the number of bays, and transformed back. Nothing on the route length enters
the cost per step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexride.scenario.track import Track


@dataclass(frozen=True)
class RailModel:
    """Modal properties of one rail (both rails are equal) in a window of ``n_bays`` bays."""

    n_bays: int
    spacing: float
    mass: float
    roll_inertia: float
    ei_vertical: float
    ei_lateral: float
    gj: float
    kz: float
    cz: float
    ky: float
    cy: float
    k_roll: float
    c_roll: float
    h_foot: float
    h_head: float

    @property
    def n_modes(self) -> int:
        """Modes per rail and direction (N − 1)."""
        return self.n_bays - 1

    @property
    def length(self) -> float:
        """Window length L (m)."""
        return self.n_bays * self.spacing

    def wavenumbers(self) -> np.ndarray:
        """Modal wavenumbers κ_k = kπ/L (rad/m)."""
        return np.arange(1, self.n_bays) * np.pi / self.length

    def vertical_stiffness(self) -> np.ndarray:
        """Generalised vertical stiffness per mode, E·I_y·κ⁴ + k_z/d (N/m²)."""
        return self.ei_vertical * self.wavenumbers() ** 4 + self.kz / self.spacing

    def lateral_bending_stiffness(self) -> np.ndarray:
        """Generalised lateral bending stiffness per mode without fasteners, E·I_z·κ⁴ (N/m²)."""
        return self.ei_lateral * self.wavenumbers() ** 4

    def torsional_stiffness(self) -> np.ndarray:
        """Generalised torsional stiffness per mode without fasteners, G·J·κ² (N)."""
        return self.gj * self.wavenumbers() ** 2

    def sine_matrix(self) -> np.ndarray:
        """S[j, k] = sin(κ_k x_j) at the interior fasteners x_j = j·d, j = 1 … N − 1."""
        j = np.arange(1, self.n_bays)[:, None]
        k = np.arange(1, self.n_bays)[None, :]
        return np.sin(np.pi * j * k / self.n_bays)


def build_rail_model(track: Track, wheel_span: float, margin: float, shift: float) -> RailModel:
    """Choose the window and build the modal rail model.

    Parameters
    ----------
    track : Track
        Track parameters.
    wheel_span : float
        Distance between the first and the last wheelset (m).
    margin : float
        Rail kept beyond the outermost wheelsets (m).
    shift : float
        Distance the window moves at once (m); the window is long enough for the wheels to
        travel this far before it moves.

    Returns
    -------
    RailModel
    """
    rail, fas = track.rail, track.fastener
    needed = wheel_span + 2.0 * margin + shift
    n_bays = int(np.ceil(needed / fas.spacing))
    return RailModel(
        n_bays=n_bays,
        spacing=fas.spacing,
        mass=rail.mass_per_length,
        roll_inertia=rail.density * rail.polar_moment,
        ei_vertical=rail.youngs_modulus * rail.iy,
        ei_lateral=rail.youngs_modulus * rail.iz,
        gj=rail.shear_modulus * rail.torsion_constant,
        kz=fas.kz,
        cz=fas.cz,
        ky=fas.ky,
        cy=fas.cy,
        k_roll=fas.k_roll,
        c_roll=fas.c_roll,
        h_foot=rail.shear_centre_above_foot,
        h_head=rail.head_above_shear_centre,
    )

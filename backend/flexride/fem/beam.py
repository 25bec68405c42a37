"""The beam car body: a free–free Euler–Bernoulli beam, the flexible car-body model of the
ride-comfort literature, as an independent second reference for the finite-element car body.

The car body is a uniform beam of its length L and mass m; its bending stiffness EI follows
from the chosen first vertical bending frequency, f_n = (β_n L)² / (2π L²) · √(EI L / m), so
that only the frequency is an input. The rigid-body coordinates keep the scenario's mass and
inertia; the elastic modes are the beam's vertical bending modes up to the body's cut-off,
mass-normalised on the uniform mass m/L and orthogonal to the rigid translation and pitch by
construction (free–free beam). A marker at longitudinal position x moves vertically with
φ_n(x) and pitches with −φ_n'(x) (u_z = −θ_y·x, the rigid body's convention): the suspension
and the measuring points sit at their real positions, as on the FE body.

Free–free modes: cos(βL)·cosh(βL) = 1 (βL = 4.7300, 7.8532, 10.9956, …), shapes
φ(x) = cosh βx + cos βx − σ (sinh βx + sin βx), σ = (cosh βL − cos βL)/(sinh βL − sin βL),
with ∫₀ᴸ φ² dx = L.

The uniform beam has the pitch inertia mL²/12 (1066 t·m² for the paper's 35.4 t, 19 m body,
whose Iyy is 1411 t·m²): its shapes do not belong to the body whose rigid motion the vehicle
describes. With ``mass_distribution="pitch_inertia"`` (the scenario's default) the beam carries
the vehicle's mass *and* pitch inertia: a uniform beam plus equal point masses at its ends when
Iyy exceeds mL²/12 (end walls, cabs, the equipment near the bogies), or a point mass at its
centre when Iyy is below it, each of the size that gives Iyy exactly (:func:`beam_masses`). Its
modes come from cubic Hermite elements (:data:`ELEMENTS`; the shapes between nodes by the same
interpolation), the bending stiffness again set by the first frequency. Where the air springs
sit relative to the first bending's nodes decides how hard the suspension drives it, so the
distribution changes the flexible effect at the floor centre severalfold (docs/fem.md).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Literal

import numpy as np
import scipy.linalg as sla

from flexride.bodies import ModalBody
from flexride.errors import FEModelError
from flexride.scenario.vehicle import Vehicle

#: Most bending modes a beam car body keeps (the shapes stay well conditioned below it).
MAX_MODES = 8
#: Hermite elements of the beam with point masses (even: a node at the centre).
ELEMENTS = 240

MassDistribution = Literal["pitch_inertia", "uniform"]
ShapeAt = Callable[[np.ndarray], np.ndarray]


def free_free_roots(n: int) -> np.ndarray:
    """The first ``n`` roots βL of cos(βL)·cosh(βL) = 1 above zero (-)."""
    from scipy.optimize import brentq

    def f(x: float) -> float:
        return math.cos(x) - 1.0 / math.cosh(x)  # cos x cosh x − 1, divided by cosh x

    # one root within π/4 of each (k + ½)π, k ≥ 1, where cos changes sign
    return np.array([brentq(f, (k + 0.25) * math.pi, (k + 0.75) * math.pi, xtol=1e-14)
                     for k in range(1, n + 1)])


def mode_shape(beta_l: float, length: float, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """φ(x) and dφ/dx (1/m) of the free–free mode with root ``beta_l`` on a beam of
    ``length`` (m), x from its left end (m), normalised so that ∫₀ᴸ φ² dx = L.
    """
    b = beta_l / length
    sigma = (math.cosh(beta_l) - math.cos(beta_l)) / (math.sinh(beta_l) - math.sin(beta_l))
    bx = b * np.asarray(x, dtype=float)
    phi = np.cosh(bx) + np.cos(bx) - sigma * (np.sinh(bx) + np.sin(bx))
    dphi = b * (np.sinh(bx) - np.sin(bx) - sigma * (np.cosh(bx) + np.cos(bx)))
    return phi, dphi


def bending_frequencies(first_bending_hz: float, cutoff_hz: float) -> tuple[np.ndarray,
                                                                           np.ndarray]:
    """The roots βL and frequencies (Hz) of the bending modes up to ``cutoff_hz`` (at most
    :data:`MAX_MODES`) of a beam whose first bends at ``first_bending_hz``.
    """
    roots = free_free_roots(MAX_MODES)
    freqs = first_bending_hz * (roots / roots[0]) ** 2
    keep = freqs <= cutoff_hz
    return roots[keep], freqs[keep]


def beam_carbody(params: Vehicle, first_bending_hz: float, cutoff_hz: float,
                 damping_ratio: float, length: float,
                 mass_distribution: MassDistribution = "pitch_inertia") -> ModalBody:
    """The car body of ``params`` as a free–free beam of ``length`` (m) whose first vertical
    bending mode is at ``first_bending_hz`` (Hz), with its bending modes up to ``cutoff_hz``
    (Hz), each damped by ``damping_ratio`` (-), its mass spread as ``mass_distribution`` says
    (module docs).

    Raises
    ------
    FEModelError
        A pitch inertia no mass distribution on the beam reaches (above mL²/4).
    """
    cb = params.carbody
    if mass_distribution == "uniform":
        freqs, shape_at = _uniform_beam(cb.mass, first_bending_hz, cutoff_hz, length)
    else:
        freqs, shape_at = _pitch_matched_beam(cb.mass, cb.iyy, first_bending_hz, cutoff_hz,
                                              length)
    return ModalBody(name="carbody", mass=cb.mass, inertia=np.array([cb.ixx, cb.iyy, cb.izz]),
                     x_ref=0.0, cg_height=cb.cg_height, elastic_frequencies=freqs,
                     elastic_damping=np.full(freqs.size, damping_ratio), shape_at=shape_at)


def _uniform_beam(mass: float, first_bending_hz: float, cutoff_hz: float, length: float
                  ) -> tuple[np.ndarray, ShapeAt]:
    """Frequencies (Hz) and mass-normalised shapes of the uniform beam (closed form)."""
    roots, freqs = bending_frequencies(first_bending_hz, cutoff_hz)
    scale = 1.0 / math.sqrt(mass)  # ∫ (m/L) φ² dx = m: mass-normalised by 1/√m

    def shape_at(pos: np.ndarray) -> np.ndarray:
        out = np.zeros((6, roots.size))
        x = min(max(float(pos[0]) + 0.5 * length, 0.0), length)
        for n, beta_l in enumerate(roots):
            phi, dphi = mode_shape(float(beta_l), length, np.array(x))
            out[2, n] = scale * float(phi)
            out[4, n] = -scale * float(dphi)
        return out

    return freqs, shape_at


def beam_masses(mass: float, iyy: float, length: float) -> tuple[float, float, float]:
    """The beam's mass per length (kg/m), each end mass and the centre mass (kg) that give
    ``mass`` (kg) and the pitch inertia ``iyy`` (kg·m², about the centre) on a beam of
    ``length`` (m): end masses M_e = (Iyy − mL²/12)/(L²/3) when Iyy ≥ mL²/12, else a centre
    mass M_c = m − 12 Iyy/L².

    Raises
    ------
    FEModelError
        If Iyy exceeds mL²/4 (all the mass at the ends) or is not positive.
    """
    uniform = mass * length**2 / 12.0
    if not 0.0 < iyy <= mass * length**2 / 4.0:
        raise FEModelError(
            f"the car body's pitch inertia {iyy:.4g} kg·m² cannot be carried by a {length:g} m "
            f"beam of {mass:.4g} kg (allowed: up to mL²/4 = {mass * length**2 / 4:.4g} kg·m²)")
    if iyy >= uniform:
        end = (iyy - uniform) / (length**2 / 3.0)
        return (mass - 2.0 * end) / length, end, 0.0
    centre = mass - 12.0 * iyy / length**2
    return (mass - centre) / length, 0.0, centre


def hermite_beam(length: float, per_length: float, end: float, centre: float,
                 elements: int = ELEMENTS) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness (for EI = 1 N·m²) and mass matrices of a free–free beam of cubic Hermite
    elements, DOFs (w, dw/dx) per node from x = 0, with ``per_length`` (kg/m) spread evenly
    and point masses ``end`` at both ends and ``centre`` at the middle (kg).
    """
    h = length / elements
    k_e = np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                    [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]]) / h**3
    m_e = per_length * h / 420.0 * np.array([
        [156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
        [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
    n = 2 * (elements + 1)
    K, M = np.zeros((n, n)), np.zeros((n, n))
    for e in range(elements):
        s = slice(2 * e, 2 * e + 4)
        K[s, s] += k_e
        M[s, s] += m_e
    M[0, 0] += end
    M[n - 2, n - 2] += end
    M[elements, elements] += centre  # node elements/2, its w DOF
    return K, M


def _pitch_matched_beam(mass: float, iyy: float, first_bending_hz: float, cutoff_hz: float,
                        length: float) -> tuple[np.ndarray, ShapeAt]:
    """Frequencies (Hz) and mass-normalised shapes of the beam carrying ``mass`` and ``iyy``
    (:func:`beam_masses`), from Hermite elements, bending first at ``first_bending_hz``.
    """
    per_length, end, centre = beam_masses(mass, iyy, length)
    K, M = hermite_beam(length, per_length, end, centre)
    lam, vec = sla.eigh(K, M)  # EI = 1: ω² = λ; two rigid modes first
    lam, vec = lam[2:2 + MAX_MODES], vec[:, 2:2 + MAX_MODES]
    freqs = first_bending_hz * np.sqrt(lam / lam[0])
    keep = freqs <= cutoff_hz
    freqs, vec = freqs[keep], vec[:, keep]
    vec = vec * np.sign(vec[0, :])  # the left end moves up, as in the closed form (φ(0) = 2)
    h = length / ELEMENTS

    def shape_at(pos: np.ndarray) -> np.ndarray:
        x = min(max(float(pos[0]) + 0.5 * length, 0.0), length)
        e = min(int(x / h), ELEMENTS - 1)
        n_w, n_dw = _hermite(x / h - e, h)
        dofs = vec[2 * e:2 * e + 4]
        out = np.zeros((6, freqs.size))
        out[2] = n_w @ dofs
        out[4] = -(n_dw @ dofs)
        return out

    return freqs, shape_at


def _hermite(xi: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Cubic Hermite shape functions and their x-derivatives (1/m) at ξ ∈ [0, 1] of an
    element of length ``h`` (m), for DOFs (w₁, w₁', w₂, w₂').
    """
    n = np.array([1 - 3 * xi**2 + 2 * xi**3, h * (xi - 2 * xi**2 + xi**3),
                  3 * xi**2 - 2 * xi**3, h * (-xi**2 + xi**3)])
    dn = np.array([-6 * xi + 6 * xi**2, h * (1 - 4 * xi + 3 * xi**2),
                   6 * xi - 6 * xi**2, h * (-2 * xi + 3 * xi**2)]) / h
    return n, dn

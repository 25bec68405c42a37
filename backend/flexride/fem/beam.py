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
"""

from __future__ import annotations

import math

import numpy as np

from flexride.bodies import ModalBody
from flexride.scenario.vehicle import Vehicle

#: Most bending modes a beam car body keeps (the shapes stay well conditioned below it).
MAX_MODES = 8


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
                 damping_ratio: float, length: float) -> ModalBody:
    """The car body of ``params`` as a free–free beam of ``length`` (m) whose first vertical
    bending mode is at ``first_bending_hz`` (Hz), with its bending modes up to ``cutoff_hz``
    (Hz), each damped by ``damping_ratio`` (-) (module docs).
    """
    cb = params.carbody
    roots, freqs = bending_frequencies(first_bending_hz, cutoff_hz)
    scale = 1.0 / math.sqrt(cb.mass)  # ∫ (m/L) φ² dx = m: mass-normalised by 1/√m

    def shape_at(pos: np.ndarray) -> np.ndarray:
        out = np.zeros((6, roots.size))
        x = min(max(float(pos[0]) + 0.5 * length, 0.0), length)
        for n, beta_l in enumerate(roots):
            phi, dphi = mode_shape(float(beta_l), length, np.array(x))
            out[2, n] = scale * float(phi)
            out[4, n] = -scale * float(dphi)
        return out

    return ModalBody(name="carbody", mass=cb.mass, inertia=np.array([cb.ixx, cb.iyy, cb.izz]),
                     x_ref=0.0, cg_height=cb.cg_height, elastic_frequencies=freqs,
                     elastic_damping=np.full(roots.size, damping_ratio), shape_at=shape_at)

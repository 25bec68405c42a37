"""The kernel's one-step map, linearised, and the largest time step for which it is stable.

One step of the kernel (:func:`~flexride.solver.kernel.run_chunk`) is Zhai's update of the
coordinates and velocities followed by one force evaluation, in which the creep forces relax
from their previous values toward the steady Kalker/SHE values over the step
(:func:`~flexride.solver.forces.contact_forces`). Linearised about an operating point, with
the state ``z_n = (X_n, V_n, A_{n−1}, c_{n−1})`` (coordinates, velocities, the previous step's
accelerations and creep forces)::

    A_n = J_AX X_n + J_AV V_n + J_Ac c_{n−1}          (the force evaluation: accelerations)
    c_n = J_cX X_n + J_cV V_n + J_cc c_{n−1}          (the force evaluation: creep state)
    X_{n+1} = X_n + Δt V_n + (½ + ψ) Δt² A_n − ψ Δt² A_{n−1}
    V_{n+1} = V_n + (1 + φ) Δt A_n − φ Δt A_{n−1}

The J blocks are central differences of the kernel's own force evaluation with the creep
relaxation of the step Δt (:func:`~flexride.solver.linearise.step_jacobian_columns`), so the
map is the kernel's, with every state it carries: for ``n`` coordinates and ``m`` creep
states, a (3n + m)² matrix :func:`one_step_map`.

**Stability.** The step is stable when no eigenvalue μ of the map lies outside the unit circle,
except where the continuous system itself grows: an eigenvalue with |ln μ| < :data:`RESOLVED`
belongs to motion the step resolves (at least 2π/κ ≈ 31 steps per period or per e-fold), such
as the rigid-body modes (μ = 1) and, above the critical speed, hunting — the physics, not the
integrator. :func:`numerical_radius` is the largest |μ| of the others.

**The limit, cheaply.** The eigenvalues that leave the unit circle as Δt grows do so at μ = −1
(a period-two oscillation: the stiff creep damping and the stiffest modes of Zhai's method).
With the z-transform of the map, μ is an eigenvalue when

    T(μ) = I − a(μ) Δt² K̃(μ) − b(μ) Δt C̃(μ)   is singular,
    a(μ) = ((1 + φ)μ − φ + ((½ + ψ)μ − ψ)(μ − 1)) / (μ(μ − 1)²),
    b(μ) = ((1 + φ)μ − φ) / (μ(μ − 1)),
    K̃ = J_AX + J_Ac (μI − J_cc)⁻¹ J_cX,  C̃ = J_AV + J_Ac (μI − J_cc)⁻¹ J_cV,

an n × n problem instead of (3n + m). At μ = −1 (a = (φ − 2ψ)/2, b = −(1 + 2φ)/2) every
eigenvalue of T(−1; Δt) is 1 at Δt = 0, and the first period-two root is the first step at which
a real one passes zero (:func:`first_period_two_step`): bracketed by doubling or halving from a
trial step and closed by regula falsi on the smallest real one among those nearest zero
(shift-invert Arnoldi), then confirmed on all eigenvalues. Finally the whole map is checked at
the step found (:func:`numerical_radius` of its eigenvalues), which would reveal a complex pair
leaving the circle earlier; if it does, the limit is bisected on the whole map.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

#: Eigenvalues with |ln μ| below this are motion the step resolves (rigid-body modes, the
#: physical dynamics including hunting above the critical speed): their growth is the
#: system's, not the integrator's.
RESOLVED = 0.2
#: Tolerance on |μ| of the other eigenvalues (rounding of the finite differences).
RADIUS_TOL = 1.0e-6
#: Finite-difference steps of the map's Jacobian: coordinates and velocities (m, rad, m/s,
#: rad/s) and creep forces (N, N·m; the map is linear in them).
H_STATE = 1.0e-7
H_CREEP = 1.0
#: Relative accuracy of the limit's search.
STEP_RTOL = 5.0e-4
#: Eigenvalues of T(−1; Δt) nearest zero computed in the limit's search.
NEAREST = 6


@dataclass(frozen=True)
class StepJacobian:
    """The blocks of the linearised one-step map (module docs) for one time step.

    Attributes
    ----------
    ax, av : numpy.ndarray
        (n, n) ∂A/∂X (1/s²) and ∂A/∂V (1/s) of the force evaluation.
    ac : numpy.ndarray
        (n, m) ∂A/∂c_prev (1/(kg·s²)·… per N: accelerations per creep force).
    cx, cv : numpy.ndarray
        (m, n) ∂c/∂X (N/m) and ∂c/∂V (N·s/m).
    cc : numpy.ndarray
        (m, m) ∂c/∂c_prev (-), the relaxation factors e^(−Δt/τ).
    """

    ax: np.ndarray
    av: np.ndarray
    ac: np.ndarray
    cx: np.ndarray
    cv: np.ndarray
    cc: np.ndarray

    @property
    def n(self) -> int:
        """Number of coordinates."""
        return int(self.ax.shape[0])

    @property
    def m(self) -> int:
        """Number of creep states."""
        return int(self.cc.shape[0])


#: A function giving the map's blocks for a time step (s).
BlocksAt = Callable[[float], StepJacobian]


def oscillator_jacobian(omega: float, damping: float) -> StepJacobian:
    """The blocks of ẍ = −ω²x − c·ẋ (ω in rad/s, c in 1/s): one coordinate, no creep."""
    e = np.zeros((1, 0))
    return StepJacobian(np.array([[-omega**2]]), np.array([[-damping]]), e, e.T, e.T,
                        np.zeros((0, 0)))


def one_step_map(jac: StepJacobian, dt: float, psi: float = 0.5, phi: float = 0.5
                 ) -> np.ndarray:
    """The linearised one-step map of the state (X, V, A_prev, c_prev), (3n + m)².

    Parameters
    ----------
    jac : StepJacobian
        Blocks for the step ``dt``.
    dt : float
        Time step (s).
    psi, phi : float
        Zhai's parameters (-).
    """
    n, m = jac.n, jac.m
    c1, c2 = (0.5 + psi) * dt**2, psi * dt**2
    c3, c4 = (1.0 + phi) * dt, phi * dt
    eye = np.eye(n)
    zero_nn = np.zeros((n, n))
    a_row = np.hstack([jac.ax, jac.av, zero_nn, jac.ac])
    c_row = np.hstack([jac.cx, jac.cv, np.zeros((m, n)), jac.cc])
    x_row = np.hstack([eye, dt * eye, -c2 * eye, np.zeros((n, m))]) + c1 * a_row
    v_row = np.hstack([zero_nn, eye, -c4 * eye, np.zeros((n, m))]) + c3 * a_row
    return np.vstack([x_row, v_row, a_row, c_row])


def numerical_radius(mu: np.ndarray) -> tuple[float, int]:
    """Largest |μ| among the eigenvalues ``mu`` the step does not resolve (|ln μ| ≥
    :data:`RESOLVED`), and its index (0.0 and −1 if there is none).
    """
    mag = np.abs(mu)
    with np.errstate(divide="ignore"):
        log_dist = np.abs(np.log(np.where(mag > 0.0, mu, 1e-300 + 0j)))
    candidates = np.flatnonzero(log_dist >= RESOLVED)
    if candidates.size == 0:
        return 0.0, -1
    k = int(candidates[np.argmax(mag[candidates])])
    return float(mag[k]), k


def map_eigen(jac: StepJacobian, dt: float, psi: float, phi: float,
              vectors: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
    """Eigenvalues (and, if asked, right eigenvectors) of :func:`one_step_map`."""
    m = one_step_map(jac, dt, psi, phi)
    if vectors:
        mu, vec = sla.eig(m, overwrite_a=True, check_finite=False)
        return mu, vec
    return sla.eigvals(m, overwrite_a=True, check_finite=False), None


def _period_two_coefficients(psi: float, phi: float) -> tuple[float, float]:
    """a(−1) and b(−1) of the module docs."""
    return 0.5 * (phi - 2.0 * psi), -0.5 * (1.0 + 2.0 * phi)


def condensed_at_minus_one(jac: StepJacobian) -> tuple[np.ndarray, np.ndarray]:
    """K̃(−1) and C̃(−1) (1/s², 1/s): the creep state condensed into the coordinates for a
    period-two motion, c = (I + J_cc)⁻¹ (J_cX X + J_cV V)·(−1)·… (module docs).
    """
    if jac.m == 0:
        return jac.ax, jac.av
    rhs = np.hstack([jac.cx, jac.cv])
    r = jac.ac @ np.linalg.solve(np.eye(jac.m) + jac.cc, rhs)
    n = jac.n
    return jac.ax - r[:, :n], jac.av - r[:, n:]


def period_two_matrix(jac: StepJacobian, dt: float, psi: float, phi: float) -> np.ndarray:
    """T(−1; Δt) = I − a Δt² K̃ − b Δt C̃, singular where an eigenvalue of the map is −1."""
    a, b = _period_two_coefficients(psi, phi)
    k, c = condensed_at_minus_one(jac)
    return np.eye(jac.n) - (a * dt**2) * k - (b * dt) * c


def smallest_real_eigenvalue(t: np.ndarray) -> float:
    """The smallest real eigenvalue of ``t`` (+inf if none is real)."""
    lam = sla.eigvals(t, overwrite_a=True, check_finite=False)
    return _least_real(lam, min)


def smallest_real_near_zero(t: np.ndarray) -> float:
    """The smallest real eigenvalue of ``t`` among its :data:`NEAREST` eigenvalues nearest
    zero (shift-invert Arnoldi on one LU factorisation): a tenth of the cost of all
    eigenvalues, and the same as :func:`smallest_real_eigenvalue` as long as no real eigenvalue
    beyond them has passed zero — which the caller confirms once at the end. If none of them
    is real, the smallest real eigenvalue of all.

    The smallest, not the one nearest zero: where two real eigenvalues cross zero at almost
    the same step (the same rail mode under the two wheelsets of a bogie), the one nearest
    zero beyond the first crossing is the second, and regula falsi on it passed the first
    (the paper's flexible vehicle: seven evaluations of all eigenvalues more per point).
    """
    import scipy.sparse.linalg as spla

    if t.shape[0] <= 4 * NEAREST:
        return smallest_real_eigenvalue(t)
    lu = sla.lu_factor(t, check_finite=False)
    inverse = spla.LinearOperator(t.shape, matvec=lambda v: sla.lu_solve(lu, v), dtype=float)
    start = np.random.default_rng(0).standard_normal(t.shape[0])  # same matrix, same answer
    try:
        nu = spla.eigs(inverse, k=NEAREST, which="LM", return_eigenvectors=False, tol=1e-10,
                       v0=start)
    except spla.ArpackNoConvergence:
        return smallest_real_eigenvalue(t)
    near = _least_real(1.0 / nu, min)
    return near if math.isfinite(near) else smallest_real_eigenvalue(t)


def _least_real(lam: np.ndarray, pick: Callable) -> float:
    """``pick`` of the real values among the eigenvalues ``lam`` (+inf if none is real)."""
    real = lam.real[np.abs(lam.imag) <= 1e-9 * np.maximum(np.abs(lam), 1e-300)]
    return float(pick(list(real))) if real.size else math.inf


def first_period_two_step(blocks_at: BlocksAt, psi: float, phi: float, guess: float,
                          ceiling: float) -> float:
    """The smallest Δt (s) at which an eigenvalue of the map reaches −1, or ``ceiling`` if
    none does below it.

    ``g(Δt)``, the smallest real eigenvalue of T(−1; Δt), is 1 at Δt = 0 and passes through
    zero at the first period-two root. The root is bracketed from ``guess`` (s) by doubling or
    halving and the bracket closed by regula falsi (Illinois) to :data:`STEP_RTOL`, on the
    smallest real one among the eigenvalues nearest zero (:func:`smallest_real_near_zero`);
    that no other real eigenvalue has passed zero before is then confirmed on all of them, and
    the search repeated on all of them if one has.
    """
    def period_two(dt: float) -> np.ndarray:
        return period_two_matrix(blocks_at(dt), dt, psi, phi)

    def g_near(dt: float) -> float:
        return smallest_real_near_zero(period_two(dt))

    def g(dt: float) -> float:
        return smallest_real_eigenvalue(period_two(dt))

    lo, hi = _bracket(g_near, min(guess, ceiling), ceiling)
    root = ceiling if hi is None else _illinois(g_near, lo, hi)
    g_root = g(root)
    if g_root > 0.0:
        return root
    # another real eigenvalue passed zero first: close in on it on all eigenvalues, from the
    # bracket's lower end if it is still below every crossing
    g_lo = g(lo[0])
    if g_lo > 0.0:
        return _illinois(g, (lo[0], g_lo), (root, g_root))
    lo, hi = _bracket(g, lo[0], ceiling)
    return ceiling if hi is None else _illinois(g, lo, hi)


def _bracket(g: Callable[[float], float], guess: float, ceiling: float
             ) -> tuple[tuple[float, float], tuple[float, float] | None]:
    """(lo, g(lo)) with g > 0 and (hi, g(hi)) with g ≤ 0 around the first root, searching
    from ``guess`` by factors of 2; hi is None when g > 0 up to ``ceiling``.
    """
    dt = guess
    value = g(dt)
    if value > 0.0:
        while True:
            if dt >= ceiling:
                return (dt, value), None
            nxt = min(dt * 2.0, ceiling)
            nv = g(nxt)
            if nv <= 0.0:
                return (dt, value), (nxt, nv)
            dt, value = nxt, nv
    while True:
        nxt = dt / 2.0
        nv = g(nxt)
        if nv > 0.0:
            return (nxt, nv), (dt, value)
        dt, value = nxt, nv


def _illinois(g: Callable[[float], float], lo: tuple[float, float],
              hi: tuple[float, float]) -> float:
    """Regula falsi (Illinois variant) on g between lo (g > 0) and hi (g ≤ 0); returns the
    largest step known to have g > 0 once the bracket is within :data:`STEP_RTOL`.
    """
    (a, ga), (b, gb) = lo, hi
    side = 0
    for _ in range(60):
        if b - a <= STEP_RTOL * b:
            break
        c = b - gb * (b - a) / (gb - ga)
        c = min(max(c, a + 0.05 * (b - a)), b - 0.05 * (b - a))
        gc = g(c)
        if gc > 0.0:
            a, ga = c, gc
            if side == 1:
                gb *= 0.5
            side = 1
        else:
            b, gb = c, gc
            if side == -1:
                ga *= 0.5
            side = -1
    return a

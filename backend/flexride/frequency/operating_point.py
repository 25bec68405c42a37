"""The operating point of the linearisation: the assembled system on smooth track, the position
on the line, and the steady state of the vehicle there (static equilibrium on straight track,
steady curving on the arc of a curve).

The rail of the time-domain model lives in a window that moves with the vehicle in whole
fastener bays; between two shifts the wheels roll through a window that stands still, over
discrete fasteners. That is a time-varying system (periodic in the bay and in the shift), so an
exactly time-invariant model does not exist. As the time-step stability check does
(:mod:`flexride.solver.stability`), the model here freezes the window at the operating point:
the wheels sit at fixed positions in it. What this neglects — the moving-load (convective)
terms, about (V/c_rail)², and the parametric excitation at the fastener-passing frequency V/d —
is listed in ``docs/analysis.md``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla

from flexride.errors import SimulationError
from flexride.frequency.errors import LinearisationError
from flexride.scenario.line import CurvedLine
from flexride.scenario.scenario import Scenario
from flexride.solver import system as S
from flexride.solver.assemble import Assembly
from flexride.solver.forces import evaluate
from flexride.solver.linearise import accelerations, workspace
from flexride.solver.static import initial_window_start, static_equilibrium
from flexride.solver.steady import smooth_assembly, steady_unknowns
from flexride.solver.steady import steady_state as solver_steady_state

#: A warm start (chord iterations) stops at this largest step (m, rad, m/s): far below
#: :data:`~flexride.solver.steady.STEADY_TOL`, so that it lands on the root a cold Newton
#: solution finds, to rounding.
CHORD_TOL = 1e-13
#: Chord iterations before a warm start gives up (Newton from the previous state follows).
CHORD_MAX_ITER = 30
#: Steady-state coordinates and velocities smaller than this (m, rad, m/s, rad/s) are the
#: rounding of an exact zero (a centred wheelset on straight track) and are set to zero: the
#: Jacobians' central differences straddle the kink of the tabulated contact geometry at a
#: centred wheelset, so they would otherwise depend on that rounding (a sweep's comfort
#: indices differed from a rebuild by 1e-10 instead of 3e-11).
ZERO_TOL = 1e-13


@dataclass
class OperatingPoint:
    """The linearisation point.

    Attributes
    ----------
    asm : Assembly
        The assembled scenario with ``sys`` on smooth track (a zero irregularity table around
        the vehicle).
    s : float
        Position of the vehicle centre on the line (m).
    s_win0 : float
        Start of the frozen rail window (m).
    X0, V0 : numpy.ndarray
        Coordinates (m, rad) and velocities (m/s, rad/s) of the steady state (velocities are
        zero but for the wheelsets' spin perturbation on a curve).
    aux : numpy.ndarray
        Per-wheel quantities at the steady state, ``[wheelset, side, AUX_*]`` (N, m, rad).
    on_arc : bool
        Whether the point lies on the arc of a curve (steady curving).
    chord_iterations : int
        Chord iterations of a warm start that converged; −1 when solved from the static
        equilibrium (cold start), −2 by Newton from a warm start's state.
    """

    asm: Assembly
    s: float
    s_win0: float
    X0: np.ndarray
    V0: np.ndarray
    aux: np.ndarray
    on_arc: bool
    chord_iterations: int = -1

    @property
    def sys(self) -> S.SystemArrays:
        """The kernel's arrays on smooth track."""
        return self.asm.sys


@dataclass
class WarmStart:
    """A steady state of a system with the same coordinates (the previous value of a
    parameter sweep) and the factorised Newton matrix there, for chord iterations.

    Attributes
    ----------
    X, V : numpy.ndarray
        Coordinates (m, rad) and velocities (m/s, rad/s) of the previous steady state.
    s, s_win0 : float
        Its position and rail-window start (m).
    lu : tuple
        ``scipy.linalg.lu_factor`` of the steady-state Newton matrix (force units): the
        columns of ∂A/∂X of every coordinate but the spin angles and of ∂A/∂V of the spin
        rates, rows scaled by the masses.
    """

    X: np.ndarray
    V: np.ndarray
    s: float
    s_win0: float
    lu: tuple[np.ndarray, np.ndarray]


def warm_start(op: OperatingPoint, dA_dX: np.ndarray, dA_dV: np.ndarray) -> WarmStart:
    """The warm start of the next sweep value from ``op`` (one LU factorisation, 5 ms for
    486 coordinates).

    Parameters
    ----------
    op : OperatingPoint
        The steady state.
    dA_dX, dA_dV : numpy.ndarray
        (n, n) ∂A/∂X (1/s²) and ∂A/∂V (1/s) there, as the linear model has them.
    """
    keep, spin = steady_unknowns(op.asm)
    scale = 1.0 / op.sys.minv
    J = np.hstack([dA_dX[:, keep], dA_dV[:, spin]]) * scale[:, None]
    return WarmStart(op.X0.copy(), op.V0.copy(), op.s, op.s_win0, sla.lu_factor(J))


def linearisation_position(scenario: Scenario, asm: Assembly) -> tuple[float, bool]:
    """Position (m) of the vehicle centre for the linearisation and whether it is on an arc.

    Straight track: 0 m. Curve: the middle of the arc, which must hold the whole vehicle.

    Raises
    ------
    LinearisationError
        The arc is shorter than the vehicle (no steady curving state).
    """
    line = scenario.line
    if not isinstance(line, CurvedLine):
        return 0.0, False
    xs = [b.x_ref for b in asm.vehicle.bodies]
    span = max(xs) - min(xs)
    if line.arc_length_m < span + 2.0:
        raise LinearisationError(
            f"line.arc_length_m = {line.arc_length_m:g} m is shorter than the vehicle "
            f"({span:.1f} m between its outermost bodies): no steady curving state to "
            "linearise about; use the time-domain solver", "equilibrium")
    return line.start_m + line.entry_transition_m + 0.5 * line.arc_length_m, True


def chord_steady_state(asm: Assembly, s: float, s_win0: float, warm: WarmStart
                       ) -> tuple[np.ndarray, np.ndarray, int] | None:
    """The steady state at ``s`` by chord iterations from ``warm`` (its Newton matrix kept):
    converges linearly at the rate the system changed since ``warm``, without a Jacobian (an
    iteration is one force evaluation and two triangular solves).

    Parameters
    ----------
    asm : Assembly
        The assembly on smooth track (the same coordinates as ``warm``).
    s, s_win0 : float
        Vehicle-centre position and rail-window start (m), those of ``warm``.
    warm : WarmStart
        The previous steady state and its Newton matrix.

    Returns
    -------
    (X, V, iterations) or None
        The steady state (m, rad; m/s, rad/s; steps below :data:`CHORD_TOL`) and the iterations
        it took, or None when the steps stop shrinking or :data:`CHORD_MAX_ITER` is reached.
    """
    sys = asm.sys
    keep, spin = steady_unknowns(asm)
    scale = 1.0 / sys.minv
    X, V = warm.X.copy(), warm.V.copy()
    last = np.inf
    for it in range(CHORD_MAX_ITER):
        r = accelerations(sys, X, V, s, s_win0) * scale
        if not np.all(np.isfinite(r)):
            return None
        dz = sla.lu_solve(warm.lu, -r)
        step = float(np.max(np.abs(dz)))
        if not step < last:  # not contracting (or not finite): leave it to Newton
            return None
        last = step
        X[keep] += dz[: keep.size]
        V[spin] += dz[keep.size:]
        if step < CHORD_TOL:
            return X, V, it + 1
    return None


def steady_state(asm: Assembly, s: float, s_win0: float, X: np.ndarray,
                 max_iter: int = 30) -> tuple[np.ndarray, np.ndarray]:
    """:func:`flexride.solver.steady.steady_state`, its failure as a
    :class:`LinearisationError`.
    """
    try:
        return solver_steady_state(asm, s, s_win0, X, max_iter)
    except SimulationError as exc:
        raise LinearisationError(f"{exc}; use the time-domain solver", "equilibrium") from None


def wheel_state(asm: Assembly, X: np.ndarray, V: np.ndarray, s: float,
                s_win0: float) -> np.ndarray:
    """Per-wheel quantities ``aux[wheelset, side, AUX_*]`` at (X, V) (N, m, rad)."""
    F, A, aux, sn, cst = workspace(asm.sys)
    evaluate(asm.sys, X.copy(), V.copy(), s, s_win0, F, A, aux, sn, cst, 0.0)
    return aux.copy()


def check_contact(asm: Assembly, X: np.ndarray, aux: np.ndarray) -> None:
    """Refuse a steady state with a lost wheel contact or with flange contact.

    Raises
    ------
    LinearisationError
        A wheel without normal force, or a flange in contact (conical tread: lateral
        displacement relative to the rail beyond ``contact.flange_clearance``; real profiles:
        load on the flange slot), with the wheel named.
    """
    sys = asm.sys
    names = [asm.vehicle.bodies[b].name for b in asm.vehicle.wheelsets]
    for w, b in enumerate(asm.vehicle.wheelsets):
        for side, sname in enumerate(("left", "right")):
            if not aux[w, side, S.AUX_N] > 0.0:
                raise LinearisationError(
                    f"{names[w]} {sname} wheel has no contact at equilibrium: the linearised "
                    "model does not hold", "contact_loss")
            if sys.par.contact_model == S.CONTACT_PROFILES:
                flange = aux[w, side, S.AUX_N_FLANGE] > 0.0
            else:
                dy = X[int(sys.body_off[b]) + 1] - aux[w, side, S.AUX_RAIL_Y]
                flange = (dy > sys.par.flange_clearance) if side == 0 else (
                    dy < -sys.par.flange_clearance)
            if flange:
                raise LinearisationError(
                    f"{names[w]} {sname} wheel is in flange contact at equilibrium (steady "
                    "curving): flange contact is not linear; use the time-domain solver",
                    "flange_contact")


def solve_operating_point(scenario: Scenario, asm: Assembly,
                          warm: WarmStart | None = None) -> OperatingPoint:
    """The linearisation point of ``scenario`` (assembled as ``asm``), without the contact
    check: from the static equilibrium, or from ``warm`` (the previous value of a sweep: chord
    iterations, then Newton from it if they stall, then the cold start). Entries below
    :data:`ZERO_TOL` are set to zero.

    Parameters
    ----------
    scenario : Scenario
        The scenario (its line gives the position).
    asm : Assembly
        Its assembly.
    warm : WarmStart, optional
        A previous steady state of the same coordinates.

    Raises
    ------
    LinearisationError
        No steady state.
    """
    s, on_arc = linearisation_position(scenario, asm)
    smooth = smooth_assembly(asm, s)
    s_win0 = initial_window_start(smooth, s)
    XVi = _from_warm(smooth, s, s_win0, warm) if warm is not None else None
    if XVi is None:
        X = static_equilibrium(smooth, s, s_win0)
        XVi = (*steady_state(smooth, s, s_win0, X), -1)
    X, V, iterations = XVi
    X, V = _snap(X), _snap(V)
    aux = wheel_state(smooth, X, V, s, s_win0)
    return OperatingPoint(smooth, s, s_win0, X, V, aux, on_arc, iterations)


def _snap(x: np.ndarray) -> np.ndarray:
    """``x`` with entries below :data:`ZERO_TOL` in magnitude set to zero."""
    return np.where(np.abs(x) < ZERO_TOL, 0.0, x)


def _from_warm(asm: Assembly, s: float, s_win0: float, warm: WarmStart
               ) -> tuple[np.ndarray, np.ndarray, int] | None:
    """Steady state from a previous one of the same layout (and the chord iterations, −2
    after Newton from it), or None (then a cold start).
    """
    if warm.X.shape != (asm.sys.minv.shape[0],) or (warm.s, warm.s_win0) != (s, s_win0):
        return None
    XVi = chord_steady_state(asm, s, s_win0, warm)
    if XVi is None:
        try:
            return (*steady_state(asm, s, s_win0, warm.X.copy()), -2)
        except (LinearisationError, np.linalg.LinAlgError):
            return None
    return XVi


def operating_point(scenario: Scenario, asm: Assembly) -> OperatingPoint:
    """The linearisation point of ``scenario`` (assembled as ``asm``).

    Raises
    ------
    LinearisationError
        No steady state, lost contact or flange contact at the steady state.
    """
    op = solve_operating_point(scenario, asm)
    check_contact(op.asm, op.X0, op.aux)
    return op

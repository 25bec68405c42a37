"""The steady state of the vehicle at a fixed position on smooth track: static equilibrium on
straight track, quasi-static curving on a curve (every acceleration zero, the wheelsets
rolling at the spin rates that balance their longitudinal creep forces).

Used where a run is linearised away from its starting point: the time-step check on a curve
(:mod:`flexride.solver.stability`) and the frequency-domain estimate
(:mod:`flexride.frequency.operating_point`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from flexride.errors import SimulationError
from flexride.scenario.line import Line
from flexride.solver.assemble import Assembly
from flexride.solver.linearise import accelerations, jacobian
from flexride.track.line_geometry import build_line_table

#: Grid step of the (zero) irregularity table of a smooth assembly (m).
IRR_GRID_STEP = 0.05
#: A smooth assembly's own line table reaches this far beyond the outermost bodies (m).
LINE_REACH_M = 25.0
#: Newton tolerance of the steady state: largest coordinate step (m, rad, m/s).
STEADY_TOL = 1e-10


def smooth_assembly(asm: Assembly, s: float, line: Line | None = None,
                    rail_half_distance: float = 0.0, travel: float = 0.0) -> Assembly:
    """``asm`` with a zero irregularity table covering the vehicle at position ``s`` (m) and,
    if ``line`` is given, the line table of that line around it and ``travel`` (m) ahead (the
    run's own table covers the run only; the heading it starts from cancels in the relative
    positions of the bodies). ``rail_half_distance`` (m) as for
    :func:`~flexride.track.line_geometry.build_line_table`.
    """
    ws_x = np.array([asm.vehicle.bodies[i].x_ref for i in asm.vehicle.wheelsets])
    s0 = s + float(ws_x.min()) - 5.0
    n = int(np.ceil((float(ws_x.max() - ws_x.min()) + 10.0) / IRR_GRID_STEP)) + 1
    par = asm.sys.par._replace(irr_s0=s0, irr_ds=IRR_GRID_STEP)
    sys0 = asm.sys._replace(par=par, irr=np.zeros((4, n)))
    if line is not None:
        xs = [b.x_ref for b in asm.vehicle.bodies]
        table = build_line_table(line, s + min(xs) - LINE_REACH_M,
                                 s + max(xs) + LINE_REACH_M + travel, rail_half_distance)
        sys0 = sys0._replace(line=table.as_array(), par=sys0.par._replace(
            ln_s0=table.s0, ln_ds=table.ds))
    return dataclasses.replace(asm, sys=sys0)


def spin_indices(asm: Assembly) -> np.ndarray:
    """State indices of the wheelsets' spin perturbation (their pitch coordinate)."""
    sys = asm.sys
    return np.array([int(sys.body_off[b]) + 4 for b in asm.vehicle.wheelsets], dtype=np.int64)


def steady_unknowns(asm: Assembly) -> tuple[np.ndarray, np.ndarray]:
    """State indices solved for as coordinates (all but the spin angles) and as velocities
    (the spin rates) in the steady state.
    """
    spin = spin_indices(asm)
    return np.setdiff1d(np.arange(asm.sys.minv.shape[0]), spin), spin


def _newton_step(J: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """The Newton step ``J⁻¹ rhs``, or, where ``J`` is singular — a vehicle with a free
    motion, e.g. the car body and frames laterally free of the wheelsets when the primary has
    no lateral stiffness: every lateral position is a steady state — the least-norm step, which
    leaves the free motion where it is.
    """
    try:
        return np.linalg.solve(J, rhs)
    except np.linalg.LinAlgError:
        return np.linalg.lstsq(J, rhs, rcond=None)[0]


def steady_state(asm: Assembly, s: float, s_win0: float, X: np.ndarray,
                 max_iter: int = 30) -> tuple[np.ndarray, np.ndarray]:
    """Steady state at ``s`` (m): every acceleration zero, solved for all coordinates but the
    spin angles (which no force depends on) and for the spin rates (which balance the
    longitudinal creep forces in a curve). Newton with finite-difference Jacobians, from ``X``.

    Returns
    -------
    X, V : numpy.ndarray
        Coordinates (m, rad) and velocities (m/s, rad/s; only the spin rates are not zero).

    Raises
    ------
    SimulationError
        Newton does not converge.
    """
    sys = asm.sys
    n = X.shape[0]
    keep, spin = steady_unknowns(asm)
    V = np.zeros(n)
    scale = 1.0 / sys.minv
    res = np.inf
    for _ in range(max_iter):
        r = accelerations(sys, X, V, s, s_win0) * scale
        res = float(np.linalg.norm(r))
        J = np.hstack([jacobian(sys, X, V, s, s_win0, keep),
                       jacobian(sys, X, V, s, s_win0, spin, wrt_velocity=True)])
        dz = _newton_step(J * scale[:, None], -r)
        lam = 1.0
        for _ls in range(20):
            Xt, Vt = X.copy(), V.copy()
            Xt[keep] += lam * dz[: keep.size]
            Vt[spin] += lam * dz[keep.size:]
            rt = accelerations(sys, Xt, Vt, s, s_win0) * scale
            if np.linalg.norm(rt) < res or lam < 1e-3:
                break
            lam *= 0.5
        X, V = Xt, Vt
        if np.max(np.abs(lam * dz)) < STEADY_TOL:
            return X, V
    raise SimulationError(
        f"no steady state found at s = {s:g} m (residual {res:.3g} N after {max_iter} Newton "
        "steps)")

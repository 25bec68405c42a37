"""Finite-difference derivatives of the kernel's forces (numba): accelerations and wheel
quantities with respect to the coordinates, the velocities and the rail irregularities seen by
each wheelset.

The kernel reads an irregularity at wheelset position s_w by linear interpolation between the
two grid points around s_w (:func:`flexride.solver.forces.contact_forces`). Adding δ to both
points changes the value seen by that wheelset by δ and by no other wheelset (they are metres
apart, the grid step is centimetres); adding −δ·(s_w − s_i) and +δ·(s_{i+1} − s_w) changes
the slope seen there by δ and the value not at all. So the input matrices are central
differences of the same force evaluation the time loop uses.
"""

from __future__ import annotations

import numba
import numpy as np

from flexride.solver.forces import evaluate
from flexride.solver.system import N_AUX, N_CST

#: Step of the irregularity perturbation (m) and of the slope perturbation (rad).
IRR_STEP = 1e-7


@numba.njit(cache=True)
def _state_jacobian(sys, X, V, s, s_win0, wrt_velocity, h, out_a, out_aux):
    """out_a[:, j] = ∂A/∂X_j (or ∂A/∂V_j), out_aux[:, j] the same of the flattened aux."""
    n = X.shape[0]
    nw = sys.ws_body.shape[0]
    nm = sys.rail_kap.shape[0]
    F = np.zeros(n)
    Ap = np.zeros(n)
    Am = np.zeros(n)
    auxp = np.zeros((nw, 2, N_AUX))
    auxm = np.zeros((nw, 2, N_AUX))
    sn = np.zeros(nm)
    cst = np.zeros((nw, 2, N_CST))
    na = nw * 2 * N_AUX
    for j in range(n):
        if wrt_velocity:
            old = V[j]
            V[j] = old + h
            evaluate(sys, X, V, s, s_win0, F, Ap, auxp, sn, cst, 0.0)
            V[j] = old - h
            evaluate(sys, X, V, s, s_win0, F, Am, auxm, sn, cst, 0.0)
            V[j] = old
        else:
            old = X[j]
            X[j] = old + h
            evaluate(sys, X, V, s, s_win0, F, Ap, auxp, sn, cst, 0.0)
            X[j] = old - h
            evaluate(sys, X, V, s, s_win0, F, Am, auxm, sn, cst, 0.0)
            X[j] = old
        for i in range(n):
            out_a[i, j] = (Ap[i] - Am[i]) / (2.0 * h)
        fp = auxp.reshape(na)
        fm = auxm.reshape(na)
        for i in range(na):
            out_aux[i, j] = (fp[i] - fm[i]) / (2.0 * h)


@numba.njit(cache=True)
def _irregularity_jacobian(sys, irr, X, V, s, s_win0, h, out_a, out_aux):
    """Columns 2·(4w + c) (value) and 2·(4w + c) + 1 (slope) of ∂(A, aux)/∂ irregularity of rail
    channel c (z left, z right, y left, y right) at wheelset w.
    """
    n = X.shape[0]
    nw = sys.ws_body.shape[0]
    nm = sys.rail_kap.shape[0]
    F = np.zeros(n)
    Ap = np.zeros(n)
    Am = np.zeros(n)
    auxp = np.zeros((nw, 2, N_AUX))
    auxm = np.zeros((nw, 2, N_AUX))
    sn = np.zeros(nm)
    cst = np.zeros((nw, 2, N_CST))
    na = nw * 2 * N_AUX
    s0 = sys.par.irr_s0
    ds = sys.par.irr_ds
    for w in range(nw):
        sw = s + sys.body_x[sys.ws_body[w]]
        i = int((sw - s0) / ds)
        frac = (sw - s0) / ds - i
        for c in range(4):
            for kind in range(2):
                # value: +δ at both neighbours; slope: δ·(s - s_w) at the two neighbours
                d0 = h if kind == 0 else -h * frac * ds
                d1 = h if kind == 0 else h * (1.0 - frac) * ds
                irr[c, i] += d0
                irr[c, i + 1] += d1
                evaluate(sys, X, V, s, s_win0, F, Ap, auxp, sn, cst, 0.0)
                irr[c, i] -= 2.0 * d0
                irr[c, i + 1] -= 2.0 * d1
                evaluate(sys, X, V, s, s_win0, F, Am, auxm, sn, cst, 0.0)
                irr[c, i] += d0
                irr[c, i + 1] += d1
                col = 2 * (4 * w + c) + kind
                for r in range(n):
                    out_a[r, col] = (Ap[r] - Am[r]) / (2.0 * h)
                fp = auxp.reshape(na)
                fm = auxm.reshape(na)
                for r in range(na):
                    out_aux[r, col] = (fp[r] - fm[r]) / (2.0 * h)


def state_jacobians(sys, X: np.ndarray, V: np.ndarray, s: float, s_win0: float,
                    wrt_velocity: bool = False, step: float = 1e-7
                    ) -> tuple[np.ndarray, np.ndarray]:
    """∂A/∂X (1/s²) or ∂A/∂V (1/s), and the same of the wheel quantities ``aux``.

    Parameters
    ----------
    sys : SystemArrays
        The kernel's arrays.
    X, V : numpy.ndarray
        Coordinates (m, rad) and velocities (m/s, rad/s) of the linearisation point.
    s, s_win0 : float
        Vehicle-centre position and rail-window start (m).
    wrt_velocity : bool
        Differentiate with respect to the velocities instead of the coordinates.
    step : float
        Central-difference step (m, rad, m/s or rad/s).

    Returns
    -------
    dA : numpy.ndarray
        (n, n) derivatives of the generalised accelerations.
    daux : numpy.ndarray
        (n_ws·2·N_AUX, n) derivatives of the per-wheel quantities (row 2·N_AUX·w + N_AUX·side +
        field, fields :data:`flexride.solver.system.AUX_FZ` …).
    """
    n = X.shape[0]
    na = int(sys.ws_body.shape[0]) * 2 * N_AUX
    out_a = np.empty((n, n))
    out_aux = np.empty((na, n))
    _state_jacobian(sys, X.copy(), V.copy(), s, s_win0, wrt_velocity, step, out_a, out_aux)
    return out_a, out_aux


def irregularity_jacobians(sys, X: np.ndarray, V: np.ndarray, s: float, s_win0: float,
                           step: float = IRR_STEP) -> tuple[np.ndarray, np.ndarray]:
    """Derivatives of the accelerations and wheel quantities with respect to the rail
    irregularities at each wheelset.

    Parameters
    ----------
    sys : SystemArrays
        The kernel's arrays; ``sys.irr`` must cover every wheelset with a grid point on both
        sides (it is perturbed in place and restored).
    X, V : numpy.ndarray
        Linearisation point (m, rad; m/s, rad/s).
    s, s_win0 : float
        Vehicle-centre position and rail-window start (m).
    step : float
        Central-difference step (m, and m/m for slopes).

    Returns
    -------
    dA : numpy.ndarray
        (n, 2·4·n_ws): column 2·(4w + c) the derivative with respect to the value of rail
        channel c (0 z left, 1 z right, 2 y left, 3 y right) at wheelset w (1/s²), column
        2·(4w + c) + 1 with respect to its slope along the track (m/s² per m/m).
    daux : numpy.ndarray
        The same for the per-wheel quantities.
    """
    n = X.shape[0]
    nw = int(sys.ws_body.shape[0])
    na = nw * 2 * N_AUX
    out_a = np.empty((n, 8 * nw))
    out_aux = np.empty((na, 8 * nw))
    _irregularity_jacobian(sys, sys.irr, X.copy(), V.copy(), s, s_win0, step, out_a, out_aux)
    return out_a, out_aux

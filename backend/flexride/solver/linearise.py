"""Finite-difference Jacobians of the accelerations (numba): used for the static equilibrium
and for the linearised stability estimate.
"""

from __future__ import annotations

import numba
import numpy as np

from flexride.solver.forces import evaluate
from flexride.solver.system import N_AUX, N_CST


@numba.njit(cache=True)
def state_jacobian_columns(sys, X, V, s, s_win0, wrt_velocity, steps, cols, out_a, out_aux):
    """out_a[:, jj] = ∂A/∂X_j (or ∂A/∂V_j), out_aux[:, jj] the same of the flattened wheel
    quantities ``aux``, for j = cols[jj], central differences with step steps[jj].
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
    P = V if wrt_velocity else X  # the perturbed vector
    for jj in range(cols.shape[0]):
        j = cols[jj]
        h = steps[jj]
        old = P[j]
        for k in range(2):  # one call site: evaluate is compiled into this kernel once
            P[j] = old + h if k == 0 else old - h
            evaluate(sys, X, V, s, s_win0, F, Ap if k == 0 else Am, auxp if k == 0 else auxm,
                     sn, cst, 0.0)
        P[j] = old
        for i in range(n):
            out_a[i, jj] = (Ap[i] - Am[i]) / (2.0 * h)
        fp = auxp.reshape(na)
        fm = auxm.reshape(na)
        for i in range(na):
            out_aux[i, jj] = (fp[i] - fm[i]) / (2.0 * h)


def workspace(sys) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Scratch arrays (F, A, aux, sn, creep state) for :func:`accelerations` and Jacobians."""
    n = sys.minv.shape[0]
    nw = int(sys.ws_body.shape[0])
    nm = int(sys.rail_kap.shape[0])
    return (np.zeros(n), np.zeros(n), np.zeros((nw, 2, N_AUX)), np.zeros(nm),
            np.zeros((nw, 2, N_CST)))


def accelerations(sys, X: np.ndarray, V: np.ndarray, s: float, s_win0: float) -> np.ndarray:
    """Generalised accelerations at (X, V, s) (copy)."""
    F, A, aux, sn, cst = workspace(sys)
    evaluate(sys, X, V, s, s_win0, F, A, aux, sn, cst, 0.0)
    return A.copy()


def jacobian(
    sys,
    X: np.ndarray,
    V: np.ndarray,
    s: float,
    s_win0: float,
    cols: np.ndarray,
    wrt_velocity: bool = False,
    step: float = 1e-7,
) -> np.ndarray:
    """∂A/∂X[:, cols] (or ∂A/∂V[:, cols]) by central differences (1/s² or 1/s)."""
    cols = np.ascontiguousarray(cols, dtype=np.int64)
    out = np.empty((X.shape[0], cols.shape[0]))
    out_aux = np.empty((sys.ws_body.shape[0] * 2 * N_AUX, cols.shape[0]))
    h = np.full(cols.shape[0], step)
    state_jacobian_columns(sys, X.copy(), V.copy(), s, s_win0, wrt_velocity, h, cols, out,
                           out_aux)
    return out



@numba.njit(cache=True)
def step_jacobian_columns(sys, X, V, cst, s, s_win0, relax_dt, h_state, h_creep, out):
    """Central differences of one force evaluation as the kernel makes it — the creep forces
    relaxed over ``relax_dt`` (s) from the state ``cst`` — with respect to the coordinates,
    the velocities and that creep state.

    ``out`` has ``n + nc`` rows (the accelerations, then the new creep state, flattened) and
    ``2n + nc`` columns (∂/∂X, ∂/∂V, ∂/∂cst); steps ``h_state`` (m, rad, m/s, rad/s) and
    ``h_creep`` (N, N·m). ``X``, ``V`` and ``cst`` are left as given.
    """
    n = X.shape[0]
    nw = sys.ws_body.shape[0]
    nm = sys.rail_kap.shape[0]
    nc = cst.size
    F = np.zeros(n)
    A = np.zeros((2, n))
    aux = np.zeros((nw, 2, N_AUX))
    sn = np.zeros(nm)
    c0 = cst.copy()
    cw = np.zeros((2, nw, 2, N_CST))
    for col in range(2 * n + nc):
        h = h_state if col < 2 * n else h_creep
        for k in range(2):
            d = h if k == 0 else -h
            cw[k] = c0
            if col < n:
                old = X[col]
                X[col] = old + d
            elif col < 2 * n:
                old = V[col - n]
                V[col - n] = old + d
            else:
                old = 0.0
                cw[k].reshape(nc)[col - 2 * n] += d
            evaluate(sys, X, V, s, s_win0, F, A[k], aux, sn, cw[k], relax_dt)
            if col < n:
                X[col] = old
            elif col < 2 * n:
                V[col - n] = old
        for i in range(n):
            out[i, col] = (A[0, i] - A[1, i]) / (2.0 * h)
        cp = cw[0].reshape(nc)
        cm = cw[1].reshape(nc)
        for i in range(nc):
            out[n + i, col] = (cp[i] - cm[i]) / (2.0 * h)

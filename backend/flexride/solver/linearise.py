"""Finite-difference Jacobians of the accelerations (numba): used for the static equilibrium
and for the linearised stability estimate.
"""

from __future__ import annotations

import numba
import numpy as np

from flexride.solver.forces import evaluate
from flexride.solver.system import N_AUX, N_CST


@numba.njit(cache=True)
def _jacobian(sys, X, V, s, s_win0, cols, wrt_velocity, h, F, A, aux, sn, cst, out):
    """out[:, j] = ∂A/∂X[cols[j]] (or ∂A/∂V) by central differences with step h[j]."""
    Ap = np.empty_like(A)
    Am = np.empty_like(A)
    for jj in range(cols.shape[0]):
        j = cols[jj]
        if wrt_velocity:
            old = V[j]
            V[j] = old + h[jj]
            evaluate(sys, X, V, s, s_win0, F, Ap, aux, sn, cst, 0.0)
            V[j] = old - h[jj]
            evaluate(sys, X, V, s, s_win0, F, Am, aux, sn, cst, 0.0)
            V[j] = old
        else:
            old = X[j]
            X[j] = old + h[jj]
            evaluate(sys, X, V, s, s_win0, F, Ap, aux, sn, cst, 0.0)
            X[j] = old - h[jj]
            evaluate(sys, X, V, s, s_win0, F, Am, aux, sn, cst, 0.0)
            X[j] = old
        for i in range(A.shape[0]):
            out[i, jj] = (Ap[i] - Am[i]) / (2.0 * h[jj])


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
    F, A, aux, sn, cst = workspace(sys)
    cols = np.ascontiguousarray(cols, dtype=np.int64)
    out = np.empty((X.shape[0], cols.shape[0]))
    h = np.full(cols.shape[0], step)
    _jacobian(sys, X.copy(), V.copy(), s, s_win0, cols, wrt_velocity, h, F, A, aux, sn, cst, out)
    return out

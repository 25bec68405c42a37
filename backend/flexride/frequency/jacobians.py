"""Finite-difference derivatives of the kernel's forces (numba): accelerations and wheel
quantities with respect to the coordinates, the velocities and the rail irregularities seen by
each wheelset.

The kernel reads an irregularity at wheelset position s_w by linear interpolation between the
two grid points around s_w (:func:`flexride.solver.forces.contact_forces`). Adding δ to both
points changes the value seen by that wheelset by δ and by no other wheelset (they are metres
apart, the grid step is centimetres); adding −δ·(s_w − s_i) and +δ·(s_{i+1} − s_w) changes
the slope seen there by δ and the value not at all. So the input matrices are central
differences of the same force evaluation the time loop uses.

Steps: the contact is the kernel's only nonlinear force, so the columns the wheel quantities
depend on (a wheelset's lateral, vertical, roll and yaw motion, the rail modes, the
irregularities) are Richardson-extrapolated central differences, (4·D(h) − D(2h))/3 with
h = 1e-6: truncation O(h⁴) (1e-9 of the column) and a rounding error ε·|A|/h ten times smaller
than a plain difference with the 1e-7 that was used before (whose truncation was 1e-7). The
suspension, elastic, inertial and traction forces are affine in the coordinates and
velocities, so every other column is exact with any step: it is differenced with 1e-4, which
makes its rounding error negligible. Both matter because the comfort indices are sensitive to
rounding in the Jacobians (a plain 1e-7 difference moved them by 3e-10 for one ulp of the
operating point); see :func:`column_methods`.
"""

from __future__ import annotations

import numba
import numpy as np

from flexride.solver.forces import evaluate
from flexride.solver.linearise import state_jacobian_columns
from flexride.solver.system import N_AUX, N_CST

#: Step h of the irregularity perturbation (m) and of the slope perturbation (rad);
#: Richardson-extrapolated from h and 2h.
IRR_STEP = 1e-6
#: Step h of the state Jacobians' central differences (m, rad, m/s, rad/s); the contact's
#: columns are Richardson-extrapolated from h and 2h.
STATE_STEP = 1e-6
#: Step of the columns no contact quantity depends on (affine forces: any step is exact).
AFFINE_STEP = 1e-4
#: A large-step column must agree with the small-step one within this fraction of its
#: largest entry (else the small step is kept).
AFFINE_CHECK_RTOL = 1e-6
#: How a column is differenced (:func:`column_methods`): central difference with STATE_STEP,
#: Richardson extrapolation from STATE_STEP and 2·STATE_STEP, central difference with
#: AFFINE_STEP.
PLAIN, RICHARDSON, AFFINE = 0, 1, 2


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
                    wrt_velocity: bool = False, step: float | np.ndarray = STATE_STEP,
                    cols: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
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
    step : float or numpy.ndarray
        Central-difference step (m, rad, m/s or rad/s), or one per column.
    cols : numpy.ndarray, optional
        Only these columns (coordinate indices), in this order; default all. A column is the
        same number whichever others are asked for.

    Returns
    -------
    dA : numpy.ndarray
        (n, n_cols) derivatives of the generalised accelerations.
    daux : numpy.ndarray
        (n_ws·2·N_AUX, n_cols) derivatives of the per-wheel quantities (row
        2·N_AUX·w + N_AUX·side + field, fields :data:`flexride.solver.system.AUX_FZ` …).
    """
    n = X.shape[0]
    idx = np.arange(n, dtype=np.int64) if cols is None else np.ascontiguousarray(
        cols, dtype=np.int64)
    na = int(sys.ws_body.shape[0]) * 2 * N_AUX
    steps = np.ascontiguousarray(np.broadcast_to(np.asarray(step, dtype=float), idx.shape))
    out_a = np.empty((n, idx.size))
    out_aux = np.empty((na, idx.size))
    state_jacobian_columns(sys, X.copy(), V.copy(), s, s_win0, wrt_velocity, steps, idx, out_a,
                    out_aux)
    return out_a, out_aux


def column_methods(dA: np.ndarray, daux: np.ndarray) -> np.ndarray:
    """How each column of a state Jacobian is differenced, from a first pass with
    :data:`STATE_STEP`: :data:`RICHARDSON` where a wheel quantity depends on the coordinate (the
    contact, nonlinear), :data:`AFFINE` where none does and the accelerations do (affine forces
    only), :data:`PLAIN` for a zero column.
    """
    contact = np.any(daux != 0.0, axis=0)
    methods = np.full(dA.shape[1], PLAIN, dtype=np.int64)
    methods[contact] = RICHARDSON
    methods[~contact & np.any(dA != 0.0, axis=0)] = AFFINE
    return methods


def jacobian_columns(sys, X: np.ndarray, V: np.ndarray, s: float, s_win0: float,
                     wrt_velocity: bool, cols: np.ndarray, methods: np.ndarray,
                     first: tuple[np.ndarray, np.ndarray] | None = None
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Columns ``cols`` of ∂A/∂X (or ∂A/∂V) and of ∂aux/∂X, each by its method.

    Parameters
    ----------
    sys, X, V, s, s_win0, wrt_velocity :
        As :func:`state_jacobians`.
    cols : numpy.ndarray
        Column (coordinate) indices.
    methods : numpy.ndarray
        One of :data:`PLAIN`, :data:`RICHARDSON`, :data:`AFFINE` per column of ``cols``.
    first : (numpy.ndarray, numpy.ndarray), optional
        These columns with :data:`STATE_STEP` already (not differenced again).

    Returns
    -------
    dA, daux : numpy.ndarray
        (n, n_cols) and (n_aux, n_cols); a column is the same number whichever others are
        asked for.
    """
    cols = np.asarray(cols, dtype=np.int64)
    args = (sys, X, V, s, s_win0, wrt_velocity)
    dA, daux = first if first is not None else state_jacobians(*args, STATE_STEP, cols)
    dA, daux = dA.copy(), daux.copy()
    rich = np.flatnonzero(methods == RICHARDSON)
    if rich.size:
        a2, x2 = state_jacobians(*args, 2.0 * STATE_STEP, cols[rich])
        dA[:, rich] = (4.0 * dA[:, rich] - a2) / 3.0
        daux[:, rich] = (4.0 * daux[:, rich] - x2) / 3.0
    aff = np.flatnonzero(methods == AFFINE)
    if aff.size:
        dA[:, aff], daux[:, aff] = state_jacobians(*args, AFFINE_STEP, cols[aff])
    return dA, daux


def refined_state_jacobians(sys, X: np.ndarray, V: np.ndarray, s: float, s_win0: float,
                            wrt_velocity: bool = False
                            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """∂A/∂X (or ∂A/∂V) and ∂aux/∂X with each column differenced by its method (module
    docstring): a first pass with :data:`STATE_STEP` finds which columns the contact depends
    on, then those are Richardson-extrapolated and the affine ones differenced with
    :data:`AFFINE_STEP` — each checked against the first pass (within
    :data:`AFFINE_CHECK_RTOL` of the column's largest entry) and left :data:`PLAIN` where
    they differ.

    Returns
    -------
    dA, daux : numpy.ndarray
        As :func:`state_jacobians` (all columns).
    methods : numpy.ndarray
        (n,) the method of each column, for :func:`jacobian_columns`.
    """
    first = state_jacobians(sys, X, V, s, s_win0, wrt_velocity, STATE_STEP)
    methods = column_methods(*first)
    cols = np.arange(X.shape[0], dtype=np.int64)
    dA, daux = jacobian_columns(sys, X, V, s, s_win0, wrt_velocity, cols, methods, first)
    aff = np.flatnonzero(methods == AFFINE)
    scale = np.abs(first[0][:, aff]).max(axis=0)
    bad = aff[np.any(np.abs(dA[:, aff] - first[0][:, aff]) > AFFINE_CHECK_RTOL * scale,
                     axis=0)]
    if bad.size:
        methods[bad] = PLAIN
        dA[:, bad], daux[:, bad] = first[0][:, bad], first[1][:, bad]
    return dA, daux, methods


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
        Central-difference step h (m, and m/m for slopes): Richardson-extrapolated from h and
        2h (module docstring).

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
    out: list[tuple[np.ndarray, np.ndarray]] = []
    for h in (step, 2.0 * step):
        out_a = np.empty((n, 8 * nw))
        out_aux = np.empty((na, 8 * nw))
        _irregularity_jacobian(sys, sys.irr, X.copy(), V.copy(), s, s_win0, h, out_a, out_aux)
        out.append((out_a, out_aux))
    (a1, x1), (a2, x2) = out
    return (4.0 * a1 - a2) / 3.0, (4.0 * x1 - x2) / 3.0

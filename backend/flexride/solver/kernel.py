"""The time loop: Zhai's explicit two-step integration of the whole system in one numba
function (DESIGN §3.5), over flat arrays, with no allocation inside.

X_{n+1} = X_n + V_n Δt + (½ + ψ) A_n Δt² − ψ A_{n−1} Δt²
V_{n+1} = V_n + (1 + φ) A_n Δt − φ A_{n−1} Δt          (first step: ψ = φ = 0)

A watch (:func:`_watch`) stops a run whose wheel forces chatter from step to step — a
period-two oscillation of the integration that a saturating creep force can hold without
diverging, which the time-step check (:mod:`flexride.solver.stability`) cannot see when it
comes from the nonlinearity.

Outputs are decimated: accelerations of points are the mean over each output interval
(velocity difference divided by the interval, an exact boxcar average that keeps aliasing
down), wheel–rail forces and suspension-element forces are averaged over the interval (the
mean of the forces evaluated at the interval's steps), displacements are sampled.
"""

from __future__ import annotations

import math

import numba

from flexride._numba_env import FASTMATH
from flexride.solver.forces import _CALLED_FROM_KERNELS, _frame_specific_force, evaluate
from flexride.solver.system import (
    AUX_ANGLE,
    AUX_FY,
    AUX_FZ,
    AUX_N,
    AUX_N_FLANGE,
    AUX_RAIL_Y,
    AUX_RAIL_Z,
    CH_COORD,
    CH_ELEMENT_FORCE,
    CH_POINT_ACC_Y,
    CH_POINT_ACC_Z,
    CH_RAIL_Y,
    CH_RAIL_Z,
    CH_WHEEL_ANGLE,
    CH_WHEEL_FY,
    CH_WHEEL_FZ,
    CH_WHEEL_N,
    CH_WHEEL_N_FLANGE,
    CHATTER_STEPS,
    T_FIRST,
    T_NREC,
    T_STEP,
    T_TIME,
    T_WIN_S0,
    W_CHANGE,
    W_COUNT,
    W_CREEP_Y,
    W_LAST,
)

_FM = set(FASTMATH)

STATUS_OK, STATUS_NONFINITE, STATUS_RUNAWAY, STATUS_FULL, STATUS_CHATTER = 0, 1, 2, 3, 4


@numba.njit(cache=True, fastmath=_FM, inline="always")
def zhai_update(X, V, A, Ap, dt, psi, phi):
    """One step of Zhai's explicit method for all coordinates; ``Ap`` becomes ``A``.

    X ← X + V·Δt + (½ + ψ)·A·Δt² − ψ·A_prev·Δt²;  V ← V + (1 + φ)·A·Δt − φ·A_prev·Δt.
    """
    dt2 = dt * dt
    c1 = (0.5 + psi) * dt2
    c2 = psi * dt2
    c3 = (1.0 + phi) * dt
    c4 = phi * dt
    for i in range(X.shape[0]):
        a = A[i]
        ap = Ap[i]
        X[i] += V[i] * dt + c1 * a - c2 * ap
        V[i] += c3 * a - c4 * ap
        Ap[i] = a


@numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)
def _shift_window(sys, X, V, Ap, nshift, u, q):
    """Move the rail window forward by ``nshift`` fastener bays.

    The modal state of each rail and direction is converted to values at the fasteners
    (discrete sine transform, exact on the N − 1 modes), shifted, and converted back; the bays
    entering at the front start undeformed. Applied to coordinates, velocities and the previous
    accelerations of Zhai's scheme.
    """
    nm = sys.par.n_rail_modes
    nv = sys.par.n_veh
    dst = sys.rail_dst
    nb = nm + 1
    for arr_id in range(3):
        arr = X if arr_id == 0 else (V if arr_id == 1 else Ap)
        for blk in range(6):
            o = nv + blk * nm
            for j in range(nm):
                acc = 0.0
                for k in range(nm):
                    acc += dst[j, k] * arr[o + k]
                u[j] = acc
            for j in range(nm):
                jj = j + nshift
                q[j] = u[jj] if jj < nm else 0.0
            for k in range(nm):
                acc = 0.0
                for j in range(nm):
                    acc += dst[j, k] * q[j]
                arr[o + k] = acc * 2.0 / nb


@numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)
def _record(sys, X, V, aux, facc, eacc, ptv, pscr, X0, s, tstate, rec, rec_t, rec_s):
    """Write one output sample (row ``tstate[T_NREC]`` of ``rec``) and restart the interval's
    means (``facc``, ``eacc``); False when ``rec`` is full.
    """
    par = sys.par
    k = int(tstate[T_NREC])
    if k >= rec.shape[0]:
        return False
    ndec = par.n_dec
    tout = ndec * par.dt
    g = par.gravity
    phi = sys.phi
    for p in range(par.n_points):
        b = sys.pt_body[p]
        o = sys.body_off[b]
        nd = sys.body_ndof[b]
        base = sys.pt_phi[p]
        # contiguous views, so that the loop vectorises
        row_y = phi[base + nd:base + 2 * nd]
        row_z = phi[base + 2 * nd:base + 3 * nd]
        row_rx = phi[base + 3 * nd:base + 4 * nd]
        xb = X[o:o + nd]
        vb = V[o:o + nd]
        vy = 0.0
        vz = 0.0
        rx = 0.0
        for j in range(nd):
            vy += row_y[j] * vb[j]
            vz += row_z[j] * vb[j]
            rx += row_rx[j] * xb[j]
        ay = (vy - ptv[p, 0]) / tout
        az = (vz - ptv[p, 1]) / tout
        ptv[p, 0] = vy
        ptv[p, 1] = vz
        f_y, f_z, _, _, _ = _frame_specific_force(sys, s + sys.body_x[b])
        pscr[p, 0] = ay + f_y + rx * f_z
        pscr[p, 1] = az + f_z - rx * f_y - g
    for c in range(par.n_ch):
        kind = sys.ch[c, 0]
        a = sys.ch[c, 1]
        bb = sys.ch[c, 2]
        if kind == CH_POINT_ACC_Y:
            val = pscr[a, 0]
        elif kind == CH_POINT_ACC_Z:
            val = pscr[a, 1]
        elif kind == CH_WHEEL_FZ:
            val = facc[a, bb, 0] / ndec
        elif kind == CH_WHEEL_FY:
            val = facc[a, bb, 1] / ndec
        elif kind == CH_WHEEL_N:
            val = facc[a, bb, 2] / ndec
        elif kind == CH_WHEEL_N_FLANGE:
            val = facc[a, bb, 3] / ndec
        elif kind == CH_WHEEL_ANGLE:
            val = facc[a, bb, 4] / ndec
        elif kind == CH_RAIL_Z:
            val = aux[a, bb, AUX_RAIL_Z]
        elif kind == CH_RAIL_Y:
            val = aux[a, bb, AUX_RAIL_Y]
        elif kind == CH_COORD:
            val = X[a] - X0[a]
        elif kind == CH_ELEMENT_FORCE:
            val = eacc[a, bb] / ndec
        else:
            val = math.nan
        rec[k, c] = val
    rec_t[k] = tstate[T_TIME]
    rec_s[k] = s
    tstate[T_NREC] = k + 1
    nw = par.n_ws
    for w in range(nw):
        for sd in range(2):
            facc[w, sd, 0] = 0.0
            facc[w, sd, 1] = 0.0
            facc[w, sd, 2] = 0.0
            facc[w, sd, 3] = 0.0
            facc[w, sd, 4] = 0.0
    for e in range(eacc.shape[0]):
        eacc[e, 0] = 0.0
        eacc[e, 1] = 0.0
        eacc[e, 2] = 0.0
    return True


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _watch_value(watch, w, sd, q, value, limit):
    """Record one step of a watched force (N); return the steps in a row its change has
    alternated in sign with a size beyond ``limit`` (N).
    """
    change = value - watch[w, sd, q, W_LAST]
    if change * watch[w, sd, q, W_CHANGE] < 0.0 and abs(change) > limit:
        watch[w, sd, q, W_COUNT] += 1.0
    else:
        watch[w, sd, q, W_COUNT] = 0.0
    watch[w, sd, q, W_LAST] = value
    watch[w, sd, q, W_CHANGE] = change
    return watch[w, sd, q, W_COUNT]


@numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)
def _watch(sys, aux, cst, watch, info):
    """Watch each wheel's lateral creep force (both slots) and normal force for a chatter:
    STATUS_CHATTER after :data:`~flexride.solver.system.CHATTER_STEPS` steps in a row of
    changes alternating in sign beyond ``chatter_force``, with ``info`` = (wheelset·2 + side,
    quantity); STATUS_OK otherwise.
    """
    limit = sys.par.chatter_force
    for w in range(sys.par.n_ws):
        for sd in range(2):
            creep_y = cst[w, sd, 1] + cst[w, sd, 4]
            for q in range(2):
                value = creep_y if q == W_CREEP_Y else aux[w, sd, AUX_N]
                if _watch_value(watch, w, sd, q, value, limit) >= CHATTER_STEPS:
                    info[0] = 2 * w + sd
                    info[1] = q
                    return STATUS_CHATTER
    return STATUS_OK


@numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)
def _check(sys, X, X0, info):
    """Return STATUS_OK, or a fault status with the offending coordinate in ``info[0]``."""
    n = X.shape[0]
    for i in range(n):
        if not math.isfinite(X[i]):
            info[0] = i
            return STATUS_NONFINITE
    lim = sys.par.runaway
    for b in range(sys.body_off.shape[0]):
        o = sys.body_off[b]
        for j in range(3):
            if abs(X[o + j] - X0[o + j]) > lim:
                info[0] = o + j
                return STATUS_RUNAWAY
    return STATUS_OK


@numba.njit(cache=True, fastmath=_FM)
def run_chunk(
    sys,
    X,
    V,
    A,
    Ap,
    F,
    aux,
    sn,
    cst,
    facc,
    eacc,
    ptv,
    pscr,
    X0,
    u,
    q,
    tstate,
    n_steps,
    rec,
    rec_t,
    rec_s,
    info,
    watch,
):
    """Advance the system by up to ``n_steps`` steps of Zhai's method.

    Returns a status code (STATUS_OK, STATUS_NONFINITE, STATUS_RUNAWAY, STATUS_CHATTER, or
    STATUS_FULL when the record buffer is full); ``tstate`` carries time, window start, step
    and record counters, ``watch`` the state of :func:`_watch`. ``facc`` (per wheel, see
    :data:`~flexride.solver.system.N_FACC`) and ``eacc`` (per suspension element, the x, y, z
    force of ``sys.el_force``; N) sum the forces of the current output interval's steps.
    """
    par = sys.par
    dt = par.dt
    speed = par.speed
    ndec = par.n_dec
    nw = par.n_ws
    spacing = par.spacing
    win_len = par.win_len
    margin = par.margin
    x_front = -1e30
    for w in range(nw):
        xb = sys.body_x[sys.ws_body[w]]
        if xb > x_front:
            x_front = xb
    nshift = par.shift_bays
    el_force = sys.el_force
    n_el = min(eacc.shape[0], el_force.shape[0])
    for _ in range(n_steps):
        if tstate[T_FIRST] == 0.0:
            psi = 0.0
            ph = 0.0
            tstate[T_FIRST] = 1.0
        else:
            psi = par.psi
            ph = par.phi
        zhai_update(X, V, A, Ap, dt, psi, ph)
        t = tstate[T_TIME] + dt
        tstate[T_TIME] = t
        s = par.s_start + speed * t
        # move the rail window when the front wheelset nears its end
        if s + x_front - tstate[T_WIN_S0] > win_len - margin:
            _shift_window(sys, X, V, Ap, nshift, u, q)
            tstate[T_WIN_S0] += nshift * spacing
        evaluate(sys, X, V, s, tstate[T_WIN_S0], F, A, aux, sn, cst, dt)
        if _watch(sys, aux, cst, watch, info) != STATUS_OK:
            tstate[T_STEP] += 1.0
            return STATUS_CHATTER
        for w in range(nw):
            for sd in range(2):
                facc[w, sd, 0] += aux[w, sd, AUX_FZ]
                facc[w, sd, 1] += aux[w, sd, AUX_FY]
                facc[w, sd, 2] += aux[w, sd, AUX_N]
                facc[w, sd, 3] += aux[w, sd, AUX_N_FLANGE]
                facc[w, sd, 4] += aux[w, sd, AUX_ANGLE]
        # every element's force (a few dozen additions, cheaper than choosing the recorded)
        for e in range(n_el):
            eacc[e, 0] += el_force[e, 0]
            eacc[e, 1] += el_force[e, 1]
            eacc[e, 2] += el_force[e, 2]
        step = tstate[T_STEP] + 1.0
        tstate[T_STEP] = step
        if int(step) % ndec == 0:
            st = _check(sys, X, X0, info)
            if st != STATUS_OK:
                return st
            if not _record(sys, X, V, aux, facc, eacc, ptv, pscr, X0, s, tstate, rec, rec_t,
                           rec_s):
                return STATUS_FULL
    return STATUS_OK

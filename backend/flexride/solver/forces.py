"""Generalised forces of the coupled vehicle–track system (numba, no allocation).

``evaluate`` fills the generalised force vector for given coordinates and velocities; the
kernel divides by the diagonal mass. It is split into the three parts the benchmark times
separately: vehicle (inertial, gravity, elastic and suspension forces), rail (fastener and beam
forces) and contact (wheel–rail normal, creep and flange forces with their projection on the
rail modes).

Each force is computed in named steps (normal load, creep forces, transformation to the track
frame, loads on the wheelset and the rail, …), helpers compiled with ``inline="always"`` so
that the compiled code is that of one long function. Two properties of the compiler decide
how the steps are cut (both checked when they were split: results bit for bit as before, time
per step not longer):

* Results: with fast-math reassociation the order in which LLVM combines the terms of a sum or
  product follows where in the function their values were read from memory. The helpers
  therefore take values from the caller where these were read before the split (the
  wheelset's coordinates and velocities, its creep state, the side sign ``sg``) instead of
  reading them again, and a load on the wheelset is added to ``F`` right where it is computed
  (in the branch of its contact model). Moving a read or such a sum changes the last bits.
* Time: an array passed to an inlined helper costs an atomic reference-count increment and
  decrement per call unless numba's pruning removes the pair, which it does only when the
  array's last use is not inside a branch. Helpers called in loops take the arrays they index
  (never ``sys``, a tuple of 33 arrays) and use them in straight-line code; the branches that
  decide whether to call them sit in the caller (e.g. ``_any_nonzero``), and table rows are
  taken from their table before the branching lookups (e.g. ``_line_values``).
"""

from __future__ import annotations

import math
from types import FunctionType
from typing import Any

import numba
import numpy as np

from flexride._numba_env import FASTMATH
from flexride.contact.creep import creep_forces
from flexride.contact.hertz import hertz_force
from flexride.solver.system import (
    AUX_ANGLE,
    AUX_DELTA,
    AUX_FX,
    AUX_FY,
    AUX_FZ,
    AUX_N,
    AUX_N_FLANGE,
    AUX_RAIL_Y,
    AUX_RAIL_Z,
    BL_DROLL,
    BL_HEADING,
    BL_HINT,
    BL_KAPPA,
    BL_ROLL,
    CT_C11,
    CT_C22,
    CT_C23,
    CT_C33,
    CT_CA,
    CT_CB,
    CT_DZ,
    CT_GAMMA,
    CT_R,
    CT_YC,
    LN_DKAPPA,
    LN_HEADING,
    LN_HINT,
    LN_KAPPA,
    LN_ROLL,
    PT_GH,
)

_FM = set(FASTMATH)
#: Options of the kernels only ever called from other compiled functions: no CPython and C
#: wrappers. A function of ``sys`` otherwise also compiles the unboxing of its 33 arrays and the
#: named scalars, which costs more than a small function itself (cold compile of a first run
#: about 2 s CPU less); the function's own code is the same. Called from Python such a function
#: crashes the process: they are private (``_vehicle_forces``, …); the public names are the same
#: functions compiled with the wrapper (:func:`_twin`), compiled only where used.
_CALLED_FROM_KERNELS: dict[str, Any] = {"no_cpython_wrapper": True, "no_cfunc_wrapper": True}


def _twin(name: str, fn: Any) -> Any:
    """A copy of the Python function ``fn`` under ``name``, to compile a second time with other
    options (its own entries in numba's cache, which are named after the function): the kernels
    call ``_vehicle_forces`` (:data:`_CALLED_FROM_KERNELS`), Python and the benchmark
    ``vehicle_forces``, the same code with the Python wrapper.
    """
    twin = FunctionType(fn.__code__, fn.__globals__, name, fn.__defaults__, fn.__closure__)
    twin.__qualname__ = name
    twin.__doc__ = fn.__doc__
    return twin


@numba.njit(cache=True, fastmath=_FM, inline="always")
def table_value(row, y0, dy, y):
    """Linear interpolation in a uniform table, clamped at both ends."""
    n = row.shape[0]
    u = (y - y0) / dy
    if u <= 0.0:
        return row[0]
    if u >= n - 1:
        return row[n - 1]
    i = int(u)
    f = u - i
    return row[i] + f * (row[i + 1] - row[i])


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _lerp_at(t, side, slot, fld, i, f):
    """Field ``fld`` of slot ``slot`` on ``side`` of a two-slot table, interpolated between grid
    points ``i`` and ``i + 1`` at fraction ``f``.
    """
    a = t[side, slot, fld, i]
    return a + f * (t[side, slot, fld, i + 1] - a)


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _rail_at(sn, X, V, oz, oy, ot, nm):
    """Rail displacements (z, y, θ) and velocities (z, y, θ) at a wheel in one pass over the
    modes (``sn`` the mode shapes there).
    """
    xz = X[oz:oz + nm]
    xy = X[oy:oy + nm]
    xt = X[ot:ot + nm]
    vz = V[oz:oz + nm]
    vy = V[oy:oy + nm]
    vt = V[ot:ot + nm]
    a0 = 0.0
    a1 = 0.0
    a2 = 0.0
    a3 = 0.0
    a4 = 0.0
    a5 = 0.0
    for k in range(nm):
        sk = sn[k]
        a0 += sk * xz[k]
        a1 += sk * xy[k]
        a2 += sk * xt[k]
        a3 += sk * vz[k]
        a4 += sk * vy[k]
        a5 += sk * vt[k]
    return a0, a1, a2, a3, a4, a5


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _lerp_or_zero(row, s0, ds, s):
    """Linear interpolation on a uniform grid, zero outside it (irregularities)."""
    n = row.shape[0]
    u = (s - s0) / ds
    if u < 0.0 or u > n - 1:
        return 0.0
    i = int(u)
    if i >= n - 1:
        return row[n - 1]
    f = u - i
    return row[i] + f * (row[i + 1] - row[i])


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _dot(a, b):
    acc = 0.0
    for j in range(a.shape[0]):
        acc += a[j] * b[j]
    return acc


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _axpy(alpha, x, y):
    for j in range(x.shape[0]):
        y[j] += alpha * x[j]


def frame_specific_force(sys, s):
    """Specific force (m/s²) a body following the track frame at ``s`` needs: (lateral,
    vertical) components in the canted track frame, plus curvature rate terms.

    Returns (f_y, f_z, kappa, roll, dkappa): f = a_frame − g, so that a body at rest in the
    frame feels f (an accelerometer reads f).
    """
    par = sys.par
    ln = sys.line
    s0, ds = par.ln_s0, par.ln_ds
    kap = table_value(ln[LN_KAPPA], s0, ds, s)
    roll = table_value(ln[LN_ROLL], s0, ds, s)
    dk = table_value(ln[LN_DKAPPA], s0, ds, s)
    v2 = par.speed * par.speed
    g = par.gravity
    c, sn = math.cos(roll), math.sin(roll)
    f_y = v2 * kap * c + g * sn
    f_z = -v2 * kap * sn + g * c
    return f_y, f_z, kap, roll, dk


_frame_specific_force = numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)(
    _twin("_frame_specific_force", frame_specific_force))
frame_specific_force = numba.njit(cache=True, fastmath=_FM)(frame_specific_force)


@numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)
def _marker_kinematics3(phi, b0, nd, X, V, o):
    """Three rows of a marker matrix (``nd`` columns, the first row at offset ``b0`` in ``phi``)
    applied to the body's coordinates and velocities (offset ``o``) in one pass: (u0, u1, u2,
    v0, v1, v2). The caller gives the offset, not a row number: numba would compile once per
    literal row number.
    """
    row0 = phi[b0:b0 + nd]
    row1 = phi[b0 + nd:b0 + 2 * nd]
    row2 = phi[b0 + 2 * nd:b0 + 3 * nd]
    x = X[o:o + nd]
    v = V[o:o + nd]
    u0 = 0.0
    u1 = 0.0
    u2 = 0.0
    v0 = 0.0
    v1 = 0.0
    v2 = 0.0
    # contiguous views (not offsets into the flat arrays) let LLVM vectorise the loop
    for j in range(nd):
        xj = x[j]
        vj = v[j]
        u0 += row0[j] * xj
        u1 += row1[j] * xj
        u2 += row2[j] * xj
        v0 += row0[j] * vj
        v1 += row1[j] * vj
        v2 += row2[j] * vj
    return u0, u1, u2, v0, v1, v2


@numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)
def _marker_force3(phi, b0, nd, F, o, f0, f1, f2):
    """Add the generalised force of marker forces (f0, f1, f2) on three rows of a marker matrix
    (the first at offset ``b0`` in ``phi``, as :func:`_marker_kinematics3`):
    F[o:o+nd] += Φ[rows]ᵀ f, in one pass.
    """
    row0 = phi[b0:b0 + nd]
    row1 = phi[b0 + nd:b0 + 2 * nd]
    row2 = phi[b0 + 2 * nd:b0 + 3 * nd]
    f = F[o:o + nd]
    for j in range(nd):
        f[j] += f0 * row0[j] + f1 * row1[j] + f2 * row2[j]


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _line_values(ln, ls0, lds, sb):
    """Heading (rad), lateral offset (m) and d(roll)/ds (rad/m, central difference over one
    table step ``lds``) of the line at arc length ``sb`` (m), from the line table ``ln``
    starting at ``ls0`` (m).
    """
    heading, hint, roll = ln[LN_HEADING], ln[LN_HINT], ln[LN_ROLL]
    return (
        table_value(heading, ls0, lds, sb),
        table_value(hint, ls0, lds, sb),
        (table_value(roll, ls0, lds, sb + 0.5 * lds) - table_value(roll, ls0, lds, sb - 0.5 * lds))
        / lds,
    )


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _store_body_line(bl, b, heading, hint, roll, kap, droll):
    """Line values at body ``b`` into ``bl[b]``: heading (rad), lateral offset (m), roll (rad),
    curvature (1/m) and d(roll)/ds (rad/m).
    """
    bl[b, BL_HEADING] = heading
    bl[b, BL_HINT] = hint
    bl[b, BL_ROLL] = roll
    bl[b, BL_KAPPA] = kap
    bl[b, BL_DROLL] = droll


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _add_elastic_forces(F, X, V, kdiag, cdiag, o, nd):
    """Add the modal restoring and damping forces −k·q − c·q̇ (N, per unit modal mass) of the
    elastic coordinates ``o + 6 … o + nd`` of one body to ``F``.
    """
    fe = F[o + 6:o + nd]
    ke = kdiag[o + 6:o + nd]
    ce = cdiag[o + 6:o + nd]
    xe = X[o + 6:o + nd]
    ve = V[o + 6:o + nd]
    for j in range(nd - 6):
        fe[j] -= ke[j] * xe[j] + ce[j] * ve[j]


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _element_frame_offsets(bl, a, bb, L):
    """Placement of body ``bb``'s track frame seen from body ``a``'s (small angles), ``L`` (m)
    apart along the line, from the line values ``bl`` of both bodies.

    Returns (Δy (m), Δψ, Δφ (rad)), their rates along the line (d/ds: 1, 1/m, 1/m) and
    cos φ_a, sin φ_a of body ``a``'s roll.
    """
    ha, hb = bl[a, BL_HEADING], bl[bb, BL_HEADING]
    ra, rb = bl[a, BL_ROLL], bl[bb, BL_ROLL]
    ka, kb = bl[a, BL_KAPPA], bl[bb, BL_KAPPA]
    dyh = (bl[bb, BL_HINT] - bl[a, BL_HINT]) - ha * L
    dh = hb - ha
    dphi = rb - ra
    ddyh = dh - ka * L
    ddh = kb - ka
    ddphi = bl[bb, BL_DROLL] - bl[a, BL_DROLL]
    return dyh, dh, dphi, ddyh, ddh, ddphi, math.cos(ra), math.sin(ra)


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _element_coefficients(el_k, el_c, e, r0):
    """Stiffnesses and dampings of element ``e`` on rows ``r0 … r0 + 2`` (translation: N/m,
    N·s/m; rotation: N·m/rad, N·m·s/rad) as (k0, k1, k2, c0, c1, c2).
    """
    return (el_k[e, r0], el_k[e, r0 + 1], el_k[e, r0 + 2],
            el_c[e, r0], el_c[e, r0 + 1], el_c[e, r0 + 2])


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _any_nonzero(kc):
    """True if any of the six coefficients of :func:`_element_coefficients` is nonzero."""
    k0, k1, k2, c0, c1, c2 = kc
    return k0 != 0.0 or k1 != 0.0 or k2 != 0.0 or c0 != 0.0 or c1 != 0.0 or c2 != 0.0


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _translation_spring_forces(ua, ub, pos_b, kc, speed, fo):
    """Forces (N) of the translational springs and dampers ``kc`` of a suspension element on
    marker A (the opposite on B), from the marker motions ``ua``, ``ub`` = (u0, u1, u2, v0, v1,
    v2) (m, m/s) taken against the relative placement ``fo`` of the bodies' track frames
    (:func:`_element_frame_offsets`); ``pos_b``: marker B from B's track-frame origin (m),
    ``speed`` in m/s.
    """
    ua0, ua1, ua2, va0, va1, va2 = ua
    ub0, ub1, ub2, vb0, vb1, vb2 = ub
    xb, yb, zb = pos_b
    k0, k1, k2, c0, c1, c2 = kc
    dyh, dh, dphi, ddyh, ddh, ddphi, cra, sra = fo
    d0 = ua0 - ub0 + dh * yb
    d1 = ua1 - ub1 - (cra * dyh + dh * xb - dphi * zb)
    d2 = ua2 - ub2 - (-sra * dyh + dphi * yb)
    w0 = va0 - vb0 - speed * (-ddh * yb)
    w1 = va1 - vb1 - speed * (cra * ddyh + ddh * xb - ddphi * zb)
    w2 = va2 - vb2 - speed * (-sra * ddyh + ddphi * yb)
    return -k0 * d0 - c0 * w0, -k1 * d1 - c1 * w1, -k2 * d2 - c2 * w2


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _rotation_spring_forces(ua, ub, kc, speed, fo):
    """Moments (N·m) of the rotational springs and dampers ``kc`` of a suspension element on
    marker A (the opposite on B), from the marker rotations and rates ``ua``, ``ub`` (rad,
    rad/s) taken against the relative roll and heading in ``fo`` (as
    :func:`_translation_spring_forces`).
    """
    ua0, ua1, ua2, va0, va1, va2 = ua
    ub0, ub1, ub2, vb0, vb1, vb2 = ub
    k3, k4, k5, c3, c4, c5 = kc
    _, dh, dphi, _, ddh, ddphi, _, _ = fo
    return (-k3 * (ua0 - ub0 - dphi) - c3 * (va0 - vb0 - speed * ddphi),
            -k4 * (ua1 - ub1) - c4 * (va1 - vb1),
            -k5 * (ua2 - ub2 - dh) - c5 * (va2 - vb2 - speed * ddh))


def vehicle_forces(sys, X, V, s, F):
    """Inertial (track frame), gravity, elastic and suspension forces on the vehicle bodies.

    The line geometry is looked up once per body (not per element) into ``sys.body_line``;
    each element's translation and rotation rows are evaluated in one fused pass over the
    coordinates of each of its two bodies (the cost of a flexible body grows with its number of
    modes times the number of its attachment markers, DESIGN §3.5). Each element's
    translational spring–damper force on marker A (N, in A's track frame; the opposite acts on
    B) is also written to ``sys.el_force[e]``, where the kernel averages it for the recorded
    suspension channels.
    """
    par = sys.par
    speed = par.speed
    phi = sys.phi
    bl = sys.body_line
    # bodies: gravity + frame acceleration on rigid coordinates, elastic restoring forces, and
    # the line values at each body (heading, lateral offset, roll, curvature, d(roll)/ds)
    for b in range(par.n_bodies):
        o = sys.body_off[b]
        nd = sys.body_ndof[b]
        sb = s + sys.body_x[b]
        f_y, f_z, kap, roll, dk = _frame_specific_force(sys, sb)
        heading, hint, droll = _line_values(sys.line, par.ln_s0, par.ln_ds, sb)
        _store_body_line(bl, b, heading, hint, roll, kap, droll)
        m = sys.body_mass[b]
        F[o + 1] -= m * f_y
        F[o + 2] -= m * f_z
        F[o + 5] -= sys.body_inertia[b, 2] * speed * speed * dk
        if nd > 6:
            _add_elastic_forces(F, X, V, sys.kdiag, sys.cdiag, o, nd)
        if sys.body_ws[b] == 1:
            # spin gyroscopics: I_y Ω (ψ̇ + Vκ) in roll, −I_y Ω φ̇ in yaw
            h = sys.body_inertia[b, 1] * speed / par.r0
            F[o + 3] += h * (V[o + 5] + speed * kap)
            F[o + 5] -= h * V[o + 3]
    # speed control: a soft longitudinal link of the car body to the moving frame stands for the
    # traction that keeps the running speed against rolling resistance (no drift)
    F[sys.body_off[0]] -= (
        par.k_traction * X[sys.body_off[0]] + par.c_traction * V[sys.body_off[0]]
    )
    # suspension elements: translation rows 0–2, rotation rows 3–5 (the branches here, not in
    # the helpers: see the module docstring); the translational force on A is kept in
    # ``el_force`` for the recorded channels (stored here, not through a helper: an array
    # passed to a helper inside a branch costs a reference count, see the module docstring)
    ef = sys.el_force
    for e in range(par.n_elem):
        a = sys.el_a[e]
        bb = sys.el_b[e]
        oa, na, pa = sys.body_off[a], sys.body_ndof[a], sys.el_phia[e]
        ob, nbd, pb = sys.body_off[bb], sys.body_ndof[bb], sys.el_phib[e]
        fo = _element_frame_offsets(bl, a, bb, sys.body_x[bb] - sys.body_x[a])
        pos_b = (sys.el_pb[e, 0], sys.el_pb[e, 1], sys.el_pb[e, 2])
        kc = _element_coefficients(sys.el_k, sys.el_c, e, 0)
        if _any_nonzero(kc):
            ua = _marker_kinematics3(phi, pa, na, X, V, oa)
            ub = _marker_kinematics3(phi, pb, nbd, X, V, ob)
            f0, f1, f2 = _translation_spring_forces(ua, ub, pos_b, kc, speed, fo)
            _marker_force3(phi, pa, na, F, oa, f0, f1, f2)
            _marker_force3(phi, pb, nbd, F, ob, -f0, -f1, -f2)
            ef[e, 0] = f0
            ef[e, 1] = f1
            ef[e, 2] = f2
        else:
            ef[e, 0] = 0.0
            ef[e, 1] = 0.0
            ef[e, 2] = 0.0
        kc = _element_coefficients(sys.el_k, sys.el_c, e, 3)
        if _any_nonzero(kc):
            ua = _marker_kinematics3(phi, pa + 3 * na, na, X, V, oa)
            ub = _marker_kinematics3(phi, pb + 3 * nbd, nbd, X, V, ob)
            f0, f1, f2 = _rotation_spring_forces(ua, ub, kc, speed, fo)
            _marker_force3(phi, pa + 3 * na, na, F, oa, f0, f1, f2)
            _marker_force3(phi, pb + 3 * nbd, nbd, F, ob, -f0, -f1, -f2)


_vehicle_forces = numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)(
    _twin("_vehicle_forces", vehicle_forces))
vehicle_forces = numba.njit(cache=True, fastmath=_FM)(vehicle_forces)


def rail_forces(sys, X, V, F):
    """Beam and fastener forces of both rails, per mode (diagonal thanks to discrete
    orthogonality of sine modes at evenly spaced fasteners).
    """
    par = sys.par
    nm = par.n_rail_modes
    nv = par.n_veh
    czd = par.cz_d
    kyd, cyd = par.ky_d, par.cy_d
    krd, crd = par.kr_d, par.cr_d
    hf = par.h_foot
    for rail in range(2):
        oz = nv + (3 * rail) * nm
        oy = oz + nm
        ot = oy + nm
        for k in range(nm):
            F[oz + k] -= sys.rail_kz[k] * X[oz + k] + czd * V[oz + k]
            qy, qt = X[oy + k], X[ot + k]
            vy, vt = V[oy + k], V[ot + k]
            ffoot = -kyd * (qy + hf * qt) - cyd * (vy + hf * vt)
            F[oy + k] += -sys.rail_kyb[k] * qy + ffoot
            F[ot + k] += -(sys.rail_ktb[k] + krd) * qt - crd * vt + hf * ffoot


_rail_forces = numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)(
    _twin("_rail_forces", rail_forces))
rail_forces = numba.njit(cache=True, fastmath=_FM)(rail_forces)


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _mode_sines_at(sn, rail_kap, par, xw):
    """Shapes sin(k·π·x/L), k = 1 … n_modes, of the rail modes at window position ``xw`` (m)
    into ``sn`` (Chebyshev recurrence); zero outside the window (never in a run, only in tests:
    a wheel there rolls on rigid rail).
    """
    nm = par.n_rail_modes
    if xw <= 0.0 or xw >= par.win_len:
        for k in range(nm):
            sn[k] = 0.0
    else:
        th = rail_kap[0] * xw
        c2 = 2.0 * math.cos(th)
        s_prev = 0.0
        s_cur = math.sin(th)
        for k in range(nm):
            sn[k] = s_cur
            s_next = c2 * s_cur - s_prev
            s_prev = s_cur
            s_cur = s_next


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _rail_at_conical(sn, X, V, oz, oy, ot, nm):
    """Rail displacements (z, y in m, θ in rad) and velocities (m/s, m/s, rad/s) at a wheel
    as :func:`_rail_at`, without the vertical velocity (returned as 0), which the conical
    model does not use.
    """
    zr = _dot(sn, X[oz:oz + nm])
    yr = _dot(sn, X[oy:oy + nm])
    tr = _dot(sn, X[ot:ot + nm])
    vyr = _dot(sn, V[oy:oy + nm])
    vtr = _dot(sn, V[ot:ot + nm])
    return zr, yr, tr, 0.0, vyr, vtr


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _reset_creep_state(cst, w, side, c0):
    """Zero the creep-force state (Fx, Fy, Mz) at ``cst[w, side, c0:c0 + 3]`` (no contact)."""
    cst[w, side, c0] = 0.0
    cst[w, side, c0 + 1] = 0.0
    cst[w, side, c0 + 2] = 0.0


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _relax_creep_state(cst, w, side, c0, fx, fy, mz, relax_dt, tau):
    """Creep forces (N, N, N·m) relaxed from the state ``cst[w, side, c0:c0 + 3]`` toward the
    steady values (fx, fy, mz) with time constant ``tau`` (s) over ``relax_dt`` (s; 0 keeps the
    steady values), stored back as the new state and returned.
    """
    if relax_dt > 0.0:
        e = math.exp(-relax_dt / tau)
        fx = fx + (cst[w, side, c0] - fx) * e
        fy = fy + (cst[w, side, c0 + 1] - fy) * e
        mz = mz + (cst[w, side, c0 + 2] - mz) * e
    cst[w, side, c0] = fx
    cst[w, side, c0 + 1] = fy
    cst[w, side, c0 + 2] = mz
    return fx, fy, mz


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _contact_force_track_frame(fy, N, cg, sgm, sg):
    """Lateral and vertical force (N) on the wheel in the track frame from the lateral creep
    force ``fy`` and the normal load ``N`` (N) at a contact angle with cosine ``cg`` and sine
    ``sgm`` in the track frame (normal n, lateral tangent t).
    """
    return fy * cg - sg * N * sgm, sg * fy * sgm + N * cg


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _add_wheelset_load(F, o, fw):
    """Add the force (N) and moment (N·m) about the wheelset centre of a wheel's contact result
    ``fw`` (:func:`_conical_wheel`, :func:`_profile_wheel`) to its coordinates at offset ``o``.
    """
    fx, fy, fz, mx, my, mz = fw[0], fw[1], fw[2], fw[3], fw[4], fw[5]
    F[o + 0] += fx
    F[o + 1] += fy
    F[o + 2] += fz
    F[o + 3] += mx
    F[o + 4] += my
    F[o + 5] += mz


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _add_rail_reaction(F, sn, rail, nm, scale, hh, fw):
    """Project the reaction of a wheel's force (lateral and vertical in N, from its contact
    result ``fw``) on the rail modes (offsets ``rail`` of the vertical, lateral and torsion
    modes, mode shapes ``sn`` at the wheel, ``scale`` = 2/L in 1/m): loads P, Q at the running
    surface and their torque about the shear centre, ``hh`` (m) below it.
    """
    oz, oy, ot = rail
    fwy, fwz = fw[1], fw[2]
    pr = -fwz
    qr = -fwy
    mr = -hh * qr
    cpz = scale * pr
    cpy = scale * qr
    cpt = scale * mr
    _axpy(cpz, sn, F[oz:oz + nm])
    _axpy(cpy, sn, F[oy:oy + nm])
    _axpy(cpt, sn, F[ot:ot + nm])


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _store_wheel_aux(aux, w, side, z_rail, y_rail, fw):
    """Per-wheel outputs into ``aux[w, side]``: from the contact result ``fw`` the wheel forces
    (N), normal load and its flange part (N), compression (m) and contact angle (rad); the rail
    head position ``z_rail``, ``y_rail`` (m).
    """
    fwx, fwy, fwz, _, _, _, n_sum, delta, n_fl, angle = fw
    aux[w, side, AUX_FZ] = fwz
    aux[w, side, AUX_FY] = fwy
    aux[w, side, AUX_FX] = fwx
    aux[w, side, AUX_N] = n_sum
    aux[w, side, AUX_RAIL_Z] = z_rail
    aux[w, side, AUX_RAIL_Y] = y_rail
    aux[w, side, AUX_DELTA] = delta
    aux[w, side, AUX_N_FLANGE] = n_fl
    aux[w, side, AUX_ANGLE] = angle


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _conical_creep_forces(ct, par, side, sg, dyrel, r_c, gam, N, vy_head, psw, wv):
    """Steady creep forces (Fx, Fy in N, Mz in N·m) of one wheel on the conical tread table at
    relative displacement ``dyrel`` (m), rolling radius ``r_c`` (m), contact angle ``gam``
    (rad) and normal load ``N`` (N > 0), from the linearised creepages referred to
    max(V, v_min); and the relaxation time constant τ = a/V (s). ``psw``: wheelset yaw (rad);
    ``wv``: wheelset velocities (ẋ, ẏ, φ̇, β̇, ψ̇) in m/s and rad/s.
    """
    y0, dy = par.ct_y0, par.ct_dy
    speed = par.speed
    vref = max(speed, par.v_min)
    b0, r0 = par.b0, par.r0
    vxw, vyw, vrw, vbw, vpsw = wv
    xi_x = (speed * (1.0 - r_c / r0) + vxw - sg * b0 * vpsw - r_c * vbw) / vref
    xi_y = (vyw + r_c * vrw - vy_head) / vref - psw
    xi_sp = vpsw / vref - sg * math.sin(gam) / r0
    fx, fy, mz = creep_forces(
        xi_x,
        xi_y,
        xi_sp,
        N,
        table_value(ct[side, CT_CA], y0, dy, dyrel),
        table_value(ct[side, CT_CB], y0, dy, dyrel),
        table_value(ct[side, CT_C11], y0, dy, dyrel),
        table_value(ct[side, CT_C22], y0, dy, dyrel),
        table_value(ct[side, CT_C23], y0, dy, dyrel),
        table_value(ct[side, CT_C33], y0, dy, dyrel),
        par.g_shear,
        par.mu,
    )
    tau = table_value(ct[side, CT_CA], y0, dy, dyrel) * N ** (1.0 / 3.0) / vref
    return fx, fy, mz, tau


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _with_flange_spring(fwy, side, dyrel, clear, kfl):
    """Lateral wheel force ``fwy`` (N) plus the conical model's flange: a stiff lateral spring
    ``kfl`` (N/m) beyond the clearance ``clear`` (m), on the flange side only.
    """
    if side == 0 and dyrel > clear:
        fwy -= kfl * (dyrel - clear)
    elif side == 1 and dyrel < -clear:
        fwy -= kfl * (dyrel + clear)
    return fwy


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _relaxed(state, fx, fy, mz, relax_dt, tau):
    """Creep forces (N, N, N·m) relaxed from the previous ``state`` toward the steady values
    (fx, fy, mz) with time constant ``tau`` (s) over ``relax_dt`` (s; 0 keeps them steady);
    :func:`_relax_creep_state` with the state passed as values.
    """
    if relax_dt > 0.0:
        e = math.exp(-relax_dt / tau)
        fx = fx + (state[0] - fx) * e
        fy = fy + (state[1] - fy) * e
        mz = mz + (state[2] - mz) * e
    return fx, fy, mz


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _conical_wheel(ct, par, relax_dt, side, sg, wx, wv, state, z_rail, z_irr, vy_head, dyrel):
    """One-point contact of one wheel on the conical tread table ``ct`` (``contact_model`` 0).

    Table values at the relative displacement ``dyrel`` (m); compression
    δ = z_rail + z_irr − (z_w + sg·b0·φ) + dz (m), Hertz load N = (δ/G)^(3/2) (N); creep forces
    relaxed from the previous ``state`` (Fx, Fy, Mz), turned by γ + sg·φ into the track frame,
    plus the flange spring; moments about the wheelset centre from the contact point
    (0, sg·b0 + y_c, −r). ``wx``: wheelset (z (m), roll φ, yaw ψ (rad)); ``wv``: its
    velocities (ẋ, ẏ, φ̇, β̇, ψ̇).

    Returns the force (N) and moment (N·m) on the wheelset in the track frame, the normal load
    (N), δ (m), the flange's share of the load (0 here) and the contact angle (rad); and the
    new creep state (zero without contact).
    """
    y0, dy = par.ct_y0, par.ct_dy
    b0 = par.b0
    zw, rw, psw = wx
    r_c = table_value(ct[side, CT_R], y0, dy, dyrel)
    gam = table_value(ct[side, CT_GAMMA], y0, dy, dyrel)
    dzc = table_value(ct[side, CT_DZ], y0, dy, dyrel)
    yc = table_value(ct[side, CT_YC], y0, dy, dyrel)
    delta = (z_rail + z_irr) - (zw + sg * b0 * rw) + dzc
    N = hertz_force(delta, par.hertz_g)
    fx = 0.0
    fy = 0.0
    mz = 0.0
    if N > 0.0:
        fx, fy, mz, tau = _conical_creep_forces(ct, par, side, sg, dyrel, r_c, gam, N, vy_head,
                                                psw, wv)
        fx, fy, mz = _relaxed(state, fx, fy, mz, relax_dt, tau)
    ge = gam + sg * rw
    cg, sgm = math.cos(ge), math.sin(ge)
    fwy, fwz = _contact_force_track_frame(fy, N, cg, sgm, sg)
    fwx = fx
    fwy = _with_flange_spring(fwy, side, dyrel, par.flange_clearance, par.flange_k)
    # moments about the wheelset centre: contact point (0, ±b0 + yc, −r)
    ry = sg * b0 + yc
    rz = -r_c
    mx = ry * fwz - rz * fwy
    my = rz * fwx - sg * sgm * mz
    mzz = -ry * fwx + mz * cg
    return (fwx, fwy, fwz, mx, my, mzz, N, delta, 0.0, ge if N > 0.0 else 0.0), (fx, fy, mz)


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _table_cell(n, y0, dy, y):
    """Grid index i and fraction f ∈ [0, 1] of ``y`` (m) in a uniform table of ``n`` points
    from ``y0`` with step ``dy`` (m), clamped to the first and last interval.
    """
    u = (y - y0) / dy
    if u <= 0.0:
        i = 0
        f = 0.0
    elif u >= n - 1:
        i = n - 2
        f = 1.0
    else:
        i = int(u)
        f = u - i
    return i, f


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _slot_normal_load(ct2, side, slot, i, f, dlz, rw, sg):
    """Contact angle of a slot in the wheelset frame γ and in the track frame γ_e = γ + sg·φ
    (rad), cos γ_e, sin γ_e, the normal approach δ_n = δ_z·cos γ_e (m) from the vertical
    compression ``dlz`` (m), and the Hertz normal load N = (δ_n/G)^(3/2) (N; 0 for δ_n ≤ 0).
    """
    gam = _lerp_at(ct2, side, slot, CT_GAMMA, i, f)
    ge = gam + sg * rw
    cg = math.cos(ge)
    sgm = math.sin(ge)
    dn = dlz * cg
    N = 0.0
    if dn > 0.0:
        N = (dn / _lerp_at(ct2, side, slot, PT_GH, i, f)) ** 1.5
    return gam, ge, cg, sgm, dn, N


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _slot_creepages(par, sg, gam, cg, sgm, r_c, ry, vy_head, vzr, psw, wv):
    """Longitudinal and lateral creepage (-) and spin (1/m) of one slot: the slip velocity of
    the wheel's material point at (0, ``ry``, −``r_c``) (m) against the rail's (lateral
    ``vy_head``, vertical ``vzr`` in m/s), projected on the contact frame (rolling direction,
    lateral tangent of angle γ_e), referred to max(V, v_min); spin ψ̇·cos γ_e/V − sg·sin γ/r0.
    ``psw``: wheelset yaw (rad); ``wv``: its velocities (ẋ, ẏ, ż, φ̇, β̇, ψ̇).
    """
    speed = par.speed
    vref = max(speed, par.v_min)
    r0 = par.r0
    vxw, vyw, vzw, vrw, vbw, vpsw = wv
    sx = speed * (1.0 - r_c / r0) + vxw - ry * vpsw - r_c * vbw
    sy = vyw + r_c * vrw - vy_head - speed * psw
    sz = vzw + ry * vrw - vzr
    xi_x = sx / vref
    xi_y = (sy * cg + sg * sgm * sz) / vref
    xi_sp = vpsw * cg / vref - sg * math.sin(gam) / r0
    return xi_x, xi_y, xi_sp


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _slot_creep_forces(ct2, par, cst, relax_dt, w, side, sg, slot, i, f, N, gam, cg, sgm, r_c,
                       ry, vy_head, vzr, psw, wv):
    """Creep forces (Fx, Fy in N, Mz in N·m) of one slot under normal load ``N`` (N): Kalker's
    linear law saturated by Shen–Hedrick–Elkins with the slot's coefficients, relaxed over
    ``relax_dt`` (s) with τ = a/V (creep state ``cst[w, side, 3·slot:3·slot + 3]``).
    """
    vref = max(par.speed, par.v_min)
    xi_x, xi_y, xi_sp = _slot_creepages(par, sg, gam, cg, sgm, r_c, ry, vy_head, vzr, psw, wv)
    ca = _lerp_at(ct2, side, slot, CT_CA, i, f)
    fx, fy, mz = creep_forces(
        xi_x, xi_y, xi_sp, N, ca,
        _lerp_at(ct2, side, slot, CT_CB, i, f),
        _lerp_at(ct2, side, slot, CT_C11, i, f),
        _lerp_at(ct2, side, slot, CT_C22, i, f),
        _lerp_at(ct2, side, slot, CT_C23, i, f),
        _lerp_at(ct2, side, slot, CT_C33, i, f),
        par.g_shear, par.mu,
    )
    tau = ca * N ** (1.0 / 3.0) / vref
    return _relax_creep_state(cst, w, side, 3 * slot, fx, fy, mz, relax_dt, tau)


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _profile_wheel(ct2, par, X, V, cst, relax_dt, w, side, o, z_rail, z_irr, vy_head, vzr,
                   dyrel):
    """Two-slot contact of one wheel on real profiles (table ``ct2``, ``contact_model`` 1).

    Both slots of the table (tread and flange branch) are evaluated at the wheelset's lateral
    displacement ``dyrel`` (m) relative to the rail head, each with its own contact angle,
    rolling radius, contact position, Hertz constant and creep coefficients: vertical
    compression δ_z = z_top − (z_w + sg·b0·φ) + dz (m), normal load from the normal approach
    (:func:`_slot_normal_load`; a slot with δ_n ≤ 0 carries nothing and its creep state is
    reset), creep forces (:func:`_slot_creep_forces`). The forces of both slots are summed.

    Returns the force (N) and moment (N·m) on the wheelset in the track frame, the normal load
    (N), the largest δ_z (m), the flange slot's load (N) and the contact angle of the more
    loaded slot (rad).
    """
    sg = 1.0 if side == 0 else -1.0
    zw, rw, psw = X[o + 2], X[o + 3], X[o + 5]
    wv = (V[o + 0], V[o + 1], V[o + 2], V[o + 3], V[o + 4], V[o + 5])
    i, f = _table_cell(ct2.shape[3], par.ct2_y0, par.ct2_dy, dyrel)
    z_rel = (z_rail + z_irr) - (zw + sg * par.b0 * rw)
    fwx = fwy = fwz = mx = my = mzz = 0.0
    n_sum = n_max = n_fl = angle = 0.0
    d_max = -1.0
    for slot in range(2):
        dlz = z_rel + _lerp_at(ct2, side, slot, CT_DZ, i, f)
        if dlz > d_max:
            d_max = dlz
        if not dlz > 0.0:
            _reset_creep_state(cst, w, side, 3 * slot)
            continue
        gam, ge, cg, sgm, dn, N = _slot_normal_load(ct2, side, slot, i, f, dlz, rw, sg)
        if not dn > 0.0:
            _reset_creep_state(cst, w, side, 3 * slot)
            continue
        r_c = _lerp_at(ct2, side, slot, CT_R, i, f)
        ry = sg * par.b0 + _lerp_at(ct2, side, slot, CT_YC, i, f)
        fx, fy, mz = _slot_creep_forces(ct2, par, cst, relax_dt, w, side, sg, slot, i, f, N,
                                        gam, cg, sgm, r_c, ry, vy_head, vzr, psw, wv)
        qy, qz = _contact_force_track_frame(fy, N, cg, sgm, sg)
        fwx += fx
        fwy += qy
        fwz += qz
        # moments about the wheelset centre: contact point (0, ry, −r_c)
        mx += ry * qz + r_c * qy
        my += -r_c * fx - sg * sgm * mz
        mzz += -ry * fx + mz * cg
        n_sum += N
        if slot == 1:
            n_fl = N
        if N > n_max:
            n_max = N
            angle = ge
    return fwx, fwy, fwz, mx, my, mzz, n_sum, d_max, n_fl, angle


def contact_forces(sys, X, V, s, s_win0, F, aux, sn, cst, relax_dt):
    """Wheel–rail forces of every wheel, on the wheelsets and projected on the rail modes.

    ``sn`` is scratch of length n_modes; ``aux[w, side, :]`` receives per-wheel values.
    ``cst[w, side, 0:3]`` holds the creep forces (Fx, Fy, Mz). With ``relax_dt`` > 0 they relax
    toward the steady Kalker/SHE values over the relaxation length a (contact semi-axis in the
    rolling direction), time constant τ = a/V, integrated exactly over ``relax_dt`` (transient
    rolling contact); with ``relax_dt`` = 0 the steady values are used (statics, Jacobians).
    """
    par = sys.par
    nm = par.n_rail_modes
    nv = par.n_veh
    hh = par.h_head
    scale = 2.0 / par.win_len
    irr = sys.irr
    is0, ids = par.irr_s0, par.irr_ds
    two_slot = par.contact_model == 1
    if two_slot and cst.shape[2] < 6:
        raise ValueError("the creep state of two-slot contact needs 6 values per wheel")
    for w in range(par.n_ws):
        b = sys.ws_body[w]
        o = sys.body_off[b]
        sw = s + sys.body_x[b]
        _mode_sines_at(sn, sys.rail_kap, par, sw - s_win0)
        # the wheelset's state for the conical model, read here (see the module docstring)
        yw, zw, rw, psw = X[o + 1], X[o + 2], X[o + 3], X[o + 5]
        vxw, vyw, vrw, vbw, vpsw = V[o + 0], V[o + 1], V[o + 3], V[o + 4], V[o + 5]
        for side in range(2):
            sg = 1.0 if side == 0 else -1.0
            oz = nv + (3 * side) * nm
            oy = oz + nm
            ot = oy + nm
            if two_slot:
                zr, yr, tr, vzr, vyr, vtr = _rail_at(sn, X, V, oz, oy, ot, nm)
            else:
                zr, yr, tr, vzr, vyr, vtr = _rail_at_conical(sn, X, V, oz, oy, ot, nm)
            z_irr = _lerp_or_zero(irr[side], is0, ids, sw)
            y_irr = _lerp_or_zero(irr[2 + side], is0, ids, sw)
            y_head = yr - hh * tr + y_irr
            vy_head = vyr - hh * vtr
            dyrel = yw - y_head
            # the wheelset load is added in each branch, where it is computed, the creep state
            # stored after it (see the module docstring)
            if two_slot:
                fw = _profile_wheel(sys.ct2, par, X, V, cst, relax_dt, w, side, o, zr, z_irr,
                                    vy_head, vzr, dyrel)
                _add_wheelset_load(F, o, fw)
            else:
                state = (cst[w, side, 0], cst[w, side, 1], cst[w, side, 2])
                fw, state = _conical_wheel(sys.ct, par, relax_dt, side, sg, (zw, rw, psw),
                                           (vxw, vyw, vrw, vbw, vpsw), state, zr, z_irr,
                                           vy_head, dyrel)
                _add_wheelset_load(F, o, fw)
                cst[w, side, 0], cst[w, side, 1], cst[w, side, 2] = state
            _add_rail_reaction(F, sn, (oz, oy, ot), nm, scale, hh, fw)
            _store_wheel_aux(aux, w, side, zr, yr - hh * tr, fw)


_contact_forces = numba.njit(cache=True, fastmath=_FM, **_CALLED_FROM_KERNELS)(
    _twin("_contact_forces", contact_forces))
contact_forces = numba.njit(cache=True, fastmath=_FM)(contact_forces)


@numba.njit(cache=True, fastmath=_FM)
def evaluate(sys, X, V, s, s_win0, F, A, aux, sn, cst, relax_dt):
    """Generalised forces ``F`` and accelerations ``A = F / m`` at coordinates ``X``,
    velocities ``V``, vehicle-centre position ``s`` (m) and rail-window start ``s_win0`` (m).

    ``cst``/``relax_dt``: creep-force state and relaxation step, see :func:`contact_forces`.
    """
    n = F.shape[0]
    for i in range(n):
        F[i] = 0.0
    _vehicle_forces(sys, X, V, s, F)
    _rail_forces(sys, X, V, F)
    _contact_forces(sys, X, V, s, s_win0, F, aux, sn, cst, relax_dt)
    minv = sys.minv
    for i in range(n):
        A[i] = F[i] * minv[i]


def route_inputs(sys, s: float) -> np.ndarray:
    """The route-table values :func:`evaluate` can read with the vehicle centre at ``s`` (m),
    whatever the coordinates and velocities: the inputs of every lookup of
    :func:`vehicle_forces` (line table at each body, also half a table step either side) and
    :func:`contact_forces` (irregularities at each wheelset).

    Keep in step with those two functions: a setup cached by content
    (:mod:`flexride.solver.setup_cache`) hashes this instead of the whole route, and its tests
    check that changing the tables elsewhere changes neither this nor the setup.

    Parameters
    ----------
    sys : SystemArrays
        The assembled system.
    s : float
        Position of the vehicle centre on the line (m).

    Returns
    -------
    numpy.ndarray
        Flat float64 array, seven values per lookup (see :func:`_lookup_inputs`).
    """
    par = sys.par
    out: list[np.ndarray] = []
    lds = par.ln_ds
    for b in range(par.n_bodies):
        sb = s + float(sys.body_x[b])
        for pos in (sb, sb + 0.5 * lds, sb - 0.5 * lds):
            out.extend(_lookup_inputs(row, par.ln_s0, lds, pos, True) for row in sys.line)
    for w in range(par.n_ws):
        sw = s + float(sys.body_x[sys.ws_body[w]])
        out.extend(_lookup_inputs(row, par.irr_s0, par.irr_ds, sw, False) for row in sys.irr)
    return np.concatenate(out) if out else np.zeros(0)


def _lookup_inputs(row: np.ndarray, y0: float, dy: float, y: float, clamped: bool
                   ) -> np.ndarray:
    """What an interpolation of ``row`` (grid origin ``y0``, step ``dy``) at ``y`` returns a
    function of: the values at the grid points i − 1 … i + 2 around ``y`` (clamped indices);
    and ``y0``, ``dy`` and the row's length unless the result does not depend on where ``y``
    falls — the values are equal and either the lookup is ``clamped`` at the ends
    (:func:`table_value`), the value is zero, or ``y`` lies two steps or more inside the grid
    (:func:`_lerp_or_zero`, zero outside the grid); all zeros for such a lookup two steps or
    more outside the grid.
    """
    n = row.shape[0]
    u = (y - y0) / dy
    i = int(np.clip(np.floor(u), 0, max(n - 1, 0)))
    vals = row[np.clip(np.arange(i - 1, i + 3), 0, n - 1)] + 0.0  # −0.0 as 0.0
    if not clamped and (u < -2.0 or u > n + 1.0):  # well outside: zero, whatever the values
        return np.zeros(7)
    constant = bool(np.all(vals == vals[0]))
    if constant and (clamped or vals[0] == 0.0 or 2.0 <= u <= n - 3.0):
        return np.append(vals, (0.0, 0.0, 0.0))
    return np.append(vals, (y0, dy, float(n)))

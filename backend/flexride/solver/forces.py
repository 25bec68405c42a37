"""Generalised forces of the coupled vehicle–track system (numba, no allocation).

``evaluate`` fills the generalised force vector for given coordinates and velocities; the
kernel divides by the diagonal mass. It is split into the three parts the benchmark times
separately: vehicle (inertial, gravity, elastic and suspension forces), rail (fastener and beam
forces) and contact (wheel–rail normal, creep and flange forces with their projection on the
rail modes).
"""

from __future__ import annotations

import math

import numba

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


@numba.njit(cache=True, fastmath=_FM)
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


@numba.njit(cache=True, fastmath=_FM)
def _marker_kinematics3(phi, p, nd, r0, X, V, o):
    """Rows ``r0 … r0+2`` of a marker matrix (offset ``p`` in ``phi``, ``nd`` columns) applied to
    the body's coordinates and velocities (offset ``o``) in one pass: (u0, u1, u2, v0, v1, v2).
    """
    b0 = p + r0 * nd
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


@numba.njit(cache=True, fastmath=_FM)
def _marker_force3(phi, p, nd, r0, F, o, f0, f1, f2):
    """Add the generalised force of marker forces (f0, f1, f2) on rows ``r0 … r0+2``:
    F[o:o+nd] += Φ[r0:r0+3]ᵀ f, in one pass.
    """
    b0 = p + r0 * nd
    row0 = phi[b0:b0 + nd]
    row1 = phi[b0 + nd:b0 + 2 * nd]
    row2 = phi[b0 + 2 * nd:b0 + 3 * nd]
    f = F[o:o + nd]
    for j in range(nd):
        f[j] += f0 * row0[j] + f1 * row1[j] + f2 * row2[j]


@numba.njit(cache=True, fastmath=_FM)
def vehicle_forces(sys, X, V, s, F):
    """Inertial (track frame), gravity, elastic and suspension forces on the vehicle bodies.

    The line geometry is looked up once per body (not per element) into ``sys.body_line``;
    each element's translation and rotation rows are evaluated in one fused pass over the
    coordinates of each of its two bodies (the cost of a flexible body grows with its number of
    modes times the number of its attachment markers, DESIGN §3.5).
    """
    par = sys.par
    nb = par.n_bodies
    speed = par.speed
    phi = sys.phi
    ln = sys.line
    ls0, lds = par.ln_s0, par.ln_ds
    bl = sys.body_line
    # bodies: gravity + frame acceleration on rigid coordinates, elastic restoring forces, and
    # the line values at each body (heading, lateral offset, roll, curvature, d(roll)/ds)
    for b in range(nb):
        o = sys.body_off[b]
        nd = sys.body_ndof[b]
        sb = s + sys.body_x[b]
        f_y, f_z, kap, roll, dk = frame_specific_force(sys, sb)
        bl[b, BL_HEADING] = table_value(ln[LN_HEADING], ls0, lds, sb)
        bl[b, BL_HINT] = table_value(ln[LN_HINT], ls0, lds, sb)
        bl[b, BL_ROLL] = roll
        bl[b, BL_KAPPA] = kap
        bl[b, BL_DROLL] = (
            table_value(ln[LN_ROLL], ls0, lds, sb + 0.5 * lds)
            - table_value(ln[LN_ROLL], ls0, lds, sb - 0.5 * lds)
        ) / lds
        m = sys.body_mass[b]
        F[o + 1] -= m * f_y
        F[o + 2] -= m * f_z
        F[o + 5] -= sys.body_inertia[b, 2] * speed * speed * dk
        if nd > 6:
            fe = F[o + 6:o + nd]
            ke = sys.kdiag[o + 6:o + nd]
            ce = sys.cdiag[o + 6:o + nd]
            xe = X[o + 6:o + nd]
            ve = V[o + 6:o + nd]
            for j in range(nd - 6):
                fe[j] -= ke[j] * xe[j] + ce[j] * ve[j]
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
    # suspension elements
    ne = par.n_elem
    for e in range(ne):
        a = sys.el_a[e]
        bb = sys.el_b[e]
        oa, na = sys.body_off[a], sys.body_ndof[a]
        ob, nbd = sys.body_off[bb], sys.body_ndof[bb]
        pa, pb = sys.el_phia[e], sys.el_phib[e]
        L = sys.body_x[bb] - sys.body_x[a]
        # relative placement of B's track frame seen from A's (small angles)
        ha, hb = bl[a, BL_HEADING], bl[bb, BL_HEADING]
        ra, rb = bl[a, BL_ROLL], bl[bb, BL_ROLL]
        ka, kb = bl[a, BL_KAPPA], bl[bb, BL_KAPPA]
        dyh = (bl[bb, BL_HINT] - bl[a, BL_HINT]) - ha * L
        dh = hb - ha
        dphi = rb - ra
        # rates along the line (d/ds), times speed below
        ddyh = dh - ka * L
        ddh = kb - ka
        ddphi = bl[bb, BL_DROLL] - bl[a, BL_DROLL]
        cra, sra = math.cos(ra), math.sin(ra)
        xb, yb, zb = sys.el_pb[e, 0], sys.el_pb[e, 1], sys.el_pb[e, 2]
        k0, k1, k2 = sys.el_k[e, 0], sys.el_k[e, 1], sys.el_k[e, 2]
        c0, c1, c2 = sys.el_c[e, 0], sys.el_c[e, 1], sys.el_c[e, 2]
        if k0 != 0.0 or k1 != 0.0 or k2 != 0.0 or c0 != 0.0 or c1 != 0.0 or c2 != 0.0:
            ua0, ua1, ua2, va0, va1, va2 = _marker_kinematics3(phi, pa, na, 0, X, V, oa)
            ub0, ub1, ub2, vb0, vb1, vb2 = _marker_kinematics3(phi, pb, nbd, 0, X, V, ob)
            d0 = ua0 - ub0 + dh * yb
            d1 = ua1 - ub1 - (cra * dyh + dh * xb - dphi * zb)
            d2 = ua2 - ub2 - (-sra * dyh + dphi * yb)
            w0 = va0 - vb0 - speed * (-ddh * yb)
            w1 = va1 - vb1 - speed * (cra * ddyh + ddh * xb - ddphi * zb)
            w2 = va2 - vb2 - speed * (-sra * ddyh + ddphi * yb)
            f0 = -k0 * d0 - c0 * w0
            f1 = -k1 * d1 - c1 * w1
            f2 = -k2 * d2 - c2 * w2
            _marker_force3(phi, pa, na, 0, F, oa, f0, f1, f2)
            _marker_force3(phi, pb, nbd, 0, F, ob, -f0, -f1, -f2)
        k3, k4, k5 = sys.el_k[e, 3], sys.el_k[e, 4], sys.el_k[e, 5]
        c3, c4, c5 = sys.el_c[e, 3], sys.el_c[e, 4], sys.el_c[e, 5]
        if k3 != 0.0 or k4 != 0.0 or k5 != 0.0 or c3 != 0.0 or c4 != 0.0 or c5 != 0.0:
            ua0, ua1, ua2, va0, va1, va2 = _marker_kinematics3(phi, pa, na, 3, X, V, oa)
            ub0, ub1, ub2, vb0, vb1, vb2 = _marker_kinematics3(phi, pb, nbd, 3, X, V, ob)
            f0 = -k3 * (ua0 - ub0 - dphi) - c3 * (va0 - vb0 - speed * ddphi)
            f1 = -k4 * (ua1 - ub1) - c4 * (va1 - vb1)
            f2 = -k5 * (ua2 - ub2 - dh) - c5 * (va2 - vb2 - speed * ddh)
            _marker_force3(phi, pa, na, 3, F, oa, f0, f1, f2)
            _marker_force3(phi, pb, nbd, 3, F, ob, -f0, -f1, -f2)


@numba.njit(cache=True, fastmath=_FM)
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


@numba.njit(cache=True, fastmath=_FM)
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
    nw = par.n_ws
    speed = par.speed
    vref = max(speed, par.v_min)
    b0, r0 = par.b0, par.r0
    hh = par.h_head
    G = par.hertz_g
    gsh, mu = par.g_shear, par.mu
    clear, kfl = par.flange_clearance, par.flange_k
    ct = sys.ct
    y0, dy = par.ct_y0, par.ct_dy
    irr = sys.irr
    is0, ids = par.irr_s0, par.irr_ds
    scale = 2.0 / par.win_len
    two_slot = par.contact_model == 1
    if two_slot and cst.shape[2] < 6:
        raise ValueError("the creep state of two-slot contact needs 6 values per wheel")
    for w in range(nw):
        b = sys.ws_body[w]
        o = sys.body_off[b]
        sw = s + sys.body_x[b]
        xw = sw - s_win0
        # sines of all modes at the wheel (Chebyshev recurrence); a wheel outside the window
        # (never in a run, only in tests) rolls on rigid rail
        if xw <= 0.0 or xw >= par.win_len:
            for k in range(nm):
                sn[k] = 0.0
        else:
            th = sys.rail_kap[0] * xw
            c2 = 2.0 * math.cos(th)
            s_prev = 0.0
            s_cur = math.sin(th)
            for k in range(nm):
                sn[k] = s_cur
                s_next = c2 * s_cur - s_prev
                s_prev = s_cur
                s_cur = s_next
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
                zr = _dot(sn, X[oz:oz + nm])
                yr = _dot(sn, X[oy:oy + nm])
                tr = _dot(sn, X[ot:ot + nm])
                vyr = _dot(sn, V[oy:oy + nm])
                vtr = _dot(sn, V[ot:ot + nm])
                vzr = 0.0
            z_irr = _lerp_or_zero(irr[side], is0, ids, sw)
            y_irr = _lerp_or_zero(irr[2 + side], is0, ids, sw)
            y_head = yr - hh * tr + y_irr
            vy_head = vyr - hh * vtr
            dyrel = yw - y_head
            if two_slot:
                _profile_wheel(sys, X, V, F, aux, sn, cst, relax_dt, w, side, o, oz, oy, ot,
                               zr, z_irr, yr - hh * tr, vy_head, vzr, dyrel)
                continue
            r_c = table_value(ct[side, CT_R], y0, dy, dyrel)
            gam = table_value(ct[side, CT_GAMMA], y0, dy, dyrel)
            dzc = table_value(ct[side, CT_DZ], y0, dy, dyrel)
            yc = table_value(ct[side, CT_YC], y0, dy, dyrel)
            delta = (zr + z_irr) - (zw + sg * b0 * rw) + dzc
            N = hertz_force(delta, G)
            fx = 0.0
            fy = 0.0
            mz = 0.0
            tau = 0.0
            if N > 0.0:
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
                    gsh,
                    mu,
                )
                tau = table_value(ct[side, CT_CA], y0, dy, dyrel) * N ** (1.0 / 3.0) / vref
            if relax_dt > 0.0 and N > 0.0:
                e = math.exp(-relax_dt / tau)
                fx = fx + (cst[w, side, 0] - fx) * e
                fy = fy + (cst[w, side, 1] - fy) * e
                mz = mz + (cst[w, side, 2] - mz) * e
            cst[w, side, 0] = fx
            cst[w, side, 1] = fy
            cst[w, side, 2] = mz
            ge = gam + sg * rw
            cg, sgm = math.cos(ge), math.sin(ge)
            # force on the wheel in the track frame (normal n, lateral tangent t)
            fwy = fy * cg - sg * N * sgm
            fwz = sg * fy * sgm + N * cg
            fwx = fx
            # flange: stiff lateral spring beyond the clearance, on the flange side only
            if side == 0 and dyrel > clear:
                fwy -= kfl * (dyrel - clear)
            elif side == 1 and dyrel < -clear:
                fwy -= kfl * (dyrel + clear)
            # moments about the wheelset centre: contact point (0, ±b0 + yc, −r)
            ry = sg * b0 + yc
            rz = -r_c
            mx = ry * fwz - rz * fwy
            my = rz * fwx - sg * sgm * mz
            mzz = -ry * fwx + mz * cg
            F[o + 0] += fwx
            F[o + 1] += fwy
            F[o + 2] += fwz
            F[o + 3] += mx
            F[o + 4] += my
            F[o + 5] += mzz
            # reaction on the rail at the running surface: P, Q, torque about the shear centre
            pr = -fwz
            qr = -fwy
            mr = -hh * qr
            cpz = scale * pr
            cpy = scale * qr
            cpt = scale * mr
            _axpy(cpz, sn, F[oz:oz + nm])
            _axpy(cpy, sn, F[oy:oy + nm])
            _axpy(cpt, sn, F[ot:ot + nm])
            aux[w, side, AUX_FZ] = fwz
            aux[w, side, AUX_FY] = fwy
            aux[w, side, AUX_FX] = fwx
            aux[w, side, AUX_N] = N
            aux[w, side, AUX_RAIL_Z] = zr
            aux[w, side, AUX_RAIL_Y] = yr - hh * tr
            aux[w, side, AUX_DELTA] = delta
            aux[w, side, AUX_N_FLANGE] = 0.0
            aux[w, side, AUX_ANGLE] = ge if N > 0.0 else 0.0


@numba.njit(cache=True, fastmath=_FM, inline="always")
def _profile_wheel(sys, X, V, F, aux, sn, cst, relax_dt, w, side, o, oz, oy, ot, z_rail,
                   z_irr, y_rail, vy_head, vzr, dyrel):
    """Two-slot contact of one wheel on real profiles (``contact_model`` 1).

    Both slots of the table (tread and flange branch) are evaluated at the wheelset's lateral
    displacement ``dyrel`` relative to the rail head, each with its own contact angle (γ + sg·φ
    in the track frame), rolling radius, contact position, Hertz constant and creep
    coefficients: vertical compression δ_z = z_top − (z_w + sg·b0·φ) + dz, normal approach
    δ_n = δ_z·cos(γ + sg·φ), N = (δ_n/G)^(3/2); a slot with δ_n ≤ 0 carries nothing and its
    creep state is reset. Creepages are the slip velocity of the wheel's material point against
    the rail's, projected on the contact frame (rolling direction x, lateral tangent
    t = (0, cos γ_e, sg·sin γ_e), normal), referred to max(V, v_min); spin is the wheel's
    angular velocity along the normal over V. The forces of both slots are summed on the
    wheelset and their resultant loads the rail at the running surface.
    """
    par = sys.par
    nm = par.n_rail_modes
    speed = par.speed
    vref = max(speed, par.v_min)
    b0, r0 = par.b0, par.r0
    hh = par.h_head
    gsh, mu = par.g_shear, par.mu
    ct2 = sys.ct2
    sg = 1.0 if side == 0 else -1.0
    zw, rw, psw = X[o + 2], X[o + 3], X[o + 5]
    vxw, vyw, vzw, vrw, vbw, vpsw = V[o + 0], V[o + 1], V[o + 2], V[o + 3], V[o + 4], V[o + 5]
    n = ct2.shape[3]
    u = (dyrel - par.ct2_y0) / par.ct2_dy
    if u <= 0.0:
        i = 0
        f = 0.0
    elif u >= n - 1:
        i = n - 2
        f = 1.0
    else:
        i = int(u)
        f = u - i
    z_rel = (z_rail + z_irr) - (zw + sg * b0 * rw)
    fwx = 0.0
    fwy = 0.0
    fwz = 0.0
    mx = 0.0
    my = 0.0
    mzz = 0.0
    n_sum = 0.0
    n_max = 0.0
    n_fl = 0.0
    angle = 0.0
    d_max = -1.0
    for slot in range(2):
        dlz = z_rel + _lerp_at(ct2, side, slot, CT_DZ, i, f)
        if dlz > d_max:
            d_max = dlz
        c0 = 3 * slot
        if not dlz > 0.0:
            cst[w, side, c0] = 0.0
            cst[w, side, c0 + 1] = 0.0
            cst[w, side, c0 + 2] = 0.0
            continue
        gam = _lerp_at(ct2, side, slot, CT_GAMMA, i, f)
        ge = gam + sg * rw
        cg = math.cos(ge)
        sgm = math.sin(ge)
        dn = dlz * cg
        if not dn > 0.0:
            cst[w, side, c0] = 0.0
            cst[w, side, c0 + 1] = 0.0
            cst[w, side, c0 + 2] = 0.0
            continue
        N = (dn / _lerp_at(ct2, side, slot, PT_GH, i, f)) ** 1.5
        r_c = _lerp_at(ct2, side, slot, CT_R, i, f)
        ry = sg * b0 + _lerp_at(ct2, side, slot, CT_YC, i, f)
        # slip velocity of the wheel's material point against the rail's (track frame)
        sx = speed * (1.0 - r_c / r0) + vxw - ry * vpsw - r_c * vbw
        sy = vyw + r_c * vrw - vy_head - speed * psw
        sz = vzw + ry * vrw - vzr
        xi_x = sx / vref
        xi_y = (sy * cg + sg * sgm * sz) / vref
        xi_sp = vpsw * cg / vref - sg * math.sin(gam) / r0
        ca = _lerp_at(ct2, side, slot, CT_CA, i, f)
        fx, fy, mz = creep_forces(
            xi_x, xi_y, xi_sp, N, ca,
            _lerp_at(ct2, side, slot, CT_CB, i, f),
            _lerp_at(ct2, side, slot, CT_C11, i, f),
            _lerp_at(ct2, side, slot, CT_C22, i, f),
            _lerp_at(ct2, side, slot, CT_C23, i, f),
            _lerp_at(ct2, side, slot, CT_C33, i, f),
            gsh, mu,
        )
        if relax_dt > 0.0:
            tau = ca * N ** (1.0 / 3.0) / vref
            e = math.exp(-relax_dt / tau)
            fx = fx + (cst[w, side, c0] - fx) * e
            fy = fy + (cst[w, side, c0 + 1] - fy) * e
            mz = mz + (cst[w, side, c0 + 2] - mz) * e
        cst[w, side, c0] = fx
        cst[w, side, c0 + 1] = fy
        cst[w, side, c0 + 2] = mz
        # force on the wheel in the track frame (normal n, lateral tangent t)
        qy = fy * cg - sg * N * sgm
        qz = sg * fy * sgm + N * cg
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
    F[o + 0] += fwx
    F[o + 1] += fwy
    F[o + 2] += fwz
    F[o + 3] += mx
    F[o + 4] += my
    F[o + 5] += mzz
    # reaction on the rail at the running surface: P, Q, torque about the shear centre
    scale = 2.0 / par.win_len
    pr = -fwz
    qr = -fwy
    mr = -hh * qr
    _axpy(scale * pr, sn, F[oz:oz + nm])
    _axpy(scale * qr, sn, F[oy:oy + nm])
    _axpy(scale * mr, sn, F[ot:ot + nm])
    aux[w, side, AUX_FZ] = fwz
    aux[w, side, AUX_FY] = fwy
    aux[w, side, AUX_FX] = fwx
    aux[w, side, AUX_N] = n_sum
    aux[w, side, AUX_RAIL_Z] = z_rail
    aux[w, side, AUX_RAIL_Y] = y_rail
    aux[w, side, AUX_DELTA] = d_max
    aux[w, side, AUX_N_FLANGE] = n_fl
    aux[w, side, AUX_ANGLE] = angle


@numba.njit(cache=True, fastmath=_FM)
def evaluate(sys, X, V, s, s_win0, F, A, aux, sn, cst, relax_dt):
    """Generalised forces ``F`` and accelerations ``A = F / m`` at coordinates ``X``,
    velocities ``V``, vehicle-centre position ``s`` (m) and rail-window start ``s_win0`` (m).

    ``cst``/``relax_dt``: creep-force state and relaxation step, see :func:`contact_forces`.
    """
    n = F.shape[0]
    for i in range(n):
        F[i] = 0.0
    vehicle_forces(sys, X, V, s, F)
    rail_forces(sys, X, V, F)
    contact_forces(sys, X, V, s, s_win0, F, aux, sn, cst, relax_dt)
    minv = sys.minv
    for i in range(n):
        A[i] = F[i] * minv[i]

"""A naive reference twin of the force evaluation (:func:`flexride.solver.forces.evaluate`).

Written from the model (docs/model.md, the element and table definitions), not from the kernel:
plain NumPy, dense matrices, no numba, no discrete-orthogonality shortcut.

* Vehicle: dense M, C, K assembled from the suspension elements (u_A − u_B of the two markers
  through their 6 × n matrices, force −k·d − c·ḋ on A and its reaction on B, virtual work for
  the generalised forces), the elastic modes (ω², 2ζω, mass-normalised), the traction link
  (0.05 Hz, critically damped on the vehicle mass), wheelset spin gyroscopics (H = I_y·V/r0:
  I_x·φ̈ = … + H·ψ̇, I_z·ψ̈ = … − H·φ̇) and gravity on the rigid vertical coordinates.
* Rails: Euler–Bernoulli beams with sine modes sin(kπx/L) on the window, k = 1 … N − 1; mass,
  bending and torsion matrices by Gauss–Legendre quadrature of ∫φφ, ∫φ″φ″, ∫φ′φ′ and the
  fasteners as point springs at the interior grid points (dense sums), the lateral fastener
  force at the foot (h_f below the shear centre: y_foot = y + h_f·θ), wheel forces at the
  running surface (y_head = y − h_h·θ).
* Contact per wheel: the ContactTable (linear interpolation in Δy = y_wheelset − y_head − y_irr),
  Hertz P = (δ/G)^{3/2} with G = 3.86·R^−0.115·10⁻⁸ (worn tread), textbook linearised creepages
  referred to max(V, 0.5 m/s), Kalker's linear law saturated by Shen–Hedrick–Elkins, forces
  turned by γ + side·φ into the track frame, the flange spring beyond the clearance, the spin
  moment about the contact normal, creep relaxation exp(−Δt·V/a).

* Real profiles (``contact.geometry: profiles``), per wheel both slots of the two-slot table
  (tread and flange branch; np.interp of each field): vertical compression
  δ_z = z_rail + z_irr − (z + sg·b0·φ) + dz, normal approach δ_z·cos(γ + sg·φ), N = (δ_n/G)^{3/2}
  with the slot's G; creepages from the slip velocity of the wheel's material point (centre
  velocity + ω × arm, ω = (φ̇, V/r0 + β̇, ψ̇), minus the rail's velocity, −Vψ in the yawed
  wheelset) projected on the slot's contact frame; spin ψ̇·n_z/V − sg·sin γ/r0; each slot's
  forces along its own normal and tangent, moments by cross products, summed.

States are small random perturbations of the paper vehicle on its rails (wheels pressed in by
their share of the weight), on straight track with random irregularity; rigid, and with an
analytic flexible car body (free–free beam bending modes).
"""

from __future__ import annotations

import itertools
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import PROFILES, beam_carbody, preset
from flexride.solver.assemble import assemble
from flexride.solver.forces import evaluate
from flexride.solver.static import initial_window_start
from flexride.solver.system import AUX_ANGLE, AUX_N, AUX_N_FLANGE, N_AUX
from flexride.vehicle.topology import build_vehicle

G_ACC = 9.81  # m/s², the model's gravity
TRACTION_HZ = 0.05  # docs/model.md: soft longitudinal link
V_MIN_CREEP = 0.5  # m/s, creepages referred to max(V, 0.5 m/s)
S_CENTRE = 30.0  # m, vehicle centre: past the 20 m fade-in of the random irregularity


# ----------------------------------------------------------------------------- vehicle


def offsets(bodies) -> list[int]:
    out, o = [], 0
    for b in bodies:
        out.append(o)
        o += b.n_dof
    return out


def vehicle_matrices(scenario, veh):
    """Dense mass, damping (incl. gyroscopic) and stiffness of the vehicle coordinates, and the
    gravity force vector (N, N·m)."""
    bodies = veh.bodies
    off = offsets(bodies)
    n = sum(b.n_dof for b in bodies)
    M = np.zeros((n, n))
    K = np.zeros((n, n))
    C = np.zeros((n, n))
    fg = np.zeros(n)
    for b, o in zip(bodies, off, strict=True):
        M[o, o] = M[o + 1, o + 1] = M[o + 2, o + 2] = b.mass
        for j in range(3):
            M[o + 3 + j, o + 3 + j] = b.inertia[j]
        fg[o + 2] = -b.mass * G_ACC
        for j, (f, zeta) in enumerate(zip(b.elastic_frequencies, b.elastic_damping,
                                          strict=True)):
            w = 2 * math.pi * f
            i = o + 6 + j
            M[i, i] = 1.0  # mass-normalised
            K[i, i] += w * w
            C[i, i] += 2 * zeta * w
    for el in veh.elements:
        # relative motion of marker A against marker B: u_A − u_B = L·x
        L = np.zeros((6, n))
        oa, ob = off[el.body_a], off[el.body_b]
        L[:, oa:oa + bodies[el.body_a].n_dof] += bodies[el.body_a].markers[el.marker_a]
        L[:, ob:ob + bodies[el.body_b].n_dof] -= bodies[el.body_b].markers[el.marker_b]
        K += L.T @ np.diag(el.stiffness) @ L
        C += L.T @ np.diag(el.damping) @ L
    m_total = sum(b.mass for b in bodies)
    w_tr = 2 * math.pi * TRACTION_HZ
    K[0, 0] += m_total * w_tr**2  # car body x (body 0) against the moving frame
    C[0, 0] += 2 * m_total * w_tr
    speed = scenario.speed_mps
    r0 = scenario.vehicle.geometry.wheel_radius
    for bi in veh.wheelsets:
        o = off[bi]
        h = bodies[bi].inertia[1] * speed / r0
        C[o + 3, o + 5] -= h  # roll: + H·ψ̇ as a force, so −H in C (F = −C·v)
        C[o + 5, o + 3] += h  # yaw: − H·φ̇
    return M, C, K, fg


# ----------------------------------------------------------------------------- rails


def rail_matrices(track, n_bays: int):
    """Mass, damping, stiffness of one rail's modes: blocks vertical (nm) and lateral +
    torsion (2·nm, coordinates [q_y, q_θ]); and the window length L (m)."""
    d = track.fastener.spacing
    L = n_bays * d
    nm = n_bays - 1
    kap = np.arange(1, n_bays) * math.pi / L
    # Gauss–Legendre on every bay (exact to rounding for these smooth integrands)
    xg, wg = np.polynomial.legendre.leggauss(24)
    x = (np.arange(n_bays)[:, None] * d + 0.5 * d * (xg[None, :] + 1)).ravel()
    w = np.tile(0.5 * d * wg, n_bays)
    ph = np.sin(np.outer(x, kap))
    d1 = np.cos(np.outer(x, kap)) * kap
    d2 = -ph * kap**2
    S = ph.T @ (w[:, None] * ph)  # ∫ φ_k φ_l dx
    T = d1.T @ (w[:, None] * d1)  # ∫ φ_k′ φ_l′ dx
    B = d2.T @ (w[:, None] * d2)  # ∫ φ_k″ φ_l″ dx
    xf = d * np.arange(1, n_bays)  # fasteners at the interior grid points
    pf = np.sin(np.outer(xf, kap))
    P = pf.T @ pf  # Σ_j φ_k(x_j) φ_l(x_j)
    r, f = track.rail, track.fastener
    m = r.density * r.area
    rho_i0 = r.density * r.polar_moment
    hf = r.shear_centre_above_foot
    Mz, Cz, Kz = m * S, f.cz * P, r.youngs_modulus * r.iy * B + f.kz * P
    Z = np.zeros((nm, nm))
    Mlt = np.block([[m * S, Z], [Z, rho_i0 * S]])
    # U = ½∫EI_z y″² + ½∫GJ θ′² + Σ ½k_y (y + h_f θ)² + ½k_r θ²  (and alike for damping)
    Klt = np.block([[r.youngs_modulus * r.iz * B + f.ky * P, f.ky * hf * P],
                    [f.ky * hf * P, r.shear_modulus * r.torsion_constant * T
                     + (f.k_roll + f.ky * hf * hf) * P]])
    Clt = np.block([[f.cy * P, f.cy * hf * P], [f.cy * hf * P, (f.c_roll + f.cy * hf * hf) * P]])
    return (Mz, Cz, Kz), (Mlt, Clt, Klt), L


# ----------------------------------------------------------------------------- contact


def hertz_g(radius: float) -> float:
    """Zhai's contact constant of a worn tread (m/N^(2/3))."""
    return 3.86 * radius**-0.115 * 1e-8


def she(fx, fy, mz, limit):
    """Shen–Hedrick–Elkins: scale the linear forces so |F| follows μN(x − x²/3 + x³/27)."""
    f = math.hypot(fx, fy)
    if f == 0.0:
        return fx, fy, mz
    x = f / limit
    fs = limit * (x - x * x / 3 + x**3 / 27) if x <= 3 else limit
    e = fs / f
    return fx * e, fy * e, mz * e


def wheel_contact(sc, table, irr, side, q_ws, v_ws, rail_q, rail_v, s_w, cst_prev, dt):
    """Force on the wheelset (Fx, Fy, Fz, Mx, My, Mz about its centre) and load on the rail at
    the running surface (vertical, lateral, torque about the shear centre), from one wheel.

    ``rail_q``/``rail_v``: (z, y, θ) of the rail at the wheel and their rates."""
    sg = 1.0 if side == 0 else -1.0
    c = sc.contact
    b0 = sc.vehicle.geometry.rolling_circle_half_distance
    r0 = sc.vehicle.geometry.wheel_radius
    h_head = sc.track.rail.head_above_shear_centre
    V = sc.speed_mps
    vref = max(V, V_MIN_CREEP)
    _, y, z, phi, _, psi = q_ws
    dx, dy, _, dphi, dbeta, dpsi = v_ws
    zr, yr, th = rail_q
    _, vyr, vth = rail_v
    zl_irr, zr_irr, yl_irr, yr_irr = (float(np.atleast_1d(a)[0]) for a in irr.sample(s_w))
    z_irr = zl_irr if side == 0 else zr_irr
    y_irr = yl_irr if side == 0 else yr_irr
    y_head = yr - h_head * th + y_irr
    vy_head = vyr - h_head * vth
    d_y = y - y_head

    def tab(name):
        return float(np.interp(d_y, table.y_grid, getattr(table, name)[side]))

    r, gam, rise, yc = tab("r"), tab("gamma"), tab("dz"), tab("yc")
    # normal compression: rail top against the wheel's contact point (rolled, on radius r)
    delta = (zr + z_irr) - (z + sg * b0 * phi) + rise
    N = (delta / hertz_g(r0)) ** 1.5 if delta > 0 else 0.0
    fx = fy = mz = 0.0
    if N > 0:
        # textbook linearised creepages (Garg & Dukkipati), nominal rolling circle b0
        xi_x = (V * (1 - r / r0) + dx - sg * b0 * dpsi - r * dbeta) / vref
        xi_y = (dy + r * dphi - vy_head) / vref - psi
        xi_sp = dpsi / vref - sg * math.sin(gam) / r0
        n13 = N ** (1 / 3)
        a, b = tab("ca") * n13, tab("cb") * n13
        gab = c.shear_modulus_for(sc.track.rail.youngs_modulus) * a * b
        f11, f22 = gab * tab("c11"), gab * tab("c22")
        f23, f33 = gab * math.sqrt(a * b) * tab("c23"), gab * a * b * tab("c33")
        fx, fy, mz = she(-f11 * xi_x, -f22 * xi_y - f23 * xi_sp, f23 * xi_y - f33 * xi_sp,
                         c.friction * N)
        if dt > 0:
            e = math.exp(-dt * vref / a)  # relaxation over the semi-axis a: τ = a/V
            fx, fy, mz = (f + (p - f) * e for f, p in zip((fx, fy, mz), cst_prev, strict=True))
    ge = gam + sg * phi
    n_vec = np.array([0.0, -sg * math.sin(ge), math.cos(ge)])  # normal on the wheel
    t_vec = np.array([0.0, math.cos(ge), sg * math.sin(ge)])  # lateral tangent
    force = fx * np.array([1.0, 0.0, 0.0]) + fy * t_vec + N * n_vec
    excess = sg * d_y - c.flange_clearance
    if excess > 0:
        force[1] -= sg * c.flange_stiffness * excess
    arm = np.array([0.0, sg * b0 + yc, -r])
    moment = np.cross(arm, force) + mz * n_vec
    rail_load = (-force[2], -force[1], h_head * force[1])  # torque of −F_y at the head
    return np.concatenate([force, moment]), rail_load, N


def wheel_contact_profiles(sc, ptable, irr, side, q_ws, v_ws, rail_q, rail_v, s_w, cst_prev,
                           dt):
    """As :func:`wheel_contact` for the two-slot table of real profiles; ``cst_prev`` holds
    (Fx, Fy, Mz) of slot 0 then slot 1; returns also the new creep state."""
    sg = 1.0 if side == 0 else -1.0
    c = sc.contact
    b0 = ptable.b0
    r0 = sc.vehicle.geometry.wheel_radius
    h_head = sc.track.rail.head_above_shear_centre
    g_shear = c.shear_modulus_for(sc.track.rail.youngs_modulus)
    V = sc.speed_mps
    vref = max(V, V_MIN_CREEP)
    _, y, z, phi, _, psi = q_ws
    dx, dy, dz_w, dphi, dbeta, dpsi = v_ws
    zr, yr, th = rail_q
    vzr, vyr, vth = rail_v
    zl_irr, zr_irr, yl_irr, yr_irr = (float(np.atleast_1d(a)[0]) for a in irr.sample(s_w))
    z_irr = zl_irr if side == 0 else zr_irr
    y_irr = yl_irr if side == 0 else yr_irr
    d_y = y - (yr - h_head * th + y_irr)
    v_rail = np.array([0.0, vyr - h_head * vth, vzr])
    omega = np.array([dphi, V / r0 + dbeta, dpsi])
    total = np.zeros(6)
    state = np.zeros(6)
    n_sum = 0.0
    for slot in range(2):
        def tab(name, slot=slot):
            return float(np.interp(d_y, ptable.y_grid, ptable.field(name)[side, slot]))

        delta_z = (zr + z_irr) - (z + sg * b0 * phi) + tab("dz")
        gam = tab("gamma")
        ge = gam + sg * phi
        delta_n = delta_z * math.cos(ge)
        if delta_z <= 0 or delta_n <= 0:
            continue
        N = (delta_n / tab("gh")) ** 1.5
        r = tab("r")
        arm = np.array([0.0, sg * b0 + tab("yc"), -r])
        n_vec = np.array([0.0, -sg * math.sin(ge), math.cos(ge)])  # normal on the wheel
        t_vec = np.array([0.0, math.cos(ge), sg * math.sin(ge)])  # lateral tangent
        slip = np.array([V + dx, dy, dz_w]) + np.cross(omega, arm) - v_rail
        slip[1] -= V * psi  # the yawed wheelset sees the forward speed turned by −ψ
        xi_x = slip[0] / vref
        xi_y = float(slip @ t_vec) / vref
        xi_sp = dpsi * n_vec[2] / vref - sg * math.sin(gam) / r0
        n13 = N ** (1 / 3)
        a, b = tab("ca") * n13, tab("cb") * n13
        gab = g_shear * a * b
        f11, f22 = gab * tab("c11"), gab * tab("c22")
        f23, f33 = gab * math.sqrt(a * b) * tab("c23"), gab * a * b * tab("c33")
        fx, fy, mz = she(-f11 * xi_x, -f22 * xi_y - f23 * xi_sp, f23 * xi_y - f33 * xi_sp,
                         c.friction * N)
        if dt > 0:
            e = math.exp(-dt * vref / a)
            prev = cst_prev[3 * slot:3 * slot + 3]
            fx, fy, mz = (f + (p - f) * e for f, p in zip((fx, fy, mz), prev, strict=True))
        state[3 * slot:3 * slot + 3] = fx, fy, mz
        force = fx * np.array([1.0, 0.0, 0.0]) + fy * t_vec + N * n_vec
        total += np.concatenate([force, np.cross(arm, force) + mz * n_vec])
        n_sum += N
    rail_load = (-total[2], -total[1], h_head * total[1])
    return total, rail_load, n_sum, state


# ----------------------------------------------------------------------------- the twin


def reference_accelerations(sc, asm, X, V, s, s_win0, cst_prev=None, dt=0.0):
    """Generalised accelerations of the whole system at (X, V), and the normal loads."""
    veh = asm.vehicle
    M, C, K, fg = vehicle_matrices(sc, veh)
    nv = M.shape[0]
    (Mz, Cz, Kz), (Mlt, Clt, Klt), L = rail_matrices(sc.track, asm.rail.n_bays)
    nm = Mz.shape[0]
    Fv = -K @ X[:nv] - C @ V[:nv] + fg
    kap = np.arange(1, nm + 1) * math.pi / L
    rail_z = [-Kz @ X[nv + 3 * r * nm:][:nm] - Cz @ V[nv + 3 * r * nm:][:nm] for r in range(2)]
    rail_lt = [-Klt @ X[nv + (3 * r + 1) * nm:][:2 * nm] - Clt @ V[nv + (3 * r + 1) * nm:][:2 * nm]
               for r in range(2)]
    off = offsets(veh.bodies)
    loads = np.zeros((len(veh.wheelsets), 2))
    if cst_prev is None:
        cst_prev = np.zeros((len(veh.wheelsets), 2, 6))
    for w, bi in enumerate(veh.wheelsets):
        o = off[bi]
        s_w = s + veh.bodies[bi].x_ref
        shape = np.sin(kap * (s_w - s_win0))
        for side in range(2):
            blk = [X[nv + (3 * side + k) * nm:][:nm] for k in range(3)]
            vblk = [V[nv + (3 * side + k) * nm:][:nm] for k in range(3)]
            rq = [float(shape @ q) for q in blk]
            rv = [float(shape @ v) for v in vblk]
            if asm.profiles is not None:
                gen, (pz, qy, mt), N, _ = wheel_contact_profiles(
                    sc, asm.profiles, asm.irregularity, side, X[o:o + 6], V[o:o + 6], rq, rv,
                    s_w, cst_prev[w, side], dt)
            else:
                gen, (pz, qy, mt), N = wheel_contact(
                    sc, asm.contact, asm.irregularity, side, X[o:o + 6], V[o:o + 6], rq, rv,
                    s_w, cst_prev[w, side], dt)
            Fv[o:o + 6] += gen
            rail_z[side] += pz * shape
            rail_lt[side][:nm] += qy * shape
            rail_lt[side][nm:] += mt * shape
            loads[w, side] = N
    A = np.zeros_like(X)
    A[:nv] = np.linalg.solve(M, Fv)
    for r in range(2):
        o = nv + 3 * r * nm
        A[o:o + nm] = np.linalg.solve(Mz, rail_z[r])
        A[o + nm:o + 3 * nm] = np.linalg.solve(Mlt, rail_lt[r])
    return A, loads


def kernel_accelerations(asm, X, V, s, s_win0, cst_prev=None, dt=0.0):
    n = X.size
    nw = len(asm.vehicle.wheelsets)
    F, A = np.zeros(n), np.zeros(n)
    aux = np.zeros((nw, 2, N_AUX))
    sn = np.zeros(asm.rail.n_modes)
    cst = np.zeros((nw, 2, 6)) if cst_prev is None else cst_prev.copy()
    evaluate(asm.sys, X.copy(), V.copy(), s, s_win0, F, A, aux, sn, cst, dt)
    return A, aux


def random_state(asm, sc, rng, scale_v=1.0, lift=False, y_set=None):
    """Wheels pressed onto the undeformed rails by their share of the weight (or lifted by
    5 cm, clear of the irregularity), every coordinate perturbed a little, random velocities;
    ``y_set`` {wheelset index: lateral displacement} moves wheelsets before they are pressed
    in."""
    veh = asm.vehicle
    off = offsets(veh.bodies)
    nv = sum(b.n_dof for b in veh.bodies)
    n = asm.sys.minv.size
    weight = sum(b.mass for b in veh.bodies) * G_ACC
    delta0 = hertz_g(sc.vehicle.geometry.wheel_radius) * (weight / 8) ** (2 / 3)
    if asm.profiles is not None:  # the tread's Hertz constant at the centred position
        delta0 = float(np.interp(0.0, asm.profiles.y_grid, asm.profiles.field("gh")[0, 0])
                       ) * (weight / 8) ** (2 / 3)
    X = np.zeros(n)
    V = np.zeros(n)
    X[:nv] = 1e-6 * rng.standard_normal(nv)  # m, rad, modal
    X[nv:] = 1e-8 * rng.standard_normal(n - nv)
    V[:nv] = 1e-2 * scale_v * rng.standard_normal(nv)
    V[nv:] = 1e-4 * scale_v * rng.standard_normal(n - nv)
    b0 = sc.vehicle.geometry.rolling_circle_half_distance
    for w, bi in enumerate(veh.wheelsets):
        o = off[bi]
        if y_set and w in y_set:
            X[o + 1] = y_set[w]
        if lift:
            X[o + 2] += 0.05
            continue
        # centred between the rails' lateral irregularity, each wheel pressed in by δ0 on the
        # rail's vertical irregularity plus the rise of its contact point
        irr = [float(a) for a in asm.irregularity.sample(S_CENTRE + veh.bodies[bi].x_ref)]
        X[o + 1] += 0.5 * (irr[2] + irr[3])
        b0 = asm.sys.par.b0
        top = [irr[side] + float(np.interp(X[o + 1] - irr[2 + side], asm.contact.y_grid,
                                           asm.contact.dz[side])) - delta0 for side in (0, 1)]
        X[o + 2] += 0.5 * (top[0] + top[1])
        X[o + 3] += (top[0] - top[1]) / (2 * b0)
    return X, V


def assert_close(a_ker, a_ref, asm, rtol):
    """Per block (body, rail direction): max error within ``rtol`` of the block's largest
    value."""
    nv = sum(b.n_dof for b in asm.vehicle.bodies)
    nm = asm.rail.n_modes
    edges = [*offsets(asm.vehicle.bodies), *range(nv, nv + 6 * nm + 1, nm)]
    for lo, hi in itertools.pairwise(edges):
        scale = np.abs(a_ref[lo:hi]).max()
        err = np.abs(a_ker[lo:hi] - a_ref[lo:hi]).max()
        assert err <= rtol * scale, (lo, hi, err, scale)


# ----------------------------------------------------------------------------- flexible body


# ----------------------------------------------------------------------------- tests


@pytest.fixture(scope="module", params=["rigid", "flexible"])
def case(request):
    sc = preset("paper-random-straight-80", distance_m=None, duration_s=4.0,
                contact__geometry="conical")
    assert sc.contact.hertz_tread == "worn" and sc.line.kind == "straight"  # the twin's scope
    veh = None
    if request.param == "flexible":
        veh = build_vehicle(sc.vehicle, sc.output, carbody=beam_carbody(sc.vehicle, 8.0, 2, 0.02))
    asm = assemble(sc, vehicle=veh)
    return sc, asm, initial_window_start(asm, S_CENTRE)


def test_linear_part_matches_dense_matrices(case):
    """Wheels lifted: suspension, elastic modes, gyroscopics, gravity and the rail beams alone,
    all linear: agreement to rounding."""
    sc, asm, s_win0 = case
    rng = np.random.default_rng(1)
    for _ in range(3):
        X, V = random_state(asm, sc, rng, lift=True)
        a_ker, aux = kernel_accelerations(asm, X, V, S_CENTRE, s_win0)
        a_ref, loads = reference_accelerations(sc, asm, X, V, S_CENTRE, s_win0)
        assert not aux[:, :, AUX_N].any() and not loads.any()  # no contact
        assert_close(a_ker, a_ref, asm, 1e-9)


@pytest.mark.parametrize("scale_v", [0.1, 30.0])  # creep: nearly linear, saturated
def test_full_forces_with_contact(case, scale_v):
    sc, asm, s_win0 = case
    rng = np.random.default_rng(2)
    for _ in range(3):
        X, V = random_state(asm, sc, rng, scale_v=scale_v)
        a_ker, aux = kernel_accelerations(asm, X, V, S_CENTRE, s_win0)
        a_ref, loads = reference_accelerations(sc, asm, X, V, S_CENTRE, s_win0)
        assert loads.min() > 0.0
        np.testing.assert_allclose(aux[:, :, AUX_N], loads, rtol=1e-9)  # normal loads
        assert_close(a_ker, a_ref, asm, 1e-9)


def test_flange_contact_and_creep_relaxation(case):
    sc, asm, s_win0 = case
    rng = np.random.default_rng(3)
    X, V = random_state(asm, sc, rng)
    off = offsets(asm.vehicle.bodies)
    X[off[asm.vehicle.wheelsets[0]] + 1] = 0.0095  # front wheelset 9.5 mm left: left flange
    X[off[asm.vehicle.wheelsets[3]] + 1] = -0.0090  # rear wheelset: right flange
    cst = 2e3 * rng.standard_normal((len(asm.vehicle.wheelsets), 2, 3))
    for dt in (0.0, 1e-4):
        a_ker, aux = kernel_accelerations(asm, X, V, S_CENTRE, s_win0, cst, dt)
        a_ref, loads = reference_accelerations(sc, asm, X, V, S_CENTRE, s_win0, cst, dt)
        np.testing.assert_allclose(aux[:, :, AUX_N], loads, rtol=1e-9)
        assert_close(a_ker, a_ref, asm, 1e-9)


@pytest.fixture(scope="module", params=["rigid", "flexible"])
def case_profiles(request):
    sc = preset("paper-random-straight-80", distance_m=None, duration_s=4.0,
                **PROFILES)
    assert sc.line.kind == "straight"
    veh = None
    if request.param == "flexible":
        veh = build_vehicle(sc.vehicle, sc.output, carbody=beam_carbody(sc.vehicle, 8.0, 2, 0.02))
    asm = assemble(sc, vehicle=veh)
    assert asm.profiles is not None
    return sc, asm, initial_window_start(asm, S_CENTRE)


@pytest.mark.parametrize("scale_v", [0.1, 30.0])
def test_two_slot_profile_contact(case_profiles, scale_v):
    """Real profiles, tread contact (nearly linear and saturated creep)."""
    sc, asm, s_win0 = case_profiles
    rng = np.random.default_rng(4)
    for _ in range(3):
        X, V = random_state(asm, sc, rng, scale_v=scale_v)
        a_ker, aux = kernel_accelerations(asm, X, V, S_CENTRE, s_win0)
        a_ref, loads = reference_accelerations(sc, asm, X, V, S_CENTRE, s_win0)
        assert loads.min() > 0.0
        np.testing.assert_allclose(aux[:, :, AUX_N], loads, rtol=1e-9)
        assert_close(a_ker, a_ref, asm, 1e-9)


def test_two_slot_flange_and_two_point_contact(case_profiles):
    """Wheelsets in two-point contact (tread and flange root both loaded) and on the flange,
    with creep relaxation from a random previous state."""
    sc, asm, s_win0 = case_profiles
    rng = np.random.default_rng(5)
    # 4.8 mm: both slots of the left wheel within reach (two-point band of S1002/60E1 at
    # the 1360 mm flange-back distance, 4.3–5.35 mm); −9 mm: the right wheel on its flange
    X, V = random_state(asm, sc, rng, y_set={0: 0.0048, 1: 0.0030, 3: -0.0090})
    off = offsets(asm.vehicle.bodies)
    o = off[asm.vehicle.wheelsets[0]]
    X[o + 2] -= 5e-5  # press the two-point wheelset in a little more: both slots loaded
    cst = 2e3 * rng.standard_normal((len(asm.vehicle.wheelsets), 2, 6))
    for dt in (0.0, 1e-4):
        a_ker, aux = kernel_accelerations(asm, X, V, S_CENTRE, s_win0, cst, dt)
        a_ref, loads = reference_accelerations(sc, asm, X, V, S_CENTRE, s_win0, cst, dt)
        np.testing.assert_allclose(aux[:, :, AUX_N], loads, rtol=1e-9)
        assert_close(a_ker, a_ref, asm, 1e-9)
    assert aux[0, 0, AUX_N_FLANGE] > 0.0 and aux[0, 0, AUX_N] > aux[0, 0, AUX_N_FLANGE]
    assert aux[3, 1, AUX_N_FLANGE] > 0.0 and aux[3, 1, AUX_ANGLE] > 0.5  # right flange


@pytest.mark.slow
def test_without_jit_the_kernel_gives_the_same_results():
    """The solver's fast unit tests (integrator, static equilibrium, this twin) pass with
    NUMBA_DISABLE_JIT=1: the compiled code and its plain-Python reading agree (≈ 20 s)."""
    root = Path(__file__).resolve().parents[2]
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    tests = ["tests/solver/test_integrator.py", "tests/solver/test_static.py",
             "tests/solver/test_forces_reference.py::test_linear_part_matches_dense_matrices",
             "tests/solver/test_forces_reference.py::test_full_forces_with_contact",
             "tests/solver/test_forces_reference.py::test_flange_contact_and_creep_relaxation",
             "tests/solver/test_forces_reference.py::test_two_slot_profile_contact",
             "tests/solver/test_forces_reference.py::test_two_slot_flange_and_two_point_contact"]
    out = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                          *tests], cwd=root, env=env, capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-2000:]

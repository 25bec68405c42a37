"""The kernel's rail forces against beam theory."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from conftest import preset
from flexride.solver.assemble import assemble
from flexride.solver.linearise import jacobian


def _rail_block(asm, side, direction):
    nv = asm.sys.par.n_veh
    nm = asm.rail.n_modes
    o = nv + (3 * side + direction) * nm
    return np.arange(o, o + nm)


def test_unsupported_rail_modes_are_simply_supported_beam_modes():
    """With almost no fastener stiffness, vertical modes → (kπ/L)²·√(EI/m), torsion modes →
    (kπ/L)·√(GJ/ρI₀) (pinned window ends)."""
    sc = preset(
        "paper-metro",
        **{
            "track.fastener.kz": 1.0e5 + 1,
            "track.fastener.ky": 1.0e5 + 1,
            "track.fastener.k_roll": 1e-6,
        },
    )
    asm = assemble(sc)
    n = asm.sys.minv.size
    X = np.zeros(n)
    K = -jacobian(asm.sys, X, X, 0.0, -1000.0, _rail_block(asm, 0, 0))  # wheels far away
    idx = _rail_block(asm, 0, 0)
    w2 = np.diag(K[idx])
    tr = sc.track
    m = tr.rail.density * tr.rail.area
    L = asm.rail.length
    k = np.arange(1, idx.size + 1)
    beam = (k * np.pi / L) ** 4 * tr.rail.youngs_modulus * tr.rail.iy / m
    found = w2 - tr.fastener.kz / tr.fastener.spacing / m
    assert np.allclose(found, beam, rtol=1e-6)
    it = _rail_block(asm, 0, 2)
    Kt = -jacobian(asm.sys, X, X, 0.0, -1000.0, it)
    gj = tr.rail.shear_modulus * tr.rail.torsion_constant
    rho_i0 = tr.rail.density * tr.rail.polar_moment
    torsion = (k * np.pi / L) ** 2 * gj / rho_i0
    hf = tr.rail.shear_centre_above_foot
    fastener_part = (tr.fastener.k_roll + hf**2 * tr.fastener.ky) / tr.fastener.spacing / rho_i0
    assert np.allclose(np.diag(Kt[it]) - fastener_part, torsion, rtol=1e-6)


def _infinite_beam_receptance(ei, m, k, c, f):
    """Point receptance of an infinite Euler beam on a continuous viscoelastic foundation:
    w/P = (1/2π) ∫ dξ / (EI ξ⁴ + k − mω² + iωc)  (numerical integral, independent of the
    modal model)."""
    w = 2 * np.pi * f
    s = k - m * w**2 + 1j * w * c

    def part(fun):
        return quad(lambda xi: fun(1.0 / (ei * xi**4 + s)), 0, np.inf, limit=400)[0]

    return (part(np.real) + 1j * part(np.imag)) / np.pi


def test_point_receptance_below_pinned_pinned_frequency():
    """The kernel's linearised rail (mass, stiffness, damping from finite differences) against
    the continuously supported beam, at mid-bay, 20–300 Hz (twice the foundation cut-on
    frequency √(k/m)/2π ≈ 145 Hz). Higher up, the periodic discrete support departs from the
    smeared model (at 400 Hz by ~50 % with these lightly damped pads, independent of the window
    length: it is the periodic structure, not a window artefact)."""
    sc = preset("paper-metro")
    asm = assemble(sc)
    idx = _rail_block(asm, 0, 0)
    n = asm.sys.minv.size
    K = -jacobian(asm.sys, np.zeros(n), np.zeros(n), 0.0, -1000.0, idx)[idx]
    C = -jacobian(asm.sys, np.zeros(n), np.zeros(n), 0.0, -1000.0, idx, wrt_velocity=True)[idx]
    m = sc.track.rail.density * sc.track.rail.area
    L = asm.rail.length
    x0 = asm.rail.spacing * (asm.rail.n_bays // 2 + 0.5)  # mid-bay near the window centre
    phi = np.sin(np.arange(1, idx.size + 1) * np.pi * x0 / L)
    ei = sc.track.rail.youngs_modulus * sc.track.rail.iy
    kf = sc.track.fastener.kz / sc.track.fastener.spacing
    cf = sc.track.fastener.cz / sc.track.fastener.spacing
    for f in (20.0, 100.0, 200.0, 300.0):
        w = 2 * np.pi * f
        # generalised force of a unit point load: (2/L)·sin(κx0)/m per unit mass
        q = np.linalg.solve(K - w**2 * np.eye(idx.size) + 1j * w * C, (2 / L) * phi / m)
        modal = phi @ q
        analytic = _infinite_beam_receptance(ei, m, kf, cf, f)
        assert abs(modal) == pytest.approx(abs(analytic), rel=0.05), f


def _fe_discrete_receptance(ei, m, kf, cf, d, n_bays, x0, freqs, ne_per_bay=8):
    """Independent oracle: Euler–Bernoulli beam of Hermite finite elements (consistent mass)
    on discrete spring–dampers at every fastener, pinned at the window ends (sparse solve)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spl

    ne = n_bays * ne_per_bay
    le = d / ne_per_bay
    nn = ne + 1
    ke = (
        ei
        / le**3
        * np.array(
            [
                [12, 6 * le, -12, 6 * le],
                [6 * le, 4 * le**2, -6 * le, 2 * le**2],
                [-12, -6 * le, 12, -6 * le],
                [6 * le, 2 * le**2, -6 * le, 4 * le**2],
            ]
        )
    )
    me = (
        m
        * le
        / 420
        * np.array(
            [
                [156, 22 * le, 54, -13 * le],
                [22 * le, 4 * le**2, 13 * le, -3 * le**2],
                [54, 13 * le, 156, -22 * le],
                [-13 * le, -3 * le**2, -22 * le, 4 * le**2],
            ]
        )
    )
    rows, cols, kv, mv = [], [], [], []
    for e in range(ne):
        idx = np.arange(2 * e, 2 * e + 4)
        rows.extend(np.repeat(idx, 4))
        cols.extend(np.tile(idx, 4))
        kv.extend(ke.ravel())
        mv.extend(me.ravel())
    K = sp.coo_matrix((kv, (rows, cols)), shape=(2 * nn, 2 * nn)).tocsr()
    M = sp.coo_matrix((mv, (rows, cols)), shape=(2 * nn, 2 * nn)).tocsr()
    sup = 2 * ne_per_bay * np.arange(1, n_bays)
    K = K + sp.coo_matrix((np.full(sup.size, kf), (sup, sup)), shape=K.shape).tocsr()
    C = sp.coo_matrix((np.full(sup.size, cf), (sup, sup)), shape=K.shape).tocsr()
    free = np.setdiff1d(np.arange(2 * nn), [0, 2 * (nn - 1)])
    K, M, C = (A[free][:, free] for A in (K, M, C))
    row = int(np.searchsorted(free, 2 * round(x0 / le)))
    out = []
    for f in freqs:
        w = 2 * np.pi * f
        rhs = np.zeros(free.size, complex)
        rhs[row] = 1.0
        out.append(spl.spsolve((K - w * w * M + 1j * w * C).tocsc(), rhs)[row])
    return np.array(out)


def test_modal_rail_matches_discretely_supported_fe_beam():
    """The kernel's modal rail (N − 1 sine modes) against an independent FE model of the same
    discretely supported, pinned window: within 5 % up to 500 Hz (measured ≤ 3.6 %; the
    truncation at N − 1 modes shows near the pinned–pinned frequency, ≈ 1.45 kHz)."""
    sc = preset("paper-metro")
    asm = assemble(sc)
    idx = _rail_block(asm, 0, 0)
    n = asm.sys.minv.size
    K = -jacobian(asm.sys, np.zeros(n), np.zeros(n), 0.0, -1000.0, idx)[idx]
    C = -jacobian(asm.sys, np.zeros(n), np.zeros(n), 0.0, -1000.0, idx, wrt_velocity=True)[idx]
    tr = sc.track
    m = tr.rail.density * tr.rail.area
    L, d = asm.rail.length, asm.rail.spacing
    x0 = d * (asm.rail.n_bays // 2 + 0.5)
    phi = np.sin(np.arange(1, idx.size + 1) * np.pi * x0 / L)
    freqs = (20.0, 100.0, 200.0, 300.0, 400.0, 500.0)
    fe = _fe_discrete_receptance(
        tr.rail.youngs_modulus * tr.rail.iy,
        m,
        tr.fastener.kz,
        tr.fastener.cz,
        d,
        asm.rail.n_bays,
        x0,
        freqs,
    )
    for f, ref in zip(freqs, fe, strict=True):
        w = 2 * np.pi * f
        modal = phi @ np.linalg.solve(K - w**2 * np.eye(idx.size) + 1j * w * C, (2 / L) * phi / m)
        assert abs(modal) == pytest.approx(abs(ref), rel=0.05), f

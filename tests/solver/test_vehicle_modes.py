"""Rigid-body modes of the coupled system against hand calculation from the suspension."""

from __future__ import annotations

import numpy as np
import pytest

from conftest import preset
from flexride.solver.assemble import assemble
from flexride.solver.linearise import jacobian
from flexride.solver.static import initial_window_start, static_equilibrium


@pytest.fixture(scope="module")
def modes():
    sc = preset("paper-metro")
    asm = assemble(sc)
    s0 = initial_window_start(asm)
    X0 = static_equilibrium(asm, 0.0, s0)
    n = X0.size
    K = -jacobian(asm.sys, X0, np.zeros(n), 0.0, s0, np.arange(n))  # M⁻¹K
    sq = np.sqrt(1 / asm.sys.minv)
    Ks = sq[:, None] * K / sq[None, :]
    lam, vec = np.linalg.eigh(0.5 * (Ks + Ks.T))
    freqs = np.sqrt(np.clip(lam, 0, None)) / (2 * np.pi)
    return sc, asm, freqs, vec


def _mode_dominated_by(asm, vec, dof):
    i = asm.dof_names.index(dof)
    return int(np.argmax(np.abs(vec[i, :])))


def _two_dof_lowest(m1, m2, k1, k2):
    """Lowest frequency (Hz) of m1 on spring k1 on m2 on spring k2 to ground."""
    M = np.diag([m1, m2])
    K = np.array([[k1, -k1], [-k1, k1 + k2]])
    w2 = np.linalg.eigvals(np.linalg.solve(M, K)).real
    return np.sqrt(w2.min()) / (2 * np.pi)


def test_car_body_bounce(modes):
    sc, asm, freqs, vec = modes
    v = sc.vehicle
    expected = _two_dof_lowest(v.carbody.mass, 2 * v.frame.mass, 4 * v.secondary.kz,
                               8 * v.primary.kz)
    got = freqs[_mode_dominated_by(asm, vec, "carbody.z")]
    assert got == pytest.approx(expected, rel=0.02)


def test_car_body_pitch(modes):
    """Car body pitch on the air springs (±l) with the frames bouncing in antiphase on the
    primary springs: θ–u two-DOF system."""
    sc, asm, freqs, vec = modes
    v = sc.vehicle
    lc = v.geometry.bogie_centre_spacing / 2
    ks, kp = v.secondary.kz, v.primary.kz
    M = np.diag([v.carbody.iyy, 2 * v.frame.mass])
    K = np.array([[4 * ks * lc**2, -4 * ks * lc], [-4 * ks * lc, 4 * ks + 8 * kp]])
    expected = np.sqrt(np.linalg.eigvals(np.linalg.solve(M, K)).real.min()) / (2 * np.pi)
    got = freqs[_mode_dominated_by(asm, vec, "carbody.pitch")]
    assert got == pytest.approx(expected, rel=0.02)

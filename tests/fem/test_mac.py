"""The modal assurance criterion against its defining properties."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse as sp

from flexride.errors import FEModelError
from flexride.fem.mac import mac
from flexride.fem.report import mac_matrix


def _spd(n: int, seed: int) -> np.ndarray:
    a = np.random.default_rng(seed).standard_normal((n, n))
    return a @ a.T + n * np.eye(n)


def test_mac_of_a_shape_with_itself_is_one_at_any_scale():
    phi = np.random.default_rng(1).standard_normal(12)
    assert mac(phi, phi)[0, 0] == pytest.approx(1.0, abs=1e-14)
    for factor in (-3.7, 1e-6, 2.0 + 1.5j):
        assert mac(phi, factor * phi)[0, 0] == pytest.approx(1.0, abs=1e-12)


def test_mass_orthogonal_modes_have_zero_mass_weighted_mac():
    K, M = _spd(10, 2), _spd(10, 3)
    _, phi = la.eigh(K, M)  # K φ = λ M φ: φᵀ M φ = I
    weighted = mac(phi, phi, M)
    assert np.allclose(weighted, np.eye(10), atol=1e-12)
    assert mac(phi, phi, sp.csr_matrix(M)) == pytest.approx(weighted, abs=1e-12)
    unweighted = mac(phi, phi)
    assert np.max(unweighted - np.diag(np.diag(unweighted))) > 0.01  # the weight matters


def test_matrix_form_and_scale_invariance_column_by_column():
    rng = np.random.default_rng(4)
    a, b = rng.standard_normal((8, 3)), rng.standard_normal((8, 5))
    m = mac(a, b)
    assert m.shape == (3, 5) and np.all((m >= 0) & (m <= 1))
    scaled = mac(a * np.array([2.0, -1.0, 0.1]), b * np.arange(1, 6))
    assert np.allclose(scaled, m)
    assert m[1, 2] == pytest.approx((a[:, 1] @ b[:, 2]) ** 2
                                    / ((a[:, 1] @ a[:, 1]) * (b[:, 2] @ b[:, 2])))
    assert np.allclose(mac_matrix(a, b), m)


def test_zero_shapes_and_mismatched_dofs():
    assert mac(np.zeros(4), np.ones(4))[0, 0] == 0.0
    with pytest.raises(FEModelError, match="same DOFs"):
        mac(np.ones(4), np.ones(5))
    with pytest.raises(FEModelError, match="same DOFs"):
        mac(np.ones(4), np.ones(4), np.eye(3))

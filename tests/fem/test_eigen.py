"""The sparse eigen solutions (``fem/eigen``).

The factorisation (``factorise``): symmetric mode where it is accurate, partial pivoting where
a diagonal pivot fails; the oracle is the residual of the solved system itself, A x = b.
The block shift-invert Lanczos with spectrum slicing (``solve_modes``): against closed-form
frequencies (spring–mass chains), a constructed spectrum of degenerate and close pairs, a
dense solution, and the number of eigenvalues below the cut-off from Sylvester's inertia of
``K − σM`` (dense Bunch–Kaufman LDLᵀ, or the pivots of the sparse symmetric factorisation).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as la
import scipy.sparse as sp
from threadpoolctl import threadpool_limits

from flexride.fem.eigen import LU_RESIDUAL_TOL, factorise, free_free_modes, solve_modes
from flexride.fem.rigid import rigid_body_vectors
from flexride.fem.vehicle_models import build_fe_model


@pytest.fixture(scope="module")
def frame(vehicle):
    """K and M of a bogie frame at 0.1 m elements (1,278 DOFs, sparse)."""
    model, _ = build_fe_model("frame", vehicle, element_size=0.1)
    K, M = model.assemble()
    return K.tocsc(), M.tocsc()


def _residual(A: sp.spmatrix, x: np.ndarray, b: np.ndarray) -> float:
    return float(np.linalg.norm(A @ x - b) / np.linalg.norm(b))


def test_a_zero_diagonal_falls_back_to_pivoting():
    """A symmetric matrix with zero diagonal entries has no factorisation with diagonal
    pivots; with row exchanges it has one (a permuted tridiagonal matrix)."""
    n = 40  # even: the determinant is ± the product of the odd off-diagonals squared
    off = np.arange(1.0, n)
    A = sp.diags([off, off], [-1, 1], format="csc")
    b = np.linspace(1.0, 2.0, n)
    lu = factorise(A)
    assert _residual(A, lu.solve(b), b) < 1e-12


def test_a_singular_matrix_raises():
    A = sp.csc_matrix(np.array([[1.0, 1.0], [1.0, 1.0]]))
    with pytest.raises(RuntimeError):
        factorise(A)


@pytest.mark.parametrize("f_shift_hz", [-1.0, 23.7, 61.3])
def test_the_frame_model_solves_accurately_below_and_inside_its_spectrum(frame, f_shift_hz):
    """K − σM of a bogie frame, σ below the spectrum (positive definite) and between its
    modes (indefinite): the kept factorisation solves to the stated residual."""
    K, M = frame
    sigma = np.sign(f_shift_hz) * (2.0 * np.pi * f_shift_hz) ** 2
    A = (K - sigma * M).tocsc()
    b = np.random.default_rng(7).standard_normal(A.shape[0])
    lu = factorise(A)
    assert _residual(A, lu.solve(b), b) < LU_RESIDUAL_TOL


def test_modes_from_the_symmetric_factorisation_satisfy_the_eigen_equation(frame):
    """Every mode of a shift-invert solution (the sparse path, forced by ``dense_below=0``):
    ‖K φ − ω² M φ‖ small against ‖K φ‖ + ω₁² ‖M φ‖ (ω₁ = 2π · 1 Hz, the scale of the
    free–free frame's rigid-body modes, whose K φ is nearly zero)."""
    K, M = frame
    modes = solve_modes(K, M, n_modes=12, dense_below=0)
    for w, phi in zip(modes.omega, modes.shapes.T, strict=True):
        r = K @ phi - w**2 * (M @ phi)
        scale = np.linalg.norm(K @ phi) + (2.0 * np.pi) ** 2 * np.linalg.norm(M @ phi)
        assert np.linalg.norm(r) <= 1e-6 * scale  # measured 5.7e-8 (general LU: 4.7e-7)


# --- the block shift-invert Lanczos and its spectrum slicing, against independent oracles ---


def _chain(n: int, k: float, m: float, fixed: bool) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    """A spring–mass chain of ``n`` masses ``m`` (kg) and springs ``k`` (N/m), held by a
    spring at each end (``fixed``) or free at both."""
    diag = np.full(n, 2.0 * k)
    if not fixed:
        diag[[0, -1]] = k
    K = sp.diags([np.full(n - 1, -k), diag, np.full(n - 1, -k)], [-1, 0, 1], format="csc")
    return K, sp.identity(n, format="csc") * m


def _hz(w2: np.ndarray) -> np.ndarray:
    return np.sqrt(w2) / (2.0 * np.pi)


def _m_orthonormal(phi: np.ndarray, M) -> float:
    """Largest deviation of ``φᵀ M φ`` from the identity."""
    return float(np.abs(phi.T @ (M @ phi) - np.eye(phi.shape[1])).max())


def test_a_fixed_spring_mass_chain_has_its_closed_form_frequencies():
    """ω_j² = (4k/m) sin²(jπ / 2(n+1)): all 100 modes below 100.5 Hz (f_j ≈ j Hz), from
    several slices of 30 modes, none missed or found twice."""
    n, m = 3000, 1.0
    k = m * (2.0 * (n + 1)) ** 2  # f_1 ≈ 1 Hz
    K, M = _chain(n, k, m, fixed=True)
    exact = _hz(4.0 * k / m * np.sin(np.arange(1, n + 1) * np.pi / (2.0 * (n + 1))) ** 2)
    modes = solve_modes(K, M, f_max=100.5, window=30)
    want = exact[exact <= 100.5]
    assert want.size == 100
    assert modes.frequencies.size == want.size
    np.testing.assert_allclose(modes.frequencies, want, rtol=1e-10)
    assert _m_orthonormal(modes.shapes, M) < 1e-8


def test_a_free_chain_deflates_its_rigid_mode():
    """A free–free chain, ω_j² = (4k/m) sin²(jπ / 2n), j = 0…n−1: the rigid mode (j = 0,
    uniform motion) is projected out and every elastic mode below ``f_max`` is returned."""
    n, m = 2000, 2.0
    k = m * (2.0 * n) ** 2  # f_1 ≈ 1 Hz
    K, M = _chain(n, k, m, fixed=False)
    exact = _hz(4.0 * k / m * np.sin(np.arange(1, n) * np.pi / (2.0 * n)) ** 2)
    modes = solve_modes(K, M, f_max=60.5, deflate=np.ones((n, 1)), window=25)
    np.testing.assert_allclose(modes.frequencies, exact[exact <= 60.5], rtol=1e-10)
    assert np.abs(modes.shapes.T @ (M @ np.ones(n))).max() < 1e-8 * np.sqrt(n * m)


def _mixing(n: int, rng: np.random.Generator) -> sp.csc_matrix:
    """A sparse orthogonal matrix: two layers of plane rotations of random index pairs."""
    G = sp.identity(n, format="csc")
    for _ in range(2):
        p = rng.permutation(n).reshape(-1, 2)
        c, s = np.cos(a := rng.uniform(0, np.pi, n // 2)), np.sin(a)
        rows = np.concatenate([p[:, 0], p[:, 0], p[:, 1], p[:, 1]])
        cols = np.concatenate([p[:, 0], p[:, 1], p[:, 0], p[:, 1]])
        G = sp.csc_matrix((np.concatenate([c, -s, s, c]), (rows, cols)), shape=(n, n)) @ G
    return G.tocsc()


def test_degenerate_and_close_pairs_are_kept_across_slice_borders():
    """``K = S Gᵀ Λ G S``, ``M = S²`` (``G`` orthogonal, ``S`` diagonal): the eigenvalues are
    ``Λ``, built of exact double eigenvalues and pairs 1e-9 apart (relative), so that slice
    borders (window 20) fall on pairs. Every eigenvalue below the cut-off is found once."""
    rng = np.random.default_rng(11)
    n = 2000
    base = (2.0 * np.pi * np.geomspace(1.0, 10.0, n // 2)) ** 2  # K's round-off ~ 1e-14 Λ
    split = np.where(np.arange(n // 2) % 3 == 1, 1e-9, 0.0)  # a third close, the rest equal
    lam = np.concatenate([base, base * (1.0 + split)])
    S = sp.diags(rng.uniform(0.5, 2.0, n))
    G = _mixing(n, rng)
    K = (S @ G.T @ sp.diags(lam) @ G @ S).tocsc()
    M = (S @ S).tocsc()
    f_max = 1.15
    want = np.sort(_hz(lam[lam <= (2.0 * np.pi * f_max) ** 2]))
    modes = solve_modes(K, M, f_max=f_max, window=20)
    assert modes.frequencies.size == want.size
    np.testing.assert_allclose(modes.frequencies, want, rtol=1e-10)
    assert _m_orthonormal(modes.shapes, M) < 1e-8


def _negative_eigenvalues(A: np.ndarray) -> int:
    """Sylvester's inertia from a dense Bunch–Kaufman ``A = L D Lᵀ`` (LAPACK ``dsytrf``):
    the negative eigenvalues of ``A`` are those of ``D`` (1 × 1 and 2 × 2 blocks)."""
    ld, piv, info = la.lapack.dsytrf(A, lower=1)
    assert info == 0
    d, off = np.diag(ld).copy(), np.zeros(A.shape[0] - 1)
    i = 0
    while i < A.shape[0]:
        if piv[i] < 0:  # a 2 × 2 block at (i, i+1): both pivots negative
            off[i] = ld[i + 1, i]
            i += 1
        i += 1
    return int(np.sum(la.eigvalsh_tridiagonal(d, off) < 0))


def _negative_pivots(A: sp.spmatrix) -> int:
    """Sylvester's inertia from the sparse factorisation in symmetric mode: with the same row
    and column permutation, ``P A Pᵀ = L U`` and ``U = D Lᵀ``, so the negative eigenvalues
    of ``A`` are the negative diagonal entries of ``U``."""
    lu = factorise(sp.csc_matrix(A))
    assert np.array_equal(lu.perm_r, lu.perm_c)
    return int(np.sum(lu.U.diagonal() < 0))


def test_the_frame_modes_match_a_dense_solution_and_the_inertia_count(frame, vehicle):
    """A free–free bogie frame through the sparse path with its six rigid-body modes deflated,
    slices of 10 modes: the number of elastic modes below 500 Hz is the inertia of
    ``K − σM`` (σ = (2π · 500 Hz)²) less the six rigid ones, and the frequencies are those
    of a dense solution."""
    K, M = frame
    model, _ = build_fe_model("frame", vehicle, element_size=0.1)
    R = rigid_body_vectors(model.nodes)
    f_max = 500.0
    modes = solve_modes(K, M, f_max=f_max, deflate=R, dense_below=0, window=10)
    sigma = (2.0 * np.pi * f_max) ** 2
    with threadpool_limits(limits=1, user_api="blas"):  # two threads crawl on a loaded machine
        assert modes.frequencies.size == _negative_eigenvalues((K - sigma * M).toarray()) - 6
        w2 = la.eigh(K.toarray(), M.toarray(), eigvals_only=True)
    kept = w2[6:][w2[6:] <= sigma]
    dense = _hz(kept)
    # the dense reference is accurate to about eps·λ_max in ω² (backward stability of the
    # symmetric-definite solution: 2.4e-6 relative at the first mode, λ_max/λ_1 ≈ 1e10), half of
    # that in frequency; the sparse path has agreed to 3e-8 (a LAPACK release moved the dense
    # first mode by that, beyond the former fixed 1e-8)
    bound = 0.5 * np.finfo(float).eps * w2[-1] / kept
    assert np.all(np.abs(modes.frequencies / dense - 1.0) <= np.maximum(bound, 1e-10))


@pytest.fixture(scope="module")
def coarse_carbody(vehicle):
    """K, M and rigid-body vectors of the car body at 0.5 m elements (5,208 DOFs; M is
    singular, so no dense generalised solution)."""
    model, _ = build_fe_model("carbody", vehicle, element_size=0.5)
    K, M = model.assemble()
    return K.tocsc(), M.tocsc(), rigid_body_vectors(model.nodes)


def test_the_coarse_car_body_modes_pass_the_inertia_count_and_residual(coarse_carbody):
    """Every elastic mode below 60 Hz of a 5,208-DOF shell model: as many as the inertia
    of ``K − σM`` counts below σ = (2π · 60 Hz)² less the six rigid-body modes (the sparse
    LDLᵀ, apart from the eigen solution), M-orthonormal, each with a small residual
    ‖Kφ − ω²Mφ‖ / (ω² ‖Mφ‖) (measured 1.2e-8 at most below 100 Hz, 3.8e-9 for the 0.2 m
    model; ARPACK's at the same tolerance 3e-10)."""
    K, M, R = coarse_carbody
    f_max = 60.0
    modes = free_free_modes(K, M, R, f_max=f_max, window=40)
    assert modes.frequencies.size == _negative_pivots(K - (2.0 * np.pi * f_max) ** 2 * M)
    w2, phi = modes.omega[6:] ** 2, modes.shapes[:, 6:]
    res = np.linalg.norm(K @ phi - (M @ phi) * w2, axis=0) / (w2 * np.linalg.norm(M @ phi, axis=0))
    assert res.max() <= 5e-8
    assert _m_orthonormal(modes.shapes, M) < 1e-8


def test_the_solution_is_repeatable():
    """Fixed start blocks: the same frequencies and shapes, bit for bit, when solved again."""
    K, M = _chain(2500, 1e7, 1.0, fixed=True)
    one, two = (solve_modes(K, M, f_max=80.0, window=25) for _ in range(2))
    np.testing.assert_array_equal(one.frequencies, two.frequencies)
    np.testing.assert_array_equal(one.shapes, two.shapes)


def test_a_small_model_falls_back_to_arpack():
    """Where the block Lanczos basis would not fit (40 of 60 DOFs wanted), ARPACK solves:
    the closed-form frequencies of a fixed chain, ω_j² = (4k/m) sin²(jπ / 2(n+1))."""
    n, k, m = 60, 1e6, 1.0
    K, M = _chain(n, k, m, fixed=True)
    exact = _hz(4.0 * k / m * np.sin(np.arange(1, n + 1) * np.pi / (2.0 * (n + 1))) ** 2)
    modes = solve_modes(K, M, n_modes=40, dense_below=0)
    np.testing.assert_allclose(modes.frequencies, exact[:40], rtol=1e-9)

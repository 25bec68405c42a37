"""Sparse generalised eigen solutions (free–free or constrained) with shift-invert Lanczos.

One sparse LU factorisation of ``K - σ M`` is made and reused by every Lanczos iteration (and
may be passed in, e.g. by the Craig–Bampton reduction that also solves with it).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from flexride.errors import FEModelError


@dataclass
class Modes:
    """Eigen solution ``K φ = ω² M φ``.

    Attributes
    ----------
    frequencies : numpy.ndarray
        Natural frequencies (Hz), ascending; rigid-body modes have (close to) zero.
    shapes : numpy.ndarray
        (n_dof, n_modes) mass-normalised mode shapes (φᵀ M φ = 1).
    """

    frequencies: np.ndarray
    shapes: np.ndarray

    @property
    def omega(self) -> np.ndarray:
        """Circular frequencies (rad/s)."""
        return 2.0 * np.pi * self.frequencies


class ShiftInvert:
    """Factorised ``K - σ M`` (SuperLU) usable as an ARPACK OPinv operator.

    Parameters
    ----------
    K, M : scipy.sparse matrix
        Stiffness and mass.
    sigma : float
        Shift (rad²/s²); negative for free–free models so that the matrix is non-singular.
    """

    def __init__(self, K: sp.spmatrix, M: sp.spmatrix, sigma: float):
        A = (K - sigma * M).tocsc() if sigma != 0.0 else sp.csc_matrix(K)
        self.sigma = float(sigma)
        self.n = A.shape[0]
        try:
            self.lu = spla.splu(A, permc_spec="COLAMD")
        except RuntimeError as exc:  # singular
            raise FEModelError(
                f"stiffness matrix is singular at shift {sigma:g} rad²/s² ({exc}); the model "
                "has mechanisms (unconnected parts or missing constraints)"
            ) from exc

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve ``(K - σ M) x = b`` for one or more right-hand sides."""
        return self.lu.solve(np.asarray(b, dtype=float))

    def operator(self) -> spla.LinearOperator:
        """ARPACK ``OPinv`` operator."""
        return spla.LinearOperator((self.n, self.n), matvec=self.solve, dtype=float)


def _mass_normalise(phi: np.ndarray, M) -> np.ndarray:
    mm = np.einsum("ij,ij->j", phi, M @ phi)
    return phi / np.sqrt(np.abs(mm))


def solve_modes(
    K: sp.spmatrix | np.ndarray,
    M: sp.spmatrix | np.ndarray,
    n_modes: int | None = None,
    f_max: float | None = None,
    sigma_hz: float = -1.0,
    factor: ShiftInvert | None = None,
    tol: float = 1e-10,
    dense_below: int = 1500,
) -> Modes:
    """Lowest natural modes of ``K φ = ω² M φ``.

    Parameters
    ----------
    K, M : sparse or dense matrix
        Stiffness and mass (symmetric; M positive definite or semi-definite with K).
    n_modes : int, optional
        Number of modes wanted (at least this many are returned when ``f_max`` is also set).
    f_max : float, optional
        Return all modes up to this frequency (Hz); the solver asks for more until it has them.
    sigma_hz : float
        Shift as a frequency (Hz); a negative value means ``σ = -(2π|sigma_hz|)²``, which
        makes ``K - σ M`` positive definite for a free–free model.
    factor : ShiftInvert, optional
        Existing factorisation of ``K - σ M`` (its σ is used).
    tol : float
        ARPACK tolerance.
    dense_below : int
        Use a dense solver for models with fewer DOFs.

    Returns
    -------
    Modes
        Frequencies (Hz) ascending and mass-normalised shapes.
    """
    n = K.shape[0]
    if n_modes is None and f_max is None:
        raise ValueError("give n_modes or f_max")
    if n <= dense_below:
        Kd = K.toarray() if sp.issparse(K) else np.asarray(K)
        Md = M.toarray() if sp.issparse(M) else np.asarray(M)
        w2, phi = la.eigh(0.5 * (Kd + Kd.T), 0.5 * (Md + Md.T))
        f = np.sqrt(np.abs(w2)) / (2 * np.pi) * np.sign(w2)
        keep = np.ones(n, dtype=bool)
        if f_max is not None:
            keep = f <= f_max
            if n_modes is not None:
                keep[: min(n_modes, n)] = True
        elif n_modes is not None:
            keep = np.arange(n) < n_modes
        return Modes(np.where(f > 0, f, 0.0)[keep], _mass_normalise(phi[:, keep], Md))

    if factor is None:
        sigma = -((2 * np.pi * sigma_hz) ** 2) if sigma_hz < 0 else (2 * np.pi * sigma_hz) ** 2
        factor = ShiftInvert(K, M, sigma)
    op = factor.operator()
    k = n_modes if n_modes is not None else 20
    k = int(min(max(k, 1), n - 2))
    while True:
        w2, phi = spla.eigsh(K, M=M, k=k, sigma=factor.sigma, which="LM", OPinv=op, tol=tol)
        order = np.argsort(w2)
        w2, phi = w2[order], phi[:, order]
        f = np.sqrt(np.abs(w2)) / (2 * np.pi)
        f[w2 < 0] = 0.0
        if f_max is None or f[-1] > f_max or k >= n - 2:
            break
        # estimate how many more are needed from the modal density so far
        k = int(min(n - 2, max(k + 10, np.ceil(k * 1.3 * (f_max / max(f[-1], 1e-3)) ** 1.0))))
    keep = np.ones(f.size, dtype=bool)
    if f_max is not None:
        keep = f <= f_max
        if n_modes is not None:
            keep[: min(n_modes, f.size)] = True
    phi = _mass_normalise(phi[:, keep], M)
    return Modes(f[keep], phi)

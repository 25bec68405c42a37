"""Modal assurance criterion (MAC) between mode shapes.

``MAC(a, b) = |aᴴ W b|² / ((aᴴ W a)(bᴴ W b))``: 1 for shapes that differ only by a factor
(of any size or sign), 0 for W-orthogonal shapes (Allemang, "The modal assurance criterion —
twenty years of use and abuse", Sound and Vibration 2003). With ``W = M`` mass-normalised modes
of one model give the identity matrix; measured shapes at sensors are compared with ``W = I``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from flexride.errors import FEModelError


def mac(phi_a: np.ndarray, phi_b: np.ndarray, weight: Any = None) -> np.ndarray:
    """MAC between the columns of ``phi_a`` and those of ``phi_b``.

    Parameters
    ----------
    phi_a : numpy.ndarray
        (n,) one shape or (n, p) shapes as columns (real or complex; any units, as long as
        ``phi_b`` has the same).
    phi_b : numpy.ndarray
        (n,) or (n, q) shapes at the same DOFs.
    weight : matrix, optional
        (n, n) symmetric positive (semi-)definite weighting (dense or sparse), e.g. the mass
        matrix; the identity when omitted.

    Returns
    -------
    numpy.ndarray
        (p, q) MAC values in [0, 1] (``p = 1`` or ``q = 1`` for a single shape); 0 where a
        shape has zero norm.

    Raises
    ------
    FEModelError
        If the shapes' numbers of DOFs (or the weight's size) differ.
    """
    a = _columns(phi_a)
    b = _columns(phi_b)
    if a.shape[0] != b.shape[0] or (weight is not None and weight.shape != (a.shape[0],) * 2):
        raise FEModelError(
            f"MAC needs shapes at the same DOFs: {a.shape[0]} and {b.shape[0]} rows"
            + ("" if weight is None else f", weight {weight.shape}")
        )
    wa = a if weight is None else weight @ a
    wb = b if weight is None else weight @ b
    num = np.abs(a.conj().T @ wb) ** 2
    da = np.real(np.einsum("ij,ij->j", a.conj(), wa))
    db = np.real(np.einsum("ij,ij->j", b.conj(), wb))
    den = np.outer(da, db)
    return np.divide(num, den, out=np.zeros_like(num, dtype=float), where=den > 0)


def _columns(phi: np.ndarray) -> np.ndarray:
    """``phi`` as a 2-D array of column shapes."""
    arr = np.asarray(phi)
    return arr[:, None] if arr.ndim == 1 else arr

"""Linear time-invariant second-order systems and their frequency responses.

A system is ``Ẍ = −K X − C Ẋ + B0 u + B1 u̇ + B2 ü`` with mass-normalised matrices (K in 1/s²,
C in 1/s, B0 in m/s² per input unit, B1 and B2 the same per input unit/s and /s²). Outputs are
``y = (−ω² P + G) X + D u`` in the frequency domain: P maps coordinates to the displacements
whose accelerations are wanted, G adds terms proportional to displacement (the gravity
component an accelerometer sees when it tilts), D a direct dependence on the input.

The frequency response is evaluated either directly, solving (−ω² I + jω C + K) X = B(ω) at
every frequency, or — faster — from one eigendecomposition of the state matrix
A = [[0, I], [−K, −C]] = R Λ R⁻¹: X(ω) = R_X diag(1/(jω − λ)) L_V B(ω) with L = R⁻¹, the
modal (closed-form) FRF. Both are exact; the tests compare them with analytic FRFs.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Modes", "OutputMap", "SecondOrderSystem", "input_matrix", "output_frf"]


@dataclass
class SecondOrderSystem:
    """Ẍ = −K X − C Ẋ + B0 u + B1 u̇ + B2 ü (mass-normalised).

    Attributes
    ----------
    K : numpy.ndarray
        (n, n) stiffness over mass (1/s²).
    C : numpy.ndarray
        (n, n) damping over mass (1/s).
    B0, B1, B2 : numpy.ndarray
        (n, m) input matrices for the input, its rate and its second derivative.
    """

    K: np.ndarray
    C: np.ndarray
    B0: np.ndarray
    B1: np.ndarray
    B2: np.ndarray

    @property
    def n(self) -> int:
        """Number of coordinates."""
        return int(self.K.shape[0])

    @property
    def m(self) -> int:
        """Number of inputs."""
        return int(self.B0.shape[1])

    def state_matrix(self) -> np.ndarray:
        """A = [[0, I], [−K, −C]], (2n, 2n) in 1/s."""
        n = self.n
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:, :n] = -self.K
        A[n:, n:] = -self.C
        return A

    def modes(self) -> Modes:
        """Eigendecomposition of the state matrix (see :class:`Modes`)."""
        lam, right = np.linalg.eig(self.state_matrix())
        left = np.linalg.solve(right, np.eye(right.shape[0], dtype=complex))
        return Modes(lam=lam, right=right, left=left)

    def frf_direct(self, f: np.ndarray) -> np.ndarray:
        """Displacement per unit input at frequencies ``f`` (Hz) by direct solution.

        Returns
        -------
        numpy.ndarray
            (n_f, n, m) complex, coordinate units per input unit.
        """
        w = 2.0 * np.pi * np.asarray(f, dtype=float)
        n = self.n
        D = (-(w**2)[:, None, None] * np.eye(n) + 1j * w[:, None, None] * self.C + self.K)
        return np.linalg.solve(D, input_matrix(self, w))

    def frf_modal(self, f: np.ndarray, modes: Modes | None = None) -> np.ndarray:
        """The same as :meth:`frf_direct` from the eigendecomposition (closed form)."""
        modes = modes or self.modes()
        w = 2.0 * np.pi * np.asarray(f, dtype=float)
        n = self.n
        q = np.einsum("kn,fnm->fkm", modes.left[:, n:], input_matrix(self, w))
        q = q / (1j * w[:, None, None] - modes.lam[None, :, None])
        return np.einsum("nk,fkm->fnm", modes.right[:n], q)


def input_matrix(sys: SecondOrderSystem, w: np.ndarray) -> np.ndarray:
    """B(ω) = B0 + jω B1 − ω² B2 at angular frequencies ``w`` (rad/s): (n_f, n, m)."""
    w = np.asarray(w, dtype=float)[:, None, None]
    return sys.B0[None] + 1j * w * sys.B1[None] - w**2 * sys.B2[None]


@dataclass
class Modes:
    """Eigenvalues and eigenvectors of a state matrix A = R diag(λ) L, L = R⁻¹.

    Attributes
    ----------
    lam : numpy.ndarray
        (2n,) eigenvalues (1/s); damped natural frequency |Im λ|/2π (Hz), damping ratio
        −Re λ/|λ|.
    right : numpy.ndarray
        (2n, 2n) right eigenvectors (columns): displacement part rows 0…n−1.
    left : numpy.ndarray
        (2n, 2n) left eigenvectors (rows), the inverse of ``right``.
    """

    lam: np.ndarray
    right: np.ndarray
    left: np.ndarray

    @property
    def frequency_hz(self) -> np.ndarray:
        """Undamped natural frequency |λ|/2π of each mode (Hz)."""
        return np.abs(self.lam) / (2.0 * np.pi)

    @property
    def damped_frequency_hz(self) -> np.ndarray:
        """Damped natural frequency |Im λ|/2π (Hz)."""
        return np.abs(self.lam.imag) / (2.0 * np.pi)

    @property
    def damping_ratio(self) -> np.ndarray:
        """−Re λ/|λ| (-); 1 for a zero eigenvalue."""
        mag = np.abs(self.lam)
        return np.where(mag > 0.0, -self.lam.real / np.where(mag > 0.0, mag, 1.0), 1.0)


@dataclass
class OutputMap:
    """Outputs y = (−ω² P + G) X + D u.

    Attributes
    ----------
    names : list of str
        One name per output row.
    P : numpy.ndarray
        (n_out, n) displacement rows whose second derivative is output.
    G : numpy.ndarray
        (n_out, n) rows proportional to displacement.
    D : numpy.ndarray
        (n_out, m) direct input rows.
    """

    names: list[str]
    P: np.ndarray
    G: np.ndarray
    D: np.ndarray


def output_frf(sys: SecondOrderSystem, out: OutputMap, f: np.ndarray,
               modes: Modes | None = None, method: str = "modal") -> np.ndarray:
    """Output per unit input at frequencies ``f`` (Hz): (n_f, n_out, m) complex.

    Parameters
    ----------
    sys : SecondOrderSystem
        The system.
    out : OutputMap
        The outputs.
    f : numpy.ndarray
        Frequencies (Hz).
    modes : Modes, optional
        A decomposition already made (modal method).
    method : {"modal", "direct"}
        Closed-form modal FRF or a direct solution at every frequency.
    """
    w = 2.0 * np.pi * np.asarray(f, dtype=float)
    hx = sys.frf_modal(f, modes) if method == "modal" else sys.frf_direct(f)
    rows = -(w**2)[:, None, None] * out.P[None] + out.G[None]
    return np.einsum("fon,fnm->fom", rows, hx) + out.D[None]

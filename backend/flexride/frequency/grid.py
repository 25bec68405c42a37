"""The frequency grid of an estimate: log-spaced over 0.1–80 Hz, denser around the damped
natural frequencies of the model's lightly damped modes.
"""

from __future__ import annotations

import numpy as np

from flexride.frequency.lti import Modes

__all__ = ["F_MAX", "F_MIN", "frequency_grid", "integration_weights"]

F_MIN = 0.1
"""Lower end of the grid (Hz)."""
F_MAX = 80.0
"""Upper end of the grid (Hz): the ISO 2631 weightings reach 80 Hz."""
#: log-spaced points over the whole band
N_LOG = 400
#: points per resonance, spread over ± RES_SPAN half-power bandwidths
N_RES = 21
RES_SPAN = 4.0
#: modes with a damping ratio above this get no extra points (their peaks are broad)
MAX_RES_DAMPING = 0.3


def frequency_grid(modes: Modes | None = None, f_min: float = F_MIN, f_max: float = F_MAX,
                   n_log: int = N_LOG) -> np.ndarray:
    """Sorted unique frequencies (Hz): ``n_log`` log-spaced points plus, for every mode with a
    damped frequency in the band and a damping ratio ζ below :data:`MAX_RES_DAMPING`,
    :data:`N_RES` points over f_d·(1 ± RES_SPAN·ζ) (the half-power bandwidth is 2ζf_d).

    Parameters
    ----------
    modes : Modes, optional
        Modes of the model; none gives the log-spaced grid only.
    f_min, f_max : float
        Band (Hz), 0 < f_min < f_max.
    n_log : int
        Number of log-spaced points.
    """
    parts = [np.geomspace(f_min, f_max, n_log)]
    if modes is not None:
        fd = modes.damped_frequency_hz
        zeta = modes.damping_ratio
        sel = (fd > f_min) & (fd < f_max) & (zeta < MAX_RES_DAMPING) & (modes.lam.imag > 0)
        span = np.linspace(-RES_SPAN, RES_SPAN, N_RES)
        for f0, z in zip(fd[sel], zeta[sel], strict=True):
            parts.append(f0 * (1.0 + max(z, 1e-3) * span))
    f = np.unique(np.concatenate(parts))
    return f[(f >= f_min) & (f <= f_max)]


def integration_weights(f: np.ndarray) -> np.ndarray:
    """Trapezoidal weights (Hz) on a sorted grid: ∫ g df ≈ Σ w_i g(f_i)."""
    f = np.asarray(f, dtype=float)
    w = np.zeros_like(f)
    d = np.diff(f)
    w[:-1] += 0.5 * d
    w[1:] += 0.5 * d
    return w

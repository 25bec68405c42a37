"""``linear_time_history``: the linear model's response to one given irregularity profile, by
FFT (the realisation the time-domain solver ran over, so both can be compared sample by sample:
what differs is nonlinearity and the frozen rail window, not the randomness of the profile).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from flexride.frequency.model import LinearModel
from flexride.frequency.response import _sub, select_channels
from flexride.track.profile import IrregularityProfile

__all__ = ["linear_time_history"]

#: Zero padding after the record (s): the slowest output-relevant modes decay within it.
PAD_S = 20.0


def linear_time_history(model: LinearModel, profile: IrregularityProfile, times: np.ndarray,
                        points: Sequence[str] | None = None, s_start: float = 0.0
                        ) -> dict[str, np.ndarray]:
    """Accelerations of the linear model running over ``profile`` from rest.

    Parameters
    ----------
    model : LinearModel
        The model (its speed V).
    profile : IrregularityProfile
        Rail irregularities (m); each wheelset w sees them at s_start + V·t + x_w, linearly
        interpolated and zero outside the grid, as in the kernel.
    times : numpy.ndarray
        Uniformly spaced output times (s).
    points : sequence of str, optional
        Points (default every car-body point).
    s_start : float
        Position of the vehicle centre at t = 0 (m).

    Returns
    -------
    dict of str to numpy.ndarray
        Acceleration (m/s²) per channel at ``times``, the system at rest (in its steady state)
        before the first sample.
    """
    t = np.asarray(times, dtype=float)
    dt = float(t[1] - t[0])
    nfft = int(2 ** np.ceil(np.log2(t.size + PAD_S / dt)))
    tt = t[0] + dt * np.arange(nfft)
    u = np.zeros((model.system.m, nfft))
    for w, x in enumerate(model.wheelset_x):
        rails = profile.sample(s_start + model.speed * tt + x)
        for c in range(4):
            u[4 * w + c] = rails[c]
    u[:, t.size:] = 0.0
    U = np.fft.rfft(u, axis=-1)
    f = np.fft.rfftfreq(nfft, dt)
    channels = select_channels(model, points)
    out = _sub(model.accelerations, channels)
    Y = _frf_times_input(model, out.P, out.G, out.D, f, U)
    y = np.fft.irfft(Y, nfft, axis=-1)[:, : t.size]
    return dict(zip(channels, y, strict=True))


def _frf_times_input(model: LinearModel, P: np.ndarray, G: np.ndarray, D: np.ndarray,
                     f: np.ndarray, U: np.ndarray) -> np.ndarray:
    """Σ_inputs H(f)·U(f) in modal form without the (n_f, n, m) FRF array (n_out, n_f)."""
    sys, modes = model.system, model.modes
    n = sys.n
    w = 2.0 * np.pi * f
    lv = modes.left[:, n:]
    q = (lv @ sys.B0) @ U + 1j * w * ((lv @ sys.B1) @ U) - w**2 * ((lv @ sys.B2) @ U)
    den = 1j * w[None, :] - modes.lam[:, None]
    eta = np.divide(q, den, out=np.zeros_like(q), where=np.abs(den) > 0.0)
    Y = -(w**2) * ((P @ modes.right[:n]) @ eta) + (G @ modes.right[:n]) @ eta + D @ U
    Y[:, 0] = 0.0
    return Y

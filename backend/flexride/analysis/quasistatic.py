"""Separation of the quasi-static part of car-body accelerations on curves.

On a curve the body-fixed lateral accelerometer sees the uncompensated centrifugal
acceleration (and the vertical one a small cant/curvature term) as a slowly varying offset that
follows the curvature ramps of the transitions. Ride-comfort indices describe the *vibration*
around it, so the quasi-static part is removed before comfort evaluation:

* EN 12299 and ISO 2631 do it through the band-limiting high pass of their weightings
  (0.4 Hz, second order), so their functions take the raw record;
* the Sperling index has no such filter in its filter form and, in its spectral form, would
  see the leakage of a large ramp into the lowest lines; :func:`analyze` therefore applies
  :func:`split_quasistatic` before the Sperling index, peak values of the dynamic part and the
  spectra.

Split (pinned, :data:`QUASISTATIC_DEFAULTS`): quasi-static part = 4th-order Butterworth low
pass at **0.3 Hz** applied forward and backward (zero phase; magnitude 1/(1 + (f/0.3)⁸), so the
quasi-static part is halved at 0.3 Hz), with an odd extension of 3/cutoff seconds at the ends
so that ramps continue smoothly. Dynamic part = record − quasi-static part (the two add up
exactly); it keeps 98.4 % of the amplitude at 0.5 Hz, the lower edge of the Sperling band, and
99.99 % at 1 Hz. (A cut-off at the 0.4 Hz of the ISO band limit would already take 14 % at
0.5 Hz.) A transition curve passed in a few seconds still leaves part of its corners in the
dynamic part, as it does in the standards' own band limitation.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Final, TypedDict

import numpy as np
from scipy import signal

from flexride.analysis._common import check_nyquist, check_rate, check_signal
from flexride.errors import AnalysisError

__all__ = ["QUASISTATIC_DEFAULTS", "QuasiStaticSplit", "remove_quasistatic", "split_quasistatic"]


class QuasiStaticDefaults(TypedDict):
    """Parameters of the quasi-static split: cut-off (Hz) and Butterworth order."""

    cutoff_hz: float
    order: int


#: Pinned defaults of the split.
QUASISTATIC_DEFAULTS: Final[QuasiStaticDefaults] = {"cutoff_hz": 0.3, "order": 4}


@dataclass
class QuasiStaticSplit:
    """Quasi-static and dynamic parts of a record (same unit as the record).

    Attributes
    ----------
    quasi_static : numpy.ndarray
        Low-passed part.
    dynamic : numpy.ndarray
        Record minus the quasi-static part.
    cutoff_hz : float
        Cut-off frequency of the low pass (Hz).
    order : int
        Butterworth order of each pass.
    method : str
        Description.
    """

    quasi_static: np.ndarray = field(metadata={"json": False})
    dynamic: np.ndarray = field(metadata={"json": False})
    cutoff_hz: float = 0.3
    order: int = 4
    method: str = ""


def split_quasistatic(
    x: np.ndarray,
    fs: float,
    *,
    cutoff_hz: float = QUASISTATIC_DEFAULTS["cutoff_hz"],
    order: int = QUASISTATIC_DEFAULTS["order"],
) -> QuasiStaticSplit:
    """Split a record into its quasi-static (low-passed) and dynamic parts.

    Parameters
    ----------
    x : array_like
        Acceleration (m/s²), shape ``(n,)`` or ``(m, n)``; at least 1/cutoff_hz seconds long.
    fs : float
        Sample rate in Hz (> 2 × cutoff).
    cutoff_hz : float
        Low-pass cut-off in Hz (default 0.3 Hz).
    order : int
        Butterworth order of each of the two passes (default 4).
    """
    fs = check_rate(fs)
    if not (cutoff_hz > 0.0):
        raise AnalysisError(f"cut-off must be positive (Hz), got {cutoff_hz!r}")
    if order != int(order) or int(order) < 1:  # int(order) alone would truncate 2.5 to 2
        raise AnalysisError(f"filter order must be an integer of at least 1, got {order!r}")
    check_nyquist(fs, cutoff_hz, f"a {cutoff_hz:g} Hz quasi-static low pass", factor=4.0)
    x = check_signal(x, fs, name="acceleration", min_duration=1.0 / cutoff_hz,
                     method=f"the quasi-static split at {cutoff_hz:g} Hz")
    sos = signal.butter(int(order), cutoff_hz, btype="low", fs=fs, output="sos")
    padlen = min(x.shape[-1] - 1, int(np.ceil(3.0 * fs / cutoff_hz)))
    qs = signal.sosfiltfilt(sos, x, axis=-1, padtype="odd", padlen=padlen)
    desc = (f"quasi-static part: Butterworth low pass, order {int(order)}, {cutoff_hz:g} Hz, "
            "forward-backward (zero phase); dynamic part = record − quasi-static part")
    return QuasiStaticSplit(quasi_static=qs, dynamic=x - qs, cutoff_hz=float(cutoff_hz),
                            order=int(order), method=desc)


def remove_quasistatic(
    x: np.ndarray,
    fs: float,
    *,
    cutoff_hz: float = QUASISTATIC_DEFAULTS["cutoff_hz"],
    order: int = QUASISTATIC_DEFAULTS["order"],
) -> np.ndarray:
    """The dynamic part of a record (see :func:`split_quasistatic`)."""
    return split_quasistatic(x, fs, cutoff_hz=cutoff_hz, order=order).dynamic

"""Calibrated default parameters of the car-body and bogie-frame models.

The car-body values below were produced by (paper Table 1 targets, 0.2 m elements)::

    flexride fe calibrate --targets 5.03,6.11,6.33,7.40,8.00,8.84 --element-size 0.2

and are used by the default model, so no calibration runs at build time. Re-run the command
(with your own ``--targets``) to recalibrate; it prints a dict to paste here.
"""

from __future__ import annotations

from flexride.fem.carbody import CarBodyParams
from flexride.fem.frame import FrameParams

#: Calibration variables of the default car body (m; fractions -).
CARBODY_CALIBRATED: dict[str, float] = {
    "floor_face": 3.0e-3,
    "floor_depth": 0.040,
    "wall_face": 2.5e-3,
    "wall_depth": 0.030,
    "roof_face": 2.0e-3,
    "roof_depth": 0.024,
    "end_face": 2.5e-3,
    "end_depth": 0.030,
    "beam_scale": 1.0,
    "nsm_underfloor": 0.35,
}

#: Paper Table 1: first six elastic car-body frequencies (Hz).
PAPER_TABLE1_HZ: tuple[float, ...] = (5.03, 6.11, 6.33, 7.40, 8.00, 8.84)


def default_carbody_params() -> CarBodyParams:
    """The calibrated default car-body parameters."""
    return CarBodyParams().with_values(**CARBODY_CALIBRATED)


def default_frame_params() -> FrameParams:
    """The default bogie-frame parameters."""
    return FrameParams()

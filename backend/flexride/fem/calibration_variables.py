"""The car body's calibration variables and their bounds: names only, no FE code.

Kept apart from :mod:`flexride.fem.calibration` (which needs SciPy and the FE model) so that
the scenario schema (``bodies.carbody.calibration.variables``) can list the allowed names from
the same source as the calibration itself.
"""

from __future__ import annotations

#: Calibration variables and their bounds (SI units: depths and face thicknesses of the
#: double-skin extrusions in m, ``beam_scale`` and ``nsm_underfloor`` dimensionless).
BOUNDS: dict[str, tuple[float, float]] = {
    "floor_depth": (0.020, 0.080),
    "wall_depth": (0.020, 0.080),
    "roof_depth": (0.015, 0.060),
    "end_depth": (0.020, 0.080),
    "floor_face": (1.5e-3, 4.0e-3),
    "wall_face": (1.5e-3, 4.0e-3),
    "roof_face": (1.5e-3, 4.0e-3),
    "end_face": (1.5e-3, 4.0e-3),
    "beam_scale": (0.5, 2.0),
    "nsm_underfloor": (0.10, 0.60),
}
#: Variables :func:`~flexride.fem.calibration.calibrate_carbody` and ``flexride fe
#: calibrate`` update when none are named.
DEFAULT_VARIABLES: tuple[str, ...] = (
    "floor_depth",
    "wall_depth",
    "roof_depth",
    "end_depth",
    "beam_scale",
    "nsm_underfloor",
)
#: Variables of the default car body's calibration (the keys of
#: :data:`flexride.fem.defaults.CARBODY_CALIBRATED`, a test checks it): those a scenario's
#: ``bodies.carbody.calibration`` updates when it names none.
DEFAULT_BODY_VARIABLES: tuple[str, ...] = (*DEFAULT_VARIABLES, "wall_face", "roof_face")


def least_budget(n_variables: int) -> int:
    """The least evaluation budget with which a calibration of ``n_variables`` variables
    takes a step: two least-squares iterations of one evaluation plus ``n_variables``
    finite-difference steps each, ``2 (n_variables + 1)``.
    """
    return 2 * (int(n_variables) + 1)

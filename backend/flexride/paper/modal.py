"""Table 1's modal analysis: the elastic modes of the car body the study's flexible runs use
(the default FE car body of ``flexride.fem``, built or loaded from the FE cache with the
flexible scenario's element size, reduction and cut-off).
"""

from __future__ import annotations

from typing import Any

from flexride.paper.plan import ReportOptions
from flexride.scenario.presets import load_preset

__all__ = ["car_body_modes"]

N_MODES = 12
"""Elastic modes listed (Table 1 has six)."""


def car_body_modes(options: ReportOptions) -> dict[str, Any]:
    """Frequencies and mode types of the car body's first elastic modes.

    Parameters
    ----------
    options : ReportOptions
        Its test overrides (e.g. a coarser mesh) apply, as for the runs.

    Returns
    -------
    dict
        ``frequencies_hz`` and ``classification`` (first :data:`N_MODES` elastic modes),
        ``element_size_m``, ``cutoff_hz``, ``method``, ``n_full_dof``, ``mass`` (mass
        properties against the vehicle parameters).
    """
    from flexride.fem.flexible import build_flexible_body

    scenario = load_preset("paper-metro", {**dict(options.overrides),
                                           "bodies.carbody.model": "flexible"})
    settings = scenario.bodies.carbody
    fb = build_flexible_body("carbody", scenario.vehicle, method=settings.reduction,
                             cutoff_hz=settings.cutoff_hz, damping_ratio=settings.damping_ratio,
                             element_size=settings.element_size_m, name="carbody", x_ref=0.0)
    freqs = [float(f) for f in fb.body.elastic_frequencies[:N_MODES]]
    report = fb.report
    return {"frequencies_hz": freqs, "classification": list(report.classification[:N_MODES]),
            "element_size_m": settings.element_size_m, "cutoff_hz": settings.cutoff_hz,
            "method": settings.reduction, "n_full_dof": report.n_full_dof,
            "mass": report.mass}

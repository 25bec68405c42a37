"""A summary quantity against the running speed over several runs (the paper's Fig. 21)."""

from __future__ import annotations

from collections.abc import Sequence

from flexride.analysis.statistics import LinearFit, regress_on_speed
from flexride.analysis.summary import Summary
from flexride.errors import AnalysisError

__all__ = ["regress_summaries"]


def regress_summaries(
    summaries: Sequence[Summary], point: str, direction: str, quantity: str = "peak"
) -> LinearFit:
    """Linear fit of one summary quantity against the running speed (km/h) over several runs.

    E.g. the paper's Fig. 21: ``regress_summaries(runs, "PR", "z", "peak")``.

    Parameters
    ----------
    summaries : sequence of Summary
        One per speed (each with ``run["speed_kmh"]``).
    point, direction, quantity : str
        See :meth:`Summary.value`.
    """
    speeds, values = [], []
    for s in summaries:
        v_kmh = s.run.get("speed_kmh")
        if v_kmh is None:
            raise AnalysisError("a summary has no running speed (run['speed_kmh'])")
        speeds.append(float(v_kmh))
        values.append(s.value(point, direction, quantity))
    unit = {"sperling": "-", "sperling_alternative": "-", "n_mv": "-"}.get(quantity, "m/s^2")
    return regress_on_speed(speeds, values, speed_unit="km/h", value_unit=unit)

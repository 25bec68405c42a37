"""Shared pieces of the claim modules: condition and model names, per-point values, orderings
and slopes against speed.
"""

from __future__ import annotations

from collections.abc import Sequence

from flexride.paper import measures
from flexride.paper.data import StudyData, speed_series

RS, RC, CO, SE = "random-straight", "random-curve", "corrugation", "settlement"
FLEX, RIGID = "flexible", "rigid"
THREE = ("PR", "PFB", "PC")
SIX = ("PR", "PFB", "PRB", "PLA", "PRA", "PC")
DIRS = {"z": "vertical", "y": "lateral"}


def at_points(data: StudyData, condition: str, speed: float, body: str,
              points: Sequence[str], direction: str, quantity: str) -> dict[str, float]:
    """Mean of a quantity at each point (its unit)."""
    return {p: data.mean(condition, speed, body, p, direction, quantity) for p in points}


def largest(values: dict[str, float]) -> str:
    """Name of the largest value."""
    return max(values, key=lambda k: values[k])


def smallest(values: dict[str, float]) -> str:
    """Name of the smallest value."""
    return min(values, key=lambda k: values[k])


def close(a: float, b: float, rel: float) -> bool:
    """|a/b − 1| ≤ rel."""
    return abs(a / b - 1.0) <= rel


def slopes(data: StudyData, condition: str, body: str, points: Sequence[str],
           directions: Sequence[str], quantity: str) -> dict[str, float]:
    """Slope of the least-squares line of a quantity against speed (unit per km/h), by
    ``point.direction``; needs two speeds (else NotComparable).
    """
    speeds = data.need_speeds(condition, 2)
    return {f"{p}.{d}": measures.line_fit(
        speeds, speed_series(data, condition, body, p, d, quantity, speeds))["slope"]
        for p in points for d in directions}


def table(values: dict[str, float], digits: int = 3) -> str:
    """``PR 0.12, PFB 0.10`` text of per-key values."""
    return ", ".join(f"{k} {v:.{digits}g}" for k, v in values.items())

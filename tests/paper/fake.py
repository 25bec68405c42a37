"""Hand-made run records for judging claims without running the solver."""

from __future__ import annotations

from typing import Any


def record(condition: str, speed: float, body: str = "flexible", seed: int | None = None,
           values: dict[tuple[str, str], dict[str, float]] | None = None,
           correlations: list[dict[str, Any]] | None = None) -> dict[str, Any]:
    """A run record whose summary holds ``values[(point, direction)]`` = {"peak", "rms",
    "sperling", "sperling_filter"} (m/s², -)."""
    points: dict[str, Any] = {}
    for (p, d), v in (values or {}).items():
        points.setdefault(p, {"directions": {}})["directions"][d] = {
            "peaks": {"max_abs": v.get("peak", 0.0), "rms": v.get("rms", 0.0)},
            "sperling": {"value": v["sperling"]} if "sperling" in v else None,
            "sperling_alternative": ({"value": v["sperling_filter"]}
                                     if "sperling_filter" in v else None),
            "iso2631": {}}
    return {"spec": {"condition": condition, "speed_kmh": speed, "body": body, "seed": seed,
                     "cutoff_hz": 40.0 if body == "flexible" else None},
            "summary": {"points": points}, "correlations": correlations or []}

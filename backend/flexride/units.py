"""Unit conversions used across flexride (SI inside; km/h only at the edges, in ``*_kmh``)."""

from __future__ import annotations

KMH_PER_MPS = 3.6
"""km/h in one m/s."""


def kmh_to_mps(speed_kmh: float) -> float:
    """Speed in m/s of ``speed_kmh`` (km/h)."""
    return float(speed_kmh) / KMH_PER_MPS


def mps_to_kmh(speed_mps: float) -> float:
    """Speed in km/h of ``speed_mps`` (m/s)."""
    return float(speed_mps) * KMH_PER_MPS

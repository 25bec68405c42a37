"""What the paper states, as data: the numbers of its tables and the facts its findings name.

Source: ``reference/paper-flexible-metro-ride-comfort.md`` (the paper), read with
``DESIGN.md`` §5 (the paper's case). Only what the paper prints is here; what flexride assumes
where the paper is silent lives in :mod:`flexride.scenario.presets`.
"""

from __future__ import annotations

TABLE1_HZ: tuple[float, ...] = (5.03, 6.11, 6.33, 7.40, 8.00, 8.84)
"""Table 1: natural frequencies of the car body's first six elastic modes (Hz)."""

TABLE2: dict[str, tuple[float, float, float]] = {
    "sperling_z": (1.76, 1.71, 0.035),
    "rms_z": (1.77, 1.69, 0.065),
    "sperling_y": (1.46, 1.45, 0.041),
    "rms_y": (1.63, 1.62, 0.043),
}
"""Table 2: (flexible model, rigid model, printed difference as a fraction) per index.

The paper does not say at which speed or point; its §3 figures are at PC on straight track.
The printed differences do not follow from the printed values (1.76/1.71 is +2.9 %, not
+3.5 %); the "RMS index" has no unit.
"""

FIG10_PEAKS_HZ: tuple[float, ...] = (1.0, 6.3, 8.0, 17.6, 89.2)
"""§5.1, Fig. 10: the five peak frequencies of the vertical acceleration at PR, 80 km/h (Hz)."""

FIG12_LATERAL_HZ = 0.95
"""§5.1, Fig. 12: main frequency of the lateral accelerations (Hz), the car body's rigid mode."""

FIG25_BANDS_HZ: tuple[tuple[float, float], ...] = ((0.0, 2.5), (6.0, 9.0))
"""§8, Fig. 25: bands holding the energy of the vertical acceleration at PRB (Hz)."""

FIG26_PR_LAG_S = -0.57
"""§8, Fig. 26: lag of the maximum of the cross-correlation (PRB, PR) at 80 km/h (s)."""

FIG26_PR_MAX = 3523.0
"""§8, Fig. 26: value of that maximum (raw correlation, unit not given)."""

SPERLING_LIMIT = 2.5
"""The "ruled value in relevant code" the paper's Sperling indices stay below: taken as 2.5
(GB 5599 "excellent"; metro vehicles are usually required to stay below it). The paper names no
number."""

EXAMPLE_SPEED_KMH = 80.0
"""The speed of the paper's detailed examples (Figs. 9–12, 15–16, 18, 24–26)."""

CONDITION_TITLES: dict[str, str] = {
    "random-straight": "rail random irregularity, straight (conditions 1–4)",
    "random-curve": "rail random irregularity, curve (conditions 5–8)",
    "corrugation": "short-wave excitation (corrugation), straight (conditions 9–12)",
    "settlement": "long-wave excitation (settlement), straight (conditions 13–16)",
}
"""Table 3's conditions, by the key of :data:`flexride.scenario.presets.PAPER_CONDITIONS`."""

PAPER_POINTS_FIG8 = ("PR", "PFB", "PC")
"""Fig. 8: the three points of §5–§7 (the paper's PB is flexride's PFB)."""

PAPER_POINTS_FIG23 = ("PR", "PFB", "PRB", "PLA", "PRA", "PC")
"""Fig. 23: the six points of §8."""

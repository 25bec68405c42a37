"""Built-in studies: the paper's Table 3 matrix and its rigid-vs-flexible comparison (Table 2).

Each preset is the request body it stands for (``POST /api/v1/studies`` with
``{"preset": NAME}``); fields given with the preset replace the preset's (e.g. a shorter
``overrides: {"duration_s": 2, "distance_m": null}`` for a quick look).
"""

from __future__ import annotations

from typing import Any

from flexride.errors import ScenarioError
from flexride.scenario.presets import PAPER_CONDITIONS, PAPER_SPEEDS_KMH

STUDY_PRESETS: dict[str, dict[str, Any]] = {
    "paper-table3": {
        "name": "paper-table3",
        "description": "Paper Table 3: four line/excitation conditions (random irregularity on "
        "straight track and on an R = 800 m curve, corrugation, settlement) at 50, 60, 70 and "
        "80 km/h, 16 jobs, with the paper's model: car body and bogie frames flexible, each "
        "keeping the elastic modes its excitation drives (cutoff: follow; 70 Hz for the "
        "corrugation). The irregularity samples are the presets' (seed 1), the same as the "
        "rigid runs of paper-table3-flexible-vs-rigid; give body_models ['rigid'] for the "
        "rigid model.",
        "base": {"preset": "paper-metro"},
        "conditions": list(PAPER_CONDITIONS),
        "speeds_kmh": [float(v) for v in PAPER_SPEEDS_KMH],
        "body_models": ["flexible"],
    },
    "paper-table2": {
        "name": "paper-table2",
        "description": "Paper Table 2: flexible against rigid car body and frames, random "
        "irregularity on straight track at 80 km/h (Sperling and rms indices at every point).",
        "base": {"preset": "paper-metro"},
        "conditions": ["random-straight"],
        "speeds_kmh": [80.0],
        "body_models": ["rigid", "flexible"],
    },
    "paper-table3-flexible-vs-rigid": {
        "name": "paper-table3-flexible-vs-rigid",
        "description": "The 16 conditions of paper Table 3, each with rigid and with flexible "
        "car body and frames (32 jobs): Table 2's comparison over all conditions and speeds.",
        "base": {"preset": "paper-metro"},
        "conditions": list(PAPER_CONDITIONS),
        "speeds_kmh": [float(v) for v in PAPER_SPEEDS_KMH],
        "body_models": ["rigid", "flexible"],
    },
    "paper-report": {
        "name": "paper-report",
        "description": "The paper reproduced, as `flexride paper report` does it (docs/paper.md):"
        " Table 3's 16 conditions rigid and flexible (96 runs: five realisations of the "
        "random conditions, or seeds N; quick: 2 speeds, shorter stretches, one realisation, "
        "16 runs), each evaluated"
        " over its stated section; when all have finished the service builds the report "
        "(index.html with every table, figure and claim beside the paper's, summary.json). "
        "Only quick and seeds may be given.",
        "quick": False,
    },
}


def study_preset(name: str) -> dict[str, Any]:
    """The request body of study preset ``name`` (a copy).

    Raises
    ------
    ScenarioError
        Unknown name (the message lists the presets).
    """
    import copy

    if name not in STUDY_PRESETS:
        raise ScenarioError(
            f"preset: unknown study preset {name!r}; available: {', '.join(STUDY_PRESETS)}"
        )
    return copy.deepcopy(STUDY_PRESETS[name])

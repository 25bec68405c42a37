"""Built-in studies: the paper's Table 3 matrix, its rigid-vs-flexible comparison (Table 2),
its element-size pre-calculation (Fig. 4) and the whole paper report.

Each preset is the request body it stands for (``POST /api/v1/studies`` with
``{"preset": NAME}``); fields given with the preset replace the preset's (e.g. a shorter
``overrides: {"duration_s": 2, "distance_m": null}`` for a quick look).
"""

from __future__ import annotations

from typing import Any

from flexride.errors import ScenarioError
from flexride.scenario.presets import PAPER_CONDITIONS, PAPER_SPEEDS_KMH, SMOOTH_CONDITION

MESH_SIZES_M: tuple[float, ...] = (0.5, 0.4, 0.3, 0.2, 0.15, 0.1)
"""Car-body element sizes of the mesh-convergence study (m): around the paper's 0.2 m, the
finest within the service's default FE limit (0.1 m: about 120,000 degrees of freedom)."""
MESH_SPEED_KMH = 80.0
"""Speed of the mesh-convergence study (km/h): the paper's example speed."""

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
    "mesh-convergence": {
        "name": "mesh-convergence",
        "description": "The paper's element-size pre-calculation (section 2.1, Fig. 4) with a "
        "verdict: the flexible vehicle (car body and frames) at 80 km/h on smooth straight track "
        "(as the paper) and on the random straight track, with the car body meshed at 0.5, 0.4, "
        "0.3, 0.2, 0.15 and 0.1 m (12 jobs; the frames keep their mesh). The study's "
        "mesh_convergence table gives the air-spring forces, the first elastic frequencies and "
        "the comfort indices against element size, with the observed order, the extrapolated "
        "value and the GCI of the three finest meshes, and judges the paper's claim (the force "
        "grows with the element; 0.2 m adequate). Each FE body is built once (cached); sizes "
        "beyond the service's FE limit (FLEXRIDE_MAX_FE_DOFS) are refused before the study "
        "starts, with the smallest admissible size. Give parameters to choose other sizes, or "
        "the path bodies.frames.element_size_m for the frames.",
        "base": {"preset": "paper-metro"},
        "conditions": [SMOOTH_CONDITION, "random-straight"],
        "speeds_kmh": [MESH_SPEED_KMH],
        "body_models": ["flexible"],
        "parameters": [{"path": "bodies.carbody.element_size_m",
                        "values": list(MESH_SIZES_M)}],
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

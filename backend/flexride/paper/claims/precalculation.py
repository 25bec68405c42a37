"""Claims of §2.1: the element-size pre-calculation (Fig. 4), judged on the report's runs of
the flexible vehicle at several car-body element sizes (:mod:`flexride.paper.mesh`, the rules of
:mod:`flexride.study.mesh_verdict`).
"""

from __future__ import annotations

from flexride.paper.claims import reasons
from flexride.paper.claims.base import Claim
from flexride.paper.data import NotComparable, StudyData
from flexride.paper.judge import Value, holds
from flexride.paper.mesh import mesh_tables, smooth_table
from flexride.study.mesh_verdict import ADEQUATE_WITHIN, GROWTH_FLOOR, REFERENCE_SIZE_M


def _grows(data: StudyData) -> Value:
    table = smooth_table(data)
    claim = table["claim"]
    if claim["grows_holds"] is None:
        raise NotComparable("no air-spring force of the smooth-track runs above the resolution "
                            f"on meshes from {REFERENCE_SIZE_M:g} m up")
    forces = {r["key"]: r["values"] for r in table["rows"] if r["group"] == "force"}
    return Value(holds=claim["grows_holds"],
                 values={"sizes_m": table["sizes_m"], "force_n": forces,
                         "coarsest_over_reference": claim["coarsest_over_reference"]},
                 words=claim["text"] + " (smooth track)")


def _adequate(data: StudyData) -> Value:
    tables = mesh_tables(data)
    verdicts = {t["group"].get("condition"): t["claim"] for t in tables}
    if any(c["adequate"] is None for c in verdicts.values()):
        raise NotComparable(f"{REFERENCE_SIZE_M:g} m is not among the pre-calculation's "
                            "sizes, or no quantity is above the resolution")
    return Value(holds=all(c["adequate"] for c in verdicts.values()),
                 values={c: v["reference_within"] for c, v in verdicts.items()},
                 words="; ".join(f"{c}: {v['text']}" for c, v in verdicts.items()))


def precalculation() -> list[Claim]:
    """§2.1 and Fig. 4: the force grows with the element size; 0.2 m is adequate."""
    return [
        Claim(id="s2.fig4.grows", source="§2.1, Fig. 4",
              statement="The secondary suspension force is divergent (increases sharply) with "
              "the increase of the element size (smooth track)",
              paper="grows with element size",
              rule="on the smooth track every air spring's force above the resolution "
              f"(largest value; rms and largest dynamic value) rises from {REFERENCE_SIZE_M:g} m "
              f"with every coarser mesh, by at least {100 * GROWTH_FLOOR:g} % to the coarsest",
              compute=_grows, judge=holds, reason=reasons.MESH_GROWTH, figure="fig4"),
        Claim(id="s2.fig4.adequate", source="§2.1",
              statement=f"An element size of {REFERENCE_SIZE_M:g} m is adequate for accuracy "
              "and efficiency", paper=f"{REFERENCE_SIZE_M:g} m adequate",
              rule=f"the {REFERENCE_SIZE_M:g} m mesh within {100 * ADEQUATE_WITHIN:g} % of the "
              "converged estimate of every quantity above the resolution (air-spring forces, "
              "first three frequencies, comfort at PC, PFB, PR) on both tracks",
              compute=_adequate, judge=holds, reason=reasons.MESH_ADEQUATE, figure="fig4"),
    ]

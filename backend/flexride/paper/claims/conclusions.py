"""Claims of §9's conclusions that span conditions: vertical against lateral Sperling indices,
the limit, and the sensitivity to long- and short-wave excitation.
"""

from __future__ import annotations

from flexride.paper.claims import reasons
from flexride.paper.claims.base import Claim
from flexride.paper.claims.common import CO, DIRS, FLEX, RC, RS, SE, THREE, table
from flexride.paper.data import NotComparable, StudyData
from flexride.paper.judge import Value, holds
from flexride.paper.reference import SPERLING_LIMIT

__all__ = ["conclusions"]


def _cases(data: StudyData, conditions: tuple[str, ...]) -> dict[str, dict[str, float]]:
    out = {}
    for cond in conditions:
        for v in data.speeds(cond):
            for p in THREE:
                try:
                    out[f"{cond} {v:g} {p}"] = {d: data.mean(cond, v, FLEX, p, d, "sperling")
                                                for d in DIRS}
                except NotComparable:
                    continue
    if not out:
        raise NotComparable("no runs with Sperling indices in this study")
    return out


def _vertical_mostly(data: StudyData) -> Value:
    cases = _cases(data, (RS, RC, SE))
    share = sum(c["z"] > c["y"] for c in cases.values()) / len(cases)
    return Value(holds=share >= 0.75, values={"share": share, "n": len(cases)},
                 words=f"vertical > lateral in {share:.0%} of {len(cases)} (condition, speed, "
                 "point) cases")


def _all_below(data: StudyData) -> Value:
    cases = _cases(data, (RS, RC, CO, SE))
    top_key = max(cases, key=lambda k: max(cases[k].values()))
    top = max(cases[top_key].values())
    return Value(holds=top < SPERLING_LIMIT, values={"largest": top, "where": top_key},
                 words=f"largest Sperling index {top:.2f} ({top_key})")


def _long_short(data: StudyData) -> Value:
    rows = {}
    for v in data.speeds(SE):
        try:
            rows[f"{v:g}"] = {c: max(data.mean(c, v, FLEX, p, "z", "sperling") for p in THREE)
                              for c in (SE, RS, CO)}
        except NotComparable:
            continue
    if not rows:
        raise NotComparable("needs settlement, random-straight and corrugation at one speed")
    ok = all(r[SE] > r[RS] > r[CO] for r in rows.values())
    return Value(holds=ok, values={"largest_vertical_sperling": rows},
                 words="; ".join(f"{v} km/h: {table(r)}" for v, r in rows.items()))


def conclusions() -> list[Claim]:
    """§9 conclusions 3 and 4."""
    return [
        Claim(id="s9.c3.vertical-above-lateral", source="§9 conclusion 3",
              statement="Under different conditions the vertical Sperling indices are almost "
              "all larger than the lateral ones", paper="vertical > lateral (almost always)",
              rule="vertical > lateral in ≥ 75 % of (condition, speed, point) cases: random "
              "straight and curve, settlement; PR, PFB, PC; flexible",
              compute=_vertical_mostly, judge=holds, reason=reasons.LATERAL_INPUTS,
              figure="fig-sperling"),
        Claim(id="s9.c3.below-limit", source="§9 conclusion 3",
              statement="With the adopted parameters all Sperling indices are less than the "
              "ruled value", paper=f"< {SPERLING_LIMIT}",
              rule=f"every Sperling index of every condition < {SPERLING_LIMIT} (flexible)",
              compute=_all_below, judge=holds, reason=reasons.SETTLEMENT,
              figure="fig-sperling"),
        Claim(id="s9.c4.long-vs-short-wave", source="§9 conclusion 4",
              statement="Ride comfort is very sensitive to long-wave and not sensitive to "
              "short-wave excitation", paper="settlement > random > corrugation",
              rule="largest vertical Sperling index (PR, PFB, PC): settlement > random "
              "irregularity (straight) > corrugation, at every speed", compute=_long_short,
              judge=holds, reason=reasons.CORRUGATION, figure="fig-sperling"),
    ]

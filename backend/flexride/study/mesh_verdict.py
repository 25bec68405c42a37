"""How a mesh-convergence table is judged and told: which quantities are too small to judge,
the paper's Fig. 4 claim (the secondary suspension force grows as the element grows; 0.2 m is
adequate) and the table as text.

Resolutions (a quantity below them is reported, not judged — on a smooth track the dynamic
forces and accelerations are numerical and parametric noise at the level of 10⁻⁵ of the static
load, the lateral air-spring forces a static 30–40 N from the meshes' small asymmetries, and a
relative change of such a quantity says nothing the engineer would act on):

* an air-spring force row whose every value is below :data:`FORCE_RESOLUTION` times the static
  air-spring load of the table (its largest ``max_abs`` value);
* an rms acceleration below :data:`RMS_RESOLUTION_M_S2` on every mesh, a Sperling index below
  :data:`SPERLING_RESOLUTION` on every mesh ("just noticeable" on Sperling's scale is 1).
"""

from __future__ import annotations

import itertools
from typing import Any

from flexride.scenario.bodies import BodyModel

__all__ = ["ADEQUATE_WITHIN", "GROWTH_FLOOR", "REFERENCE_SIZE_M", "format_table",
           "mark_negligible", "paper_claim"]

REFERENCE_SIZE_M: float = float(BodyModel.model_fields["element_size_m"].default)
"""The element size judged (m): the scenarios' default, the paper's 0.2 m."""
ADEQUATE_WITHIN = 0.05
"""A mesh is adequate for a quantity within this relative distance of its converged estimate
(-): the 5 % an engineer accepts for a design load or a comfort index."""
GROWTH_FLOOR = 0.01
"""The least rise (-) from the reference mesh to the coarsest that counts as growth: the paper's
force "increases sharply"; 1 % is far below sharp and above the runs' numerical noise."""
FORCE_RESOLUTION = 1.0e-3
"""Air-spring forces below this fraction of the static load are not judged (-): a tenth of a
per cent, finer than an air spring's load is known (its pressure is read to about 1 %)."""
RMS_RESOLUTION_M_S2 = 1.0e-3
"""Rms accelerations below this are not judged (m/s²): a hundredth of what people notice."""
SPERLING_RESOLUTION = 1.0
"""Sperling indices below this are not judged (-): "just noticeable" is 1."""


def _largest(row: dict[str, Any]) -> float:
    got = [abs(v) for v in row["values"] if v is not None]
    return max(got) if got else 0.0


def mark_negligible(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """Set each row's ``negligible``: why it is below the resolution (module docs), or None.

    Returns
    -------
    list of dict
        ``rows``, each with ``negligible`` set.
    """
    static = max((_largest(r) for r in rows
                  if r["group"] == "force" and r["key"].endswith(".z.max_abs")), default=0.0)
    for r in rows:
        top, why = _largest(r), None
        if r["group"] == "force" and static and top < FORCE_RESOLUTION * static:
            why = (f"below {FORCE_RESOLUTION:g} of the static air-spring load "
                   f"({static / 1000:.1f} kN) on every mesh")
        elif r["unit"] == "m/s^2" and top < RMS_RESOLUTION_M_S2:
            why = f"below {RMS_RESOLUTION_M_S2:g} m/s² on every mesh"
        elif r["key"].endswith(".sperling") and top < SPERLING_RESOLUTION:
            why = f"below {SPERLING_RESOLUTION:g} (just noticeable) on every mesh"
        r["negligible"] = why
    return rows


def _grows(sizes: list[float], values: list[float | None]) -> bool | None:
    """Every coarser mesh from the reference size on gives a larger value, and the coarsest
    at least :data:`GROWTH_FLOOR` more than the reference (None: fewer than two such meshes).
    """
    got = [v for h, v in zip(sizes, values, strict=True)
           if h >= REFERENCE_SIZE_M - 1e-12 and v is not None]
    if len(got) < 2:
        return None
    rising = all(b > a for a, b in itertools.pairwise(got))
    return rising and got[-1] > (1.0 + GROWTH_FLOOR) * got[0]


def _ratio(sizes: list[float], values: list[float | None]) -> float | None:
    v = dict(zip(sizes, values, strict=True))
    ref, coarse = v.get(REFERENCE_SIZE_M), v.get(sizes[-1])
    if not ref or coarse is None or sizes[-1] <= REFERENCE_SIZE_M:
        return None
    return coarse / ref


def paper_claim(sizes: list[float], rows: list[dict[str, Any]]) -> dict[str, Any]:
    """The paper's claim (§2.1, Fig. 4) judged on one table's rows that are not negligible.

    The claim has two parts: the secondary suspension force "is divergent (increases
    sharply) with the increase of the element size", and 0.2 m is adequate.

    Returns
    -------
    dict
        ``grows``: ``[n, of]``, the force rows that grow (monotonically, by at least
        :data:`GROWTH_FLOOR`) from the reference size to the coarsest mesh, of those judged;
        ``grows_holds``: all of them grow (None: none judged); ``coarsest_over_reference``:
        the largest ratio of the coarsest mesh's value to the reference's over the judged force
        rows; ``reference_within``: the largest |relative distance| of the reference mesh
        from the converged estimates over the judged force rows and over all judged rows
        (``{"force", "all"}``, -; None when the reference size is not among the sizes);
        ``adequate``: that distance is at most :data:`ADEQUATE_WITHIN` for all (None: not
        judged); ``negligible``: the rows not judged; ``text``: the verdict in words.
    """
    judged = [r for r in rows if not r.get("negligible")]
    force = [r for r in judged if r["group"] == "force"]
    grow = [g for g in (_grows(sizes, r["values"]) for r in force) if g is not None]
    ratios = [x for x in (_ratio(sizes, r["values"]) for r in force) if x is not None]

    def worst(selected: list[dict[str, Any]]) -> float | None:
        devs = [abs(r["at_reference"]) for r in selected if r["at_reference"] is not None]
        return max(devs) if devs else None

    within = {"force": worst(force), "all": worst(judged)}
    claim: dict[str, Any] = {
        "grows": [sum(grow), len(grow)], "grows_holds": all(grow) if grow else None,
        "coarsest_over_reference": max(ratios) if ratios else None,
        "reference_within": within,
        "adequate": None if within["all"] is None else within["all"] <= ADEQUATE_WITHIN,
        "negligible": [r["key"] for r in rows if r.get("negligible")]}
    claim["text"] = _claim_text(claim, sizes, bool(force))
    return claim


def _claim_text(claim: dict[str, Any], sizes: list[float], any_force: bool) -> str:
    n, of = claim["grows"]
    parts = []
    if of:
        ratio = claim["coarsest_over_reference"]
        how = (f" (the coarsest, {sizes[-1]:g} m, at most {ratio:.3f}× the "
               f"{REFERENCE_SIZE_M:g} m value)" if ratio is not None else "")
        parts.append(f"the air-spring force grows with the element size in {n} of {of} "
                     f"judged rows{how}")
    elif any_force:
        parts.append(f"no mesh coarser than {REFERENCE_SIZE_M:g} m: growth not judged")
    else:
        parts.append("no air-spring force above the resolution: growth not judged")
    w = claim["reference_within"]
    if w["all"] is None:
        parts.append(f"{REFERENCE_SIZE_M:g} m is not among the sizes, or no row is large "
                     "enough to judge: adequacy not judged")
    else:
        verdict = "adequate" if claim["adequate"] else "not adequate"
        force = (f"{100 * w['force']:.1f} % for the forces, " if w["force"] is not None
                 else "")
        parts.append(f"{REFERENCE_SIZE_M:g} m is {verdict} ({100 * ADEQUATE_WITHIN:g} % rule): "
                     f"at most {force}{100 * w['all']:.1f} % for any quantity from its "
                     "converged estimate")
    if claim["negligible"]:
        parts.append(f"{len(claim['negligible'])} rows below the resolution, not judged")
    return "; ".join(parts)


def _cell(v: float | None, unit: str) -> str:
    if v is None:
        return f"{'–':>10}"
    digits = 4 if unit in ("Hz", "-") else 3
    return f"{v:10.{digits}g}"


def format_table(table: dict[str, Any]) -> str:
    """A readable text table of one mesh-convergence table: each quantity per element size,
    the observed order, the converged estimate, its band and the reference mesh's distance
    from it; rows below the resolution marked; the claim's verdict last.
    """
    sizes = table["sizes_m"]
    group = ", ".join(f"{k}={v}" for k, v in table["group"].items())
    head = "".join(f"{h:>8g} m " for h in sizes)
    ref = table["reference_size_m"]
    lines = [f"{table['body']} element size ({group})",
             f"{'quantity':<44} {'unit':<6}{head} {'order':>6} {'converged':>10} "
             f"{'band %':>7} {f'{ref:g} m vs it':>12}"]
    for r in table["rows"]:
        e = r["estimate"] or {}
        order = e.get("order")
        mark = "~" if e.get("oscillatory") else ("?" if e and not e.get("reliable") else " ")
        at, band = r["at_reference"], e.get("band")
        tail = (f" {'–' if order is None else f'{order:5.2f}':>6}{mark}"
                + _cell(e.get("converged"), r["unit"])
                + f" {'–' if band is None else f'{100 * band:6.2f}':>7}"
                + f" {'–' if at is None else f'{100 * at:+.2f} %':>12}")
        if r.get("negligible"):
            tail = f"  (not judged: {r['negligible']})"
        lines.append(f"{r['label'][:44]:<44} {r['unit']:<6}"
                     + "".join(_cell(v, r["unit"]) for v in r["values"]) + tail)
    lines.append("~ oscillatory, ? order below 0.5: converged = the finest mesh's value, band = "
                 "the spread of the fine meshes; else Richardson's value and the GCI")
    lines.append(f"verdict: {table['claim']['text']}")
    return "\n".join(lines)

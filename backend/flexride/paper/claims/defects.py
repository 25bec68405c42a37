"""Claims of §6 (short-wave excitation: corrugation) and §7 (long-wave excitation:
settlement).
"""

from __future__ import annotations

import itertools

from flexride.paper import measures
from flexride.paper.claims import reasons
from flexride.paper.claims.base import Claim
from flexride.paper.claims.common import CO, FLEX, RS, SE, THREE, at_points, slopes, table
from flexride.paper.data import NotComparable, StudyData, speed_series
from flexride.paper.judge import Value, holds
from flexride.paper.plan import shortest_wavelength

__all__ = ["section6", "section7"]


def _same_frequency(data: StudyData) -> Value:
    v = data.example_speed(CO)
    f0 = v / 3.6 / shortest_wavelength(CO)
    f, p = data.mean_psd(CO, v, FLEX, "PR", "z")
    near = [x for x in measures.spectral_peaks(f, p, (1.0, 100.0)) if abs(x / f0 - 1) <= 0.05]
    return Value(holds=bool(near), values={"corrugation_hz": f0, "peaks_hz": near},
                 words=(f"peak at {near[0]:.2f} Hz" if near else "no peak")
                 + f" (V/λ = {f0:.2f} Hz at {v:g} km/h)")


def _rises(data: StudyData) -> Value:
    s = slopes(data, CO, FLEX, THREE, ("z",), "peak")
    return Value(holds=all(x > 0 for x in s.values()), values={"slope_m_s2_per_kmh": s},
                 words="slopes of the vertical peak (m/s² per km/h): " + table(s))


def _pc_sensitive(data: StudyData) -> Value:
    speeds = data.need_speeds(CO, 2)
    low = at_points(data, CO, speeds[0], FLEX, THREE, "z", "peak")
    high = at_points(data, CO, speeds[-1], FLEX, THREE, "z", "peak")
    ok = min(low, key=lambda k: low[k]) == "PC" and max(high, key=lambda k: high[k]) == "PC"
    return Value(holds=ok, values={f"{speeds[0]:g}": low, f"{speeds[-1]:g}": high},
                 words=f"{speeds[0]:g} km/h: {table(low)}; {speeds[-1]:g} km/h: {table(high)}")


def _small_sperling(data: StudyData) -> Value:
    rows = {}
    for v in data.speeds(CO):
        for p in THREE:
            try:
                rows[f"{p} {v:g}"] = (data.mean(CO, v, FLEX, p, "z", "sperling"),
                                      data.mean(RS, v, FLEX, p, "z", "sperling"))
            except NotComparable:
                continue
    if not rows:
        raise NotComparable("needs corrugation and random-straight runs at the same speeds")
    bad = [k for k, (c, r) in rows.items() if c >= r]
    return Value(holds=not bad, values={"corrugation_random": rows},
                 words=f"corrugation below random irregularity in {len(rows) - len(bad)} of "
                 f"{len(rows)} cases; largest corrugation index "
                 f"{max(c for c, _ in rows.values()):.2f}")


def _little_lateral(data: StudyData) -> Value:
    v = data.example_speed(CO)
    co = data.mean(CO, v, FLEX, "PC", "y", "rms")
    rs = data.mean(RS, v, FLEX, "PC", "y", "rms")
    return Value(holds=co < 0.1 * rs, values={"corrugation_rms": co, "random_rms": rs},
                 words=f"lateral rms at PC {co:.3g} m/s² (random irregularity {rs:.3g})")


def section6() -> list[Claim]:
    """§6, Figs. 18–19: corrugation."""
    return [
        Claim(id="s6.fig18.same-frequency", source="§6, Fig. 18",
              statement="The car body vibrates in response to the corrugation with the same "
              "frequency", paper="peak at the corrugation frequency V/λ",
              rule="a PSD peak at PR within ±5 % of V/λ (80 km/h)", compute=_same_frequency,
              judge=holds, reason=reasons.CORRUGATION, figure="fig18"),
        Claim(id="s6.fig19.rises", source="§6, Fig. 19",
              statement="The accelerations at the different locations increase with speed",
              paper="increase with speed", rule="slope of the vertical peak against speed > 0 "
              "at PR, PFB, PC", compute=_rises, judge=holds, reason=reasons.CORRUGATION,
              figure="fig19"),
        Claim(id="s6.fig19.pc-most-sensitive", source="§6, Fig. 19",
              statement="The vertical acceleration at PC is the smallest at 50 km/h and the "
              "largest at 80 km/h", paper="PC smallest at 50, largest at 80 km/h",
              rule="among PR, PFB, PC (vertical peaks) at the lowest and highest speed",
              compute=_pc_sensitive, judge=holds, reason=reasons.CORRUGATION, figure="fig19"),
        Claim(id="s6.sperling-small", source="§6",
              statement="The Sperling index under corrugation is very small: short-wave "
              "excitation has little influence on ride comfort", paper="very small",
              rule="vertical Sperling under corrugation below that under random irregularity "
              "(straight) at every speed and point", compute=_small_sperling, judge=holds,
              reason=reasons.CORRUGATION, figure="fig-sperling"),
        Claim(id="s6.lateral-little", source="§6",
              statement="Short-wave excitation has little influence on lateral vibration",
              paper="little lateral vibration", rule="lateral rms at PC under corrugation < "
              "10 % of that under random irregularity (80 km/h)", compute=_little_lateral,
              judge=holds, reason=reasons.CORRUGATION, figure="fig-sperling"),
    ]


def _peak_increase(data: StudyData) -> Value:
    speeds = data.need_speeds(SE, 2)
    peaks = speed_series(data, SE, FLEX, "PR", "z", "peak", speeds)
    ok = all(b > a for a, b in itertools.pairwise(peaks))
    return Value(holds=ok, values={"peak_m_s2": dict(zip([f"{v:g}" for v in speeds], peaks,
                                                           strict=True))},
                 words="PR vertical peak: " + ", ".join(
                     f"{v:g} km/h {a:.3g}" for v, a in zip(speeds, peaks, strict=True)))


def _linear(data: StudyData) -> Value:
    speeds = data.need_speeds(SE, 3)
    fits = {p: measures.line_fit(speeds, speed_series(data, SE, FLEX, p, "z", "peak", speeds))
            for p in THREE}
    r2 = {p: f["r_squared"] for p, f in fits.items()}
    return Value(holds=all(x > 0.99 for x in r2.values()), values={"fits": fits},
                 words="R² of peak against speed: " + table(r2, 4))


def _settlement_order(data: StudyData) -> Value:
    rows = {f"{v:g}": at_points(data, SE, v, FLEX, THREE, "z", "peak") for v in data.speeds(SE)}
    if not rows:
        raise NotComparable("no settlement runs in this study")
    ok = all(max(r, key=lambda k: r[k]) == "PR" and min(r, key=lambda k: r[k]) == "PC"
             for r in rows.values())
    return Value(holds=ok, values={"peak_m_s2": rows},
                 words="; ".join(f"{v} km/h: {table(r)}" for v, r in rows.items()))


def _sperling_sharp(data: StudyData) -> Value:
    se = slopes(data, SE, FLEX, THREE, ("z",), "sperling")
    rs = slopes(data, RS, FLEX, THREE, ("z",), "sperling")
    ok = all(se[k] > max(rs[k], 0.0) for k in se)
    return Value(holds=ok, values={"settlement_slope": se, "random_slope": rs},
                 words="vertical Sperling slope per km/h, settlement: " + table(se, 2)
                 + "; random irregularity: " + table(rs, 2))


def _greatest(data: StudyData) -> Value:
    rows: dict[str, dict[str, float]] = {}
    for v in data.speeds(SE):
        row = {}
        for cond in data_conditions(data):
            try:
                row[cond] = max(data.mean(cond, v, FLEX, p, "z", "sperling") for p in THREE)
            except NotComparable:
                continue
        if len(row) > 1:
            rows[f"{v:g}"] = row
    if not rows:
        raise NotComparable("needs settlement and another condition at the same speed")
    ok = all(max(r, key=lambda k: r[k]) == SE for r in rows.values())
    return Value(holds=ok, values={"largest_vertical_sperling": rows},
                 words="; ".join(f"{v} km/h: {table(r, 3)}" for v, r in rows.items()))


def data_conditions(data: StudyData) -> list[str]:
    """The conditions with flexible runs in the study."""
    return sorted({r["spec"]["condition"] for r in data.records})


def section7() -> list[Claim]:
    """§7, Figs. 20–22: settlement."""
    return [
        Claim(id="s7.fig20.increase", source="§7, Fig. 20",
              statement="With increasing speed the car body acceleration (PR) increases "
              "sharply", paper="increases with speed", rule="the vertical peak at PR grows "
              "from each speed to the next", compute=_peak_increase, judge=holds,
              reason=reasons.SETTLEMENT, figure="fig20"),
        Claim(id="s7.fig21.linear", source="§7, Fig. 21",
              statement="The peak acceleration increases linearly with speed; all fitting "
              "factors larger than 0.99", paper=0.99, unit="R²",
              rule="R² of the least-squares line of the vertical peak against speed > 0.99 at "
              "PR, PFB and PC (needs ≥ 3 speeds)", compute=_linear, judge=holds,
              reason=reasons.SETTLEMENT, figure="fig21"),
        Claim(id="s7.fig21.order", source="§7, Fig. 21",
              statement="The acceleration at PR is the largest, at PC the smallest",
              paper="PR largest, PC smallest", rule="vertical peaks at every speed",
              compute=_settlement_order, judge=holds, reason=reasons.MODE_SHAPES,
              figure="fig21"),
        Claim(id="s7.fig22.sperling-sharp", source="§7, Fig. 22",
              statement="The Sperling index increases sharply with speed under settlement",
              paper="increases sharply", rule="slope of the vertical Sperling index against "
              "speed larger than under random irregularity (straight) at PR, PFB, PC",
              compute=_sperling_sharp, judge=holds, reason=reasons.SETTLEMENT,
              figure="fig22"),
        Claim(id="s7.greatest-influence", source="§7; §9 conclusion 4",
              statement="Among all conditions, long-wave excitation has the greatest influence "
              "on ride comfort", paper="settlement gives the largest Sperling index",
              rule="at every speed the largest vertical Sperling index (PR, PFB, PC) is the "
              "settlement's", compute=_greatest, judge=holds, reason=reasons.SETTLEMENT,
              figure="fig-sperling"),
    ]

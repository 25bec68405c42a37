"""Claims of §5: ride comfort under random irregularity, straight (§5.1) and curve (§5.2)."""

from __future__ import annotations

from flexride.paper import measures
from flexride.paper.claims import reasons
from flexride.paper.claims.base import Claim
from flexride.paper.claims.common import (
    DIRS,
    FLEX,
    RC,
    RS,
    THREE,
    at_points,
    close,
    largest,
    slopes,
    smallest,
    table,
)
from flexride.paper.data import StudyData
from flexride.paper.judge import Value, holds
from flexride.paper.reference import FIG10_PEAKS_HZ, FIG12_LATERAL_HZ, SPERLING_LIMIT

_PEAK_BAND = (0.3, 100.0)
_LATERAL_BAND = (0.3, 20.0)
_DOMINANT = 0.5
_NAMES = {RS: "straight", RC: "curve"}


def _vertical_pr_pfb_pc(cond: str):
    def compute(data: StudyData) -> Value:
        v = data.example_speed(cond)
        rms = at_points(data, cond, v, FLEX, THREE, "z", "rms")
        ok = close(rms["PR"], rms["PFB"], 0.2) and rms["PC"] <= 0.8 * min(rms["PR"], rms["PFB"])
        return Value(holds=ok, values={"rms_m_s2": rms},
                     words=f"rms z (m/s²) at {v:g} km/h: {table(rms)}")
    return compute


def _lateral_order(cond: str):
    def compute(data: StudyData) -> Value:
        v = data.example_speed(cond)
        rms = at_points(data, cond, v, FLEX, THREE, "y", "rms")
        ok = largest(rms) == "PR" and rms["PC"] <= 0.8 * rms["PFB"]
        if cond == RS:
            ok = ok and rms["PR"] <= 1.3 * rms["PFB"]
        return Value(holds=ok, values={"rms_m_s2": rms},
                     words=f"rms y (m/s²) at {v:g} km/h: {table(rms)}")
    return compute


def _fig10_peak(f0: float):
    def compute(data: StudyData) -> Value:
        v = data.example_speed(RS)
        cutoff = data.first(RS, v, FLEX)["spec"].get("cutoff_hz") or 0.0
        f, p = data.mean_psd(RS, v, FLEX, "PR", "z")
        tol = max(0.05 * f0, 0.3)
        found = [x for x in measures.spectral_peaks(f, p, _PEAK_BAND) if abs(x - f0) <= tol]
        words = (f"peak at {found[0]:.2f} Hz" if found else
                 f"no peak within ±{tol:.2g} Hz of {f0:g} Hz") + f" ({v:g} km/h)"
        if f0 > cutoff > 0:
            return Value(holds=False, comparable=False, words=words, why=(
                f"{f0:g} Hz lies above the elastic modes kept in this run (cut-off {cutoff:g} "
                "Hz): a peak there is no car-body mode of this model. " + reasons.HIGH_MODE))
        return Value(holds=bool(found), values={"peaks_hz": found}, words=words)
    return compute


def _common_frequencies(data: StudyData) -> Value:
    v = data.example_speed(RS)
    peaks = {p: measures.spectral_peaks(*data.mean_psd(RS, v, FLEX, p, "z"), (0.5, 20.0))[:3]
             for p in THREE}

    def matched(x: float) -> bool:
        return any(abs(x - y) <= max(0.1 * y, 0.3) for y in peaks["PR"])

    ok = all(matched(x) for p in ("PFB", "PC") for x in peaks[p])
    return Value(holds=ok, values={"three_largest_peaks_hz": peaks},
                 words="; ".join(f"{p}: " + ", ".join(f"{x:.2f}" for x in xs) + " Hz"
                                 for p, xs in peaks.items()))


def _main_lateral(cond: str, single: bool):
    def compute(data: StudyData) -> Value:
        v = data.example_speed(cond)
        found = {p: measures.peak_dominance(*data.mean_psd(cond, v, FLEX, p, "y"),
                                            _LATERAL_BAND) for p in THREE}
        if single:
            ok = all(abs(fp - FIG12_LATERAL_HZ) <= 0.3 for fp, _ in found.values())
        else:
            ok = all(share < _DOMINANT for _, share in found.values())
        return Value(holds=ok, values={p: {"main_hz": fp, "share_within_0.25_hz": s}
                                       for p, (fp, s) in found.items()},
                     words="; ".join(f"{p}: largest line {fp:.2f} Hz holding {s:.0%} of "
                                     "0.3–20 Hz" for p, (fp, s) in found.items()))
    return compute


def _peak_rises(data: StudyData) -> Value:
    s = slopes(data, RS, FLEX, ("PR",), ("z", "y"), "peak")
    return Value(holds=all(x > 0 for x in s.values()), values={"slope_m_s2_per_kmh": s},
                 words="slopes of the peak (m/s² per km/h): " + table(s))


def _peak_order(direction: str):
    def compute(data: StudyData) -> Value:
        rows = {f"{v:g}": at_points(data, RS, v, FLEX, THREE, direction, "peak")
                for v in data.need_speeds(RS, 1)}
        if direction == "z":
            ok = all(close(r["PR"], r["PFB"], 0.2) and r["PC"] < min(r["PR"], r["PFB"])
                     for r in rows.values())
        else:
            ok = all(largest(r) == "PR" and smallest(r) == "PC" for r in rows.values())
        return Value(holds=ok, values={"peak_m_s2": rows},
                     words="; ".join(f"{v} km/h: {table(r)}" for v, r in rows.items()))
    return compute


def _sperling_rises(cond: str):
    def compute(data: StudyData) -> Value:
        s = slopes(data, cond, FLEX, THREE, ("z", "y"), "sperling")
        return Value(holds=all(x > 0 for x in s.values()), values={"slope_per_kmh": s},
                     words="slopes of Sperling against speed (per km/h): " + table(s, 2))
    return compute


def _vertical_above_lateral(cond: str):
    def compute(data: StudyData) -> Value:
        pairs = {f"{p} {v:g}": (data.mean(cond, v, FLEX, p, "z", "sperling"),
                                data.mean(cond, v, FLEX, p, "y", "sperling"))
                 for v in data.need_speeds(cond, 1) for p in THREE}
        bad = [k for k, (z, y) in pairs.items() if z <= y]
        return Value(holds=not bad, values={"vertical_lateral": pairs},
                     words=f"vertical > lateral in {len(pairs) - len(bad)} of {len(pairs)} "
                     f"(point, speed) cases" + (f"; not at {', '.join(bad)}" if bad else ""))
    return compute


def _below_limit(cond: str):
    def compute(data: StudyData) -> Value:
        vals = [data.mean(cond, v, FLEX, p, d, "sperling")
                for v in data.need_speeds(cond, 1) for p in THREE for d in DIRS]
        top = max(vals)
        return Value(holds=top < SPERLING_LIMIT, values={"largest": top},
                     words=f"largest Sperling index {top:.2f}")
    return compute


def _vertical_as_straight(data: StudyData) -> Value:
    v = data.example_speed(RC)
    bands = [(0.5, 2.5), (2.5, 6.0), (6.0, 10.0), (10.0, 20.0), (20.0, 40.0)]
    ratios = {f"{lo:g}-{hi:g} Hz": data.mean(RC, v, FLEX, "PR", "z", f"band:{lo:g}:{hi:g}")
              / data.mean(RS, v, FLEX, "PR", "z", f"band:{lo:g}:{hi:g}") for lo, hi in bands}
    return Value(holds=all(2 / 3 <= r <= 1.5 for r in ratios.values()),
                 values={"curve/straight band rms at PR": ratios},
                 words="band rms curve/straight at PR: " + table(ratios, 2))


def _point_claims(cond: str, sec: str, fig_t: str) -> list[Claim]:
    name = _NAMES[cond]
    return [
        Claim(id=f"{sec}.{fig_t}.vertical", source=f"§{sec[1:]}, Fig. {fig_t[3:]}",
              statement=f"Vertical vibration ({name}): PR almost the same as PB, both much "
              "larger than PC", paper="PR ≈ PB ≫ PC",
              rule="flexible, 80 km/h, rms: |PR/PFB − 1| ≤ 0.2 and PC ≤ 0.8·min(PR, PFB)",
              compute=_vertical_pr_pfb_pc(cond), judge=holds, reason=reasons.MODE_SHAPES,
              figure=fig_t),
        Claim(id=f"{sec}.{fig_t}.lateral", source=f"§{sec[1:]}, Fig. {fig_t[3:]}",
              statement=f"Lateral vibration ({name}): PR "
              + ("a little larger than PB" if cond == RS else "the largest")
              + ", PC much smaller", paper="PR > PB > PC" if cond == RS else "PR largest, "
              "PC smallest",
              rule="flexible, 80 km/h, rms: PR largest"
              + (" and ≤ 1.3·PFB" if cond == RS else "") + ", PC ≤ 0.8·PFB",
              compute=_lateral_order(cond), judge=holds,
              reason=reasons.CURVE_FLANGE if cond == RC else reasons.LATERAL_INPUTS,
              figure=fig_t),
    ]


def _sperling_claims(cond: str, sec: str, fig_s: str) -> list[Claim]:
    name = _NAMES[cond]
    return [
        Claim(id=f"{sec}.{fig_s}.sperling-rises", source=f"§{sec[1:]}, Fig. {fig_s[3:]}",
              statement=f"Lateral and vertical Sperling indices increase with speed ({name})",
              paper="increase with speed", rule="flexible: least-squares slope against speed "
              "> 0 at PR, PFB and PC, both directions", compute=_sperling_rises(cond),
              judge=holds, reason=reasons.SINGLE_SAMPLE, figure=fig_s),
        Claim(id=f"{sec}.{fig_s}.vertical-above-lateral",
              source=f"§{sec[1:]}, Fig. {fig_s[3:]}",
              statement=f"The vertical Sperling index is larger than the lateral ({name})",
              paper="vertical > lateral", rule="flexible: vertical > lateral at PR, PFB and PC "
              "at every speed", compute=_vertical_above_lateral(cond), judge=holds,
              reason=reasons.LATERAL_INPUTS, figure=fig_s),
        Claim(id=f"{sec}.{fig_s}.below-limit", source=f"§{sec[1:]}, Fig. {fig_s[3:]}",
              statement=f"All Sperling indices are less than the ruled value ({name})",
              paper=f"< {SPERLING_LIMIT} (value not named; GB 5599 'excellent' taken)",
              rule=f"every Sperling index (flexible, PR/PFB/PC, y/z) < {SPERLING_LIMIT}",
              compute=_below_limit(cond), judge=holds, reason=reasons.LATERAL_INPUTS,
              figure=fig_s),
    ]


def section5() -> list[Claim]:
    """§5.1 (Figs. 9–14) and §5.2 (Figs. 15–17)."""
    claims = _point_claims(RS, "s5.1", "fig9")
    claims += [Claim(id=f"s5.1.fig10.peak-{f0:g}hz", source="§5.1, Fig. 10",
                     statement=f"A peak of the vertical acceleration at PR near {f0:g} Hz",
                     paper=f0, unit="Hz", rule="a PSD peak (≥ 2× its surroundings) within "
                     "±5 % (at least ±0.3 Hz), flexible, 80 km/h",
                     compute=_fig10_peak(f0), judge=holds,
                     reason=reasons.LATERAL_MODE if f0 < 2 else reasons.PEAK_FREQUENCIES,
                     figure="fig10") for f0 in FIG10_PEAKS_HZ]
    claims += [
        Claim(id="s5.1.fig11.common-frequencies", source="§5.1, Fig. 11",
              statement="The vertical vibration frequencies are similar at the different "
              "locations", paper="same frequency bands at PR, PB, PC",
              rule="the three largest PSD peaks (0.5–20 Hz) of PFB and PC each within ±10 % "
              "of a peak of PR", compute=_common_frequencies, judge=holds,
              reason=reasons.PEAK_FREQUENCIES, figure="fig11"),
        Claim(id="s5.1.fig12.lateral-0.95hz", source="§5.1, Fig. 12",
              statement="The main lateral frequency is 0.95 Hz (rigid property of the car "
              "body) at all locations", paper=FIG12_LATERAL_HZ, unit="Hz",
              rule="largest PSD line in 0.3–20 Hz within 0.95 ± 0.3 Hz at PR, PFB and PC",
              compute=_main_lateral(RS, single=True), judge=holds,
              reason=reasons.LATERAL_MODE, figure="fig12"),
        Claim(id="s5.1.fig13.peak-rises", source="§5.1, Fig. 13",
              statement="The maximum acceleration at PR increases with speed",
              paper="increases with speed", rule="slope of the peak against speed > 0, "
              "vertical and lateral", compute=_peak_rises, judge=holds,
              reason=reasons.SINGLE_SAMPLE, figure="fig13"),
        Claim(id="s5.1.fig13.vertical-order", source="§5.1, Fig. 13",
              statement="Vertical peaks at PR almost equal to PB, larger than at PC",
              paper="PR ≈ PB > PC", rule="at every speed: |PR/PFB − 1| ≤ 0.2 and PC < "
              "min(PR, PFB)", compute=_peak_order("z"), judge=holds,
              reason=reasons.MODE_SHAPES, figure="fig13"),
        Claim(id="s5.1.fig13.lateral-order", source="§5.1, Fig. 13",
              statement="Lateral peaks largest at PR, smallest at PC",
              paper="PR largest, PC smallest", rule="at every speed", compute=_peak_order("y"),
              judge=holds, reason=reasons.LATERAL_INPUTS, figure="fig13"),
    ]
    claims += _sperling_claims(RS, "s5.1", "fig14")
    claims += _point_claims(RC, "s5.2", "fig15")
    claims += [
        Claim(id="s5.2.fig16.vertical-as-straight", source="§5.2, Fig. 16",
              statement="Vertical acceleration in the frequency domain almost the same as on "
              "the straight", paper="same as straight",
              rule="band rms at PR (0.5–2.5, 2.5–6, 6–10, 10–20, 20–40 Hz) curve/straight "
              "within 2/3–3/2", compute=_vertical_as_straight, judge=holds,
              reason=reasons.CURVE_FLANGE, figure="fig16"),
        Claim(id="s5.2.fig16.lateral-no-dominant", source="§5.2, Fig. 16",
              statement="Lateral acceleration on the curve has no obvious dominant frequency",
              paper="no dominant frequency", rule="the largest lateral PSD line holds < 50 % "
              "of the 0.3–20 Hz variance (±0.25 Hz) at PR, PFB and PC",
              compute=_main_lateral(RC, single=False), judge=holds,
              reason=reasons.CURVE_FLANGE, figure="fig16"),
    ]
    return claims + _sperling_claims(RC, "s5.2", "fig17")

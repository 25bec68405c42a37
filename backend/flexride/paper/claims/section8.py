"""Claims of §8: the six points of Fig. 23 (Fig. 24), the PRB time–frequency plot (Fig. 25)
and the cross-correlations with their lags (Fig. 26); and §9's conclusions on the points.
"""

from __future__ import annotations

from flexride.paper import measures
from flexride.paper.claims import reasons
from flexride.paper.claims.base import Claim
from flexride.paper.claims.common import FLEX, RS, SIX, at_points, close, table
from flexride.paper.data import StudyData
from flexride.paper.judge import Value, holds, within_abs
from flexride.paper.measures import mean_ci
from flexride.paper.reference import EXAMPLE_SPEED_KMH, FIG25_BANDS_HZ, FIG26_PR_LAG_S

__all__ = ["section8"]

_OTHERS = ("PR", "PFB", "PLA", "PRA", "PC")


def _six(data: StudyData, quantity: str = "rms") -> tuple[float, dict[str, float]]:
    v = data.example_speed(RS)
    return v, at_points(data, RS, v, FLEX, SIX, "z", quantity)


def _rear_alike(data: StudyData) -> Value:
    v, rms = _six(data)
    _, peak = _six(data, "peak")
    ok = all(close(rms[p], rms["PRB"], 0.1) and close(peak[p], peak["PRB"], 0.15)
             for p in ("PLA", "PRA"))
    sub = {p: rms[p] for p in ("PRB", "PLA", "PRA")}
    return Value(holds=ok, values={"rms": sub, "peak": {p: peak[p] for p in sub}},
                 words=f"rms z (m/s²) at {v:g} km/h: {table(sub)}")


def _pc_smallest(data: StudyData) -> Value:
    _, rms = _six(data)
    ok = min(rms, key=lambda k: rms[k]) == "PC" and rms["PC"] <= 0.8 * min(rms["PRB"],
                                                                          rms["PFB"])
    return Value(holds=ok, values={"rms": rms}, words=f"rms z (m/s²): {table(rms)}")


def _pfb_below_prb(data: StudyData) -> Value:
    _, rms = _six(data)
    r = rms["PFB"] / rms["PRB"]
    return Value(holds=0.8 <= r < 1.0, values={"PFB/PRB": r}, words=f"PFB/PRB = {r:.3f}")


def _roof(data: StudyData) -> Value:
    _, rms = _six(data)
    return Value(comparable=False, values={"rms": rms}, words=f"PR {rms['PR']:.3g} m/s² rms",
                 why="The six points hold one roof point (PR): differences along the roof "
                 "cannot be judged from them.")


def _air_springs(data: StudyData) -> Value:
    v = data.example_speed(RS)
    w = at_points(data, RS, v, FLEX, SIX, "z", "sperling")
    ok = max(w["PLA"], w["PRA"]) > w["PC"]
    return Value(holds=ok, values={"sperling_z": w},
                 words=f"vertical Sperling at {v:g} km/h: {table(w)}")


def _pr_largest(data: StudyData) -> Value:
    _, rms = _six(data)
    ok = max(rms, key=lambda k: rms[k]) == "PR" and min(rms, key=lambda k: rms[k]) == "PC"
    return Value(holds=ok, values={"rms": rms}, words=f"rms z (m/s²): {table(rms)}")


def _bands(data: StudyData) -> Value:
    v = data.example_speed(RS)
    f, p = data.mean_psd(RS, v, FLEX, "PRB", "z")
    share = measures.band_share(f, p, FIG25_BANDS_HZ, (0.3, 20.0))
    return Value(holds=share >= 0.6, values={"share": share},
                 words=f"{share:.0%} of the 0.3–20 Hz variance at PRB lies in 0–2.5 and 6–9 Hz")


def _corr_max(data: StudyData) -> dict[str, float]:
    v = data.example_speed(RS)
    return {p: mean_ci([c["normalised_max"] for c in data.correlations(RS, v, FLEX, p)]).mean
            for p in _OTHERS}


def _pla_largest(data: StudyData) -> Value:
    v = data.example_speed(RS)
    peaks = _corr_max(data)
    lag = mean_ci([c["lag_s"] for c in data.correlations(RS, v, FLEX, "PLA")]).mean
    ok = max(peaks, key=lambda k: peaks[k]) == "PLA" and abs(lag) <= 0.05
    return Value(holds=ok, values={"normalised_max": peaks, "lag_PLA_s": lag},
                 words=f"normalised maxima with PRB: {table(peaks)}; PLA at {lag:+.3f} s")


def _pc_least(data: StudyData) -> Value:
    peaks = _corr_max(data)
    return Value(holds=min(peaks, key=lambda k: peaks[k]) == "PC",
                 values={"normalised_max": peaks},
                 words=f"normalised maxima with PRB: {table(peaks)}")


def _pc_two_peaks(data: StudyData) -> Value:
    v = data.example_speed(RS)
    c = data.correlations(RS, v, FLEX, "PC")[0]
    near = [m for m in c["maxima"] if abs(m["lag"]) <= 0.1]
    far = [m for m in c["maxima"] if abs(m["lag"]) > 0.1]
    ok = bool(near and far) and max(m["value"] for m in far) > max(m["value"] for m in near)
    return Value(holds=ok, values={"maxima": c["maxima"]}, words="local maxima (lag s, "
                 "normalised): " + ", ".join(f"({m['lag']:+.2f}, {m['normalised']:.2f})"
                                             for m in sorted(c["maxima"],
                                                             key=lambda m: m["lag"])))


def _pr_lag(data: StudyData) -> Value:
    v = EXAMPLE_SPEED_KMH
    est = mean_ci([c["lag_s"] for c in data.correlations(RS, v, FLEX, "PR")])
    return Value(estimate=est, unit="s", words=f"maximum of R(PRB, PR) at {est.text()} s "
                 f"({v:g} km/h; bogie spacing / V = {-12.6 / (v / 3.6):.3f} s)")


def section8() -> list[Claim]:
    """§8, Figs. 24–26, and the conclusions they support."""
    fig24 = "§8, Fig. 24"
    fig26 = "§8, Fig. 26"
    return [
        Claim(id="s8.fig24.rear-bogie-alike", source=fig24,
              statement="The vibrations at PRB, PLA and PRA are almost the same, as are their "
              "peaks", paper="PRB ≈ PLA ≈ PRA", rule="rms within ±10 % and peaks within ±15 % "
              "of PRB's (vertical, flexible, 80 km/h)", compute=_rear_alike, judge=holds,
              reason=reasons.MODE_SHAPES, figure="fig24"),
        Claim(id="s8.fig24.pc-smallest", source=fig24,
              statement="The vibration at PC is the smallest, much smaller than at PRB and "
              "PFB", paper="PC smallest", rule="PC the smallest rms of the six and ≤ "
              "0.8·min(PRB, PFB)", compute=_pc_smallest, judge=holds,
              reason=reasons.MODE_SHAPES, figure="fig24"),
        Claim(id="s8.fig24.pfb-below-prb", source=fig24,
              statement="The vibration at PFB is a little smaller than at PRB",
              paper="PFB a little < PRB", rule="0.8 ≤ PFB/PRB < 1 (rms)",
              compute=_pfb_below_prb, judge=holds, reason=reasons.VERTICAL_LEVEL,
              figure="fig24"),
        Claim(id="s8.fig24.roof", source=fig24,
              statement="Vibrations at the roof do not show great special differences",
              paper="no great differences along the roof", rule="—", compute=_roof,
              judge=holds, figure="fig24"),
        Claim(id="s8.floor-centre-not-enough", source="§8; §9 conclusion 5",
              statement="Evaluating only at the floor centre is not accurate enough; watch "
              "the air-spring locations", paper="air-spring points exceed PC",
              rule="vertical Sperling at PLA or PRA larger than at PC (80 km/h)",
              compute=_air_springs, judge=holds, reason=reasons.MODE_SHAPES, figure="fig24"),
        Claim(id="s9.c2.pr-largest-pc-smallest", source="§9 conclusion 2",
              statement="Vibration at PR is the largest, at PC the smallest",
              paper="PR largest, PC smallest", rule="rms of the six points (vertical, "
              "flexible, 80 km/h)", compute=_pr_largest, judge=holds,
              reason=reasons.MODE_SHAPES, figure="fig24"),
        Claim(id="s8.fig25.bands", source="§8, Fig. 25",
              statement="The energy of the vertical acceleration at PRB is concentrated in "
              "0–2.5 Hz and 6–9 Hz", paper="0–2.5 and 6–9 Hz",
              rule="≥ 60 % of the 0.3–20 Hz variance at PRB in those bands", compute=_bands,
              judge=holds, reason=reasons.PEAK_FREQUENCIES, figure="fig25"),
        Claim(id="s8.fig26.pla-largest", source=fig26,
              statement="The cross-correlation of PRB and PLA is the largest; the two vibrate "
              "almost synchronously", paper="PLA largest, lag ≈ 0",
              rule="largest normalised maximum with PRB, at |lag| ≤ 0.05 s",
              compute=_pla_largest, judge=holds, reason=reasons.MODE_SHAPES, figure="fig26"),
        Claim(id="s8.fig26.pc-smallest", source=fig26,
              statement="The cross-correlation of PRB and PC is the smallest",
              paper="PC smallest", rule="smallest normalised maximum with PRB",
              compute=_pc_least, judge=holds, reason=reasons.MODE_SHAPES, figure="fig26"),
        Claim(id="s8.fig26.pc-two-peaks", source=fig26,
              statement="Two peaks in the correlation of PC and PRB: the smaller at the "
              "origin, the bigger at a shifted lag", paper="small peak at 0, larger one shifted",
              rule="a local maximum at |lag| ≤ 0.1 s and a larger one beyond",
              compute=_pc_two_peaks, judge=holds, reason=reasons.MODE_SHAPES, figure="fig26"),
        Claim(id="s8.fig26.pr-lag", source=fig26,
              statement="The maximum of the cross-correlation of PRB and PR lies at −0.57 s, a "
              "shift due to the distance between the two points", paper=FIG26_PR_LAG_S,
              unit="s", rule="within ±0.05 s of −0.57 s (80 km/h)", compute=_pr_lag,
              judge=within_abs(0.05), reason=reasons.BOGIE_SPACING,
              agree=reasons.BOGIE_SPACING.split(" A short")[0], figure="fig26"),
    ]

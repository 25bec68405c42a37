"""Claims of Table 1 (modal analysis), Table 2 and §3 (flexible against rigid model)."""

from __future__ import annotations

from flexride.paper.claims import reasons
from flexride.paper.claims.base import Claim
from flexride.paper.claims.common import FLEX, RIGID, RS
from flexride.paper.data import NotComparable, StudyData
from flexride.paper.judge import Value, holds, within
from flexride.paper.measures import Estimate
from flexride.paper.reference import TABLE1_HZ, TABLE2

__all__ = ["section3", "table1", "table2"]

# The paper's "RMS index" is read as Sperling's rms-based (filter) form: reasons.RMS_INDEX
_T2_ROWS = {"sperling_z": ("z", "sperling", "vertical Sperling index"),
            "rms_z": ("z", "sperling_filter", "vertical RMS index"),
            "sperling_y": ("y", "sperling", "lateral Sperling index"),
            "rms_y": ("y", "sperling_filter", "lateral RMS index")}


def _mode(k: int):
    def compute(data: StudyData) -> Value:
        if data.modal is None or len(data.modal["frequencies_hz"]) < k:
            raise NotComparable("no modal analysis of the car body in this report")
        f = data.modal["frequencies_hz"][k - 1]
        kind = data.modal["classification"][k - 1]
        return Value(estimate=Estimate(f, None, 1), unit="Hz",
                     values={"mode_type": kind, "element_size_m": data.modal["element_size_m"]},
                     words=f"{f:.3f} Hz, {kind}")
    return compute


def table1() -> list[Claim]:
    """Table 1: the first six elastic frequencies of the car body, each within 5 %."""
    return [Claim(id=f"table1.mode{k}", source="Table 1",
                  statement=f"Elastic mode {k} of the car body at {f:.2f} Hz",
                  paper=f, unit="Hz", rule="within 5 % of the paper's frequency",
                  compute=_mode(k), judge=within(0.05), reason=reasons.TABLE1_MISSED,
                  agree=reasons.TABLE1_CALIBRATED, figure="table1")
            for k, f in enumerate(TABLE1_HZ, start=1)]


def _table2_value(row: str, body: str):
    direction, quantity, _ = _T2_ROWS[row]

    def compute(data: StudyData) -> Value:
        v = data.example_speed(RS)
        est = data.value(RS, v, body, "PC", direction, quantity)
        if quantity == "sperling_filter":
            rms = data.value(RS, v, body, "PC", direction, "rms")
            return Value(estimate=est, unit="-", values={"rms_m_s2": rms.mean},
                         words=f"{est.text()} at PC, {v:g} km/h (Sperling filter form, "
                         f"4.42·a_B^0.3; rms {rms.text()} m/s²)")
        return Value(estimate=est, unit="-", words=f"{est.text()} at PC, {v:g} km/h "
                     "(spectral form)")
    return compute


def _table2_diff(row: str):
    direction, quantity, _ = _T2_ROWS[row]

    def compute(data: StudyData) -> Value:
        v = data.example_speed(RS)
        ratio = data.paired_ratio(RS, v, "PC", direction, quantity)
        diff = Estimate(ratio.mean - 1.0, ratio.ci95, ratio.n)
        return Value(estimate=diff, unit="-", words=f"flexible/rigid − 1 = {diff.mean:+.1%} "
                     f"at PC, {v:g} km/h")
    return compute


def _same_sign_close(paper: object, value: Value) -> bool:
    if value.estimate is None:
        return False
    d = value.estimate.mean
    return d > 0 and abs(d - float(paper)) <= 0.05  # type: ignore[arg-type]


def _table2_reason(row: str) -> str:
    reason = reasons.LATERAL_INPUTS if row.endswith("_y") else reasons.VERTICAL_LEVEL
    return f"{reasons.RMS_INDEX} {reason}" if row.startswith("rms") else reason


def table2() -> list[Claim]:
    """Table 2: each index of both models within ±20 %, and the flexible–rigid differences."""
    claims = []
    for row, (flex, rigid, diff) in TABLE2.items():
        name = _T2_ROWS[row][2]
        for body, paper in ((FLEX, flex), (RIGID, rigid)):
            claims.append(Claim(
                id=f"table2.{row}.{body}", source="Table 2",
                statement=f"{name[0].upper()}{name[1:]}, {body} model: {paper:.2f}", paper=paper,
                unit="-", rule="within ±20 % of the paper's value (random irregularity, "
                "straight, PC, 80 km/h)", compute=_table2_value(row, body), judge=within(0.20),
                reason=_table2_reason(row), figure="table2"))
        claims.append(Claim(
            id=f"table2.{row}.difference", source="Table 2",
            statement=f"{name[0].upper()}{name[1:]}: flexible larger than rigid by {diff:.1%}",
            paper=diff, unit="-", rule="flexride's flexible/rigid − 1 positive and within 5 "
            "percentage points of the paper's difference", compute=_table2_diff(row),
            judge=_same_sign_close, reason=reasons.TABLE2_DIFF, figure="table2"))
    return claims


def _all_larger(data: StudyData) -> Value:
    v = data.example_speed(RS)
    ratios = {row: data.paired_ratio(RS, v, "PC", d, q).mean
              for row, (d, q, _) in _T2_ROWS.items()}
    return Value(holds=all(r > 1.0 for r in ratios.values()),
                 values={f"{k} flexible/rigid": r for k, r in ratios.items()},
                 words=", ".join(f"{k} ×{r:.2f}" for k, r in ratios.items()))


def _band_gain(data: StudyData, direction: str, bands: list[tuple[float, float]]
               ) -> dict[str, float]:
    """Increase of the variance (m²/s⁴) from rigid to flexible in each band at PC."""
    v = data.example_speed(RS)
    out = {}
    for lo, hi in bands:
        q = f"band:{lo:g}:{hi:g}"
        out[f"{lo:g}-{hi:g} Hz"] = (data.mean(RS, v, FLEX, "PC", direction, q) ** 2
                                    - data.mean(RS, v, RIGID, "PC", direction, q) ** 2)
    return out


def _vertical_band(data: StudyData) -> Value:
    v = data.example_speed(RS)
    ratio = data.paired_ratio(RS, v, "PC", "z", "rms").mean
    gain = _band_gain(data, "z", [(0.5, 4.0), (4.0, 10.0), (10.0, 40.0)])
    ok = ratio > 1.1 and max(gain, key=lambda k: gain[k]) == "4-10 Hz"
    return Value(holds=ok, values={"rms flexible/rigid": ratio, "variance increase": gain},
                 words=f"rms ×{ratio:.2f}; variance added per band (m²/s⁴): "
                 + ", ".join(f"{k} {g:.2e}" for k, g in gain.items()))


def _lateral_band(data: StudyData) -> Value:
    v = data.example_speed(RS)
    ratio = data.paired_ratio(RS, v, "PC", "y", "rms").mean
    gain = _band_gain(data, "y", [(0.3, 1.0), (1.0, 4.0), (4.0, 10.0), (10.0, 40.0)])
    ok = 1.0 < ratio <= 1.3 and max(gain, key=lambda k: gain[k]) == "0.3-1 Hz"
    return Value(holds=ok, values={"rms flexible/rigid": ratio, "variance increase": gain},
                 words=f"rms ×{ratio:.2f}; variance added per band (m²/s⁴): "
                 + ", ".join(f"{k} {g:.2e}" for k, g in gain.items()))


def _sensitive_band(data: StudyData) -> Value:
    v = data.example_speed(RS)
    ratio = data.paired_ratio(RS, v, "PC", "z", "band:4:8")
    return Value(estimate=ratio, holds=ratio.mean >= 1.2, unit="-",
                 words=f"4–8 Hz rms at PC flexible/rigid ×{ratio.text()}")


def section3() -> list[Claim]:
    """§3, Figs. 6–7 and Table 2's reading: the flexible model vibrates more."""
    return [
        Claim(id="s3.table2.flexible-larger", source="§3, Table 2",
              statement="The ride comfort indices of the flexible model are larger than those "
              "of the rigid model", paper="flexible > rigid for all four indices",
              rule="flexible/rigid > 1 for the Sperling and rms indices, vertical and lateral, "
              "at PC", compute=_all_larger, judge=holds, reason=reasons.LATERAL_INPUTS,
              figure="table2"),
        Claim(id="s3.fig7.vertical-4-10hz", source="§3, Figs. 6–7",
              statement="Vertical acceleration of the flexible model obviously larger than the "
              "rigid model's, especially in 4–10 Hz",
              paper="flexible > rigid, mostly in 4–10 Hz",
              rule="rms ratio > 1.1 and the 4–10 Hz band adds more variance than 0.5–4 and "
              "10–40 Hz (PC, 80 km/h)", compute=_vertical_band, judge=holds,
              reason=reasons.FLEXIBLE_GAIN, figure="fig7"),
        Claim(id="s3.fig7.lateral-below-1hz", source="§3, Figs. 6–7",
              statement="Lateral acceleration of the flexible model a little larger than the "
              "rigid model's, especially under 1 Hz",
              paper="flexible a little > rigid, mostly below 1 Hz",
              rule="1 < rms ratio ≤ 1.3 and the 0.3–1 Hz band adds the most variance (PC)",
              compute=_lateral_band, judge=holds, reason=reasons.LATERAL_MODE, figure="fig7"),
        Claim(id="s9.c1.sensitive-band", source="§3; §9 conclusion 1",
              statement="The flexible model reflects the band humans are sensitive to "
              "(4–8 Hz vertical), which the rigid model misses",
              paper="more 4–8 Hz vibration with the flexible model",
              rule="4–8 Hz rms at PC flexible/rigid ≥ 1.2", compute=_sensitive_band,
              judge=holds, reason=reasons.FLEXIBLE_GAIN, figure="fig7"),
    ]



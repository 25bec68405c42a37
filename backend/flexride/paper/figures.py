"""flexride's versions of the paper's figures as Plotly figure specifications (plain dicts of
``data`` and ``layout``), from the study's results: time histories and spectra at the paper's
points, indices against speed, the PRB spectrogram and the cross-correlations, and the
element-size pre-calculation (:mod:`flexride.paper.mesh`).

Every figure is ``{"id", "title", "paper", "panels": [{"title", "data", "layout"}], "note"}``;
a figure the study cannot draw (a condition not run) carries only its ``note``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from flexride.paper.claims.common import CO, DIRS, FLEX, RC, RIGID, RS, SE, SIX, THREE
from flexride.paper.data import NotComparable, StudyData, record_psd
from flexride.paper.measures import line_fit
from flexride.paper.mesh import fig4_panels
from flexride.paper.plan import shortest_wavelength
from flexride.paper.reference import (
    FIG10_PEAKS_HZ,
    FIG12_LATERAL_HZ,
    FIG26_PR_LAG_S,
    SPERLING_LIMIT,
    TABLE1_HZ,
)

__all__ = ["build_figures"]

Figure = dict[str, Any]
COLORS = {"PR": "#d62728", "PFB": "#1f77b4", "PC": "#2ca02c", "PRB": "#9467bd",
          "PLA": "#ff7f0e", "PRA": "#8c564b", RIGID: "#7f7f7f", FLEX: "#1f77b4",
          RS: "#1f77b4", RC: "#ff7f0e", CO: "#2ca02c", SE: "#d62728"}
_UNIT = {"z": "vertical acceleration (m/s²)", "y": "lateral acceleration (m/s²)"}


def _layout(x: str, y: str, *, log_x: bool = False, log_y: bool = False,
            x_range: list[float] | None = None, lines: list[float] | None = None,
            hlines: list[float] | None = None) -> dict[str, Any]:
    shapes = [{"type": "line", "x0": v, "x1": v, "yref": "paper", "y0": 0, "y1": 1,
               "line": {"dash": "dot", "color": "#555", "width": 1}} for v in lines or []]
    shapes += [{"type": "line", "y0": v, "y1": v, "xref": "paper", "x0": 0, "x1": 1,
                "line": {"dash": "dash", "color": "#b00", "width": 1}} for v in hlines or []]
    xaxis: dict[str, Any] = {"title": {"text": x}, "type": "log" if log_x else "linear"}
    if x_range is not None:
        xaxis["range"] = x_range
    return {"xaxis": xaxis, "yaxis": {"title": {"text": y}, "type": "log" if log_y else "linear"},
            "shapes": shapes, "margin": {"l": 60, "r": 10, "t": 30, "b": 45}, "height": 340,
            "legend": {"orientation": "h", "y": -0.25}}


def _trace(x: Any, y: Any, name: str, color: str | None = None, dash: str | None = None,
           mode: str = "lines", error: list[float | None] | None = None) -> dict[str, Any]:
    t: dict[str, Any] = {"type": "scatter", "mode": mode, "x": list(x), "y": list(y),
                         "name": name, "line": {"width": 1.2}}
    if color:
        t["line"]["color"] = color
    if dash:
        t["line"]["dash"] = dash
    if error is not None and any(e is not None for e in error):
        t["error_y"] = {"type": "data", "array": [e or 0.0 for e in error], "visible": True}
    return t


def _series(rec: dict[str, Any], key: str, *, distance: bool = False) -> tuple[list, list]:
    s = rec["series"]
    if key not in s:
        raise NotComparable(f"no time history of {key}")
    y = s[key]
    rate = s["rate_hz"]
    if distance:
        v = float(rec["spec"]["speed_kmh"]) / 3.6
        x = [round(s["s0"] + i * v / rate, 3) for i in range(len(y))]
    else:
        x = [round(s["t0"] + i / rate, 4) for i in range(len(y))]
    return x, y


def _psd_trace(rec: dict[str, Any], point: str, d: str, name: str, color: str,
               dash: str | None = None, f_max: float = 100.0) -> dict[str, Any]:
    f, p = record_psd(rec, point, d)
    keep = (f > 0) & (f <= f_max)
    return _trace(np.round(f[keep], 4).tolist(), [float(f"{v:.4g}") for v in p[keep]], name,
                  color, dash)


def _panel(title: str, data: list[dict[str, Any]], layout: dict[str, Any]) -> dict[str, Any]:
    return {"title": title, "data": data, "layout": layout}


def _time_panels(data: StudyData, cond: str, points: tuple[str, ...],
                 bodies: tuple[str, ...] = (FLEX,)) -> list[dict[str, Any]]:
    v = data.example_speed(cond)
    panels = []
    for d in DIRS:
        traces = []
        for body in bodies:
            rec = data.first(cond, v, body)
            for p in points:
                x, y = _series(rec, f"{p}.{d}")
                name = f"{p} {body}" if len(bodies) > 1 else p
                color = COLORS[body] if len(bodies) > 1 else COLORS[p]
                traces.append(_trace(x, y, name, color))
        panels.append(_panel(f"{DIRS[d]}, {v:g} km/h", traces, _layout("time (s)", _UNIT[d])))
    return panels


def _psd_panels(data: StudyData, cond: str, points: tuple[str, ...],
                bodies: tuple[str, ...] = (FLEX,), lines: dict[str, list[float]] | None = None,
                dirs: tuple[str, ...] = ("z", "y")) -> list[dict[str, Any]]:
    v = data.example_speed(cond)
    panels = []
    for d in dirs:
        traces = [_psd_trace(data.first(cond, v, body), p, d,
                             f"{p} {body}" if len(bodies) > 1 else p,
                             COLORS[body] if len(bodies) > 1 else COLORS[p],
                             "dot" if body == RIGID and len(bodies) > 1 else None)
                  for body in bodies for p in points]
        layout = _layout("frequency (Hz)", "PSD ((m/s²)²/Hz)", log_x=True, log_y=True,
                         lines=(lines or {}).get(d))
        _psd_range(layout, traces)
        panels.append(_panel(f"{DIRS[d]} PSD, {v:g} km/h", traces, layout))
    return panels


def _psd_range(layout: dict[str, Any], traces: list[dict[str, Any]],
               decades: float = 6.0) -> None:
    """Show ``decades`` decades of PSD below the largest value (log axis)."""
    top = max((v for t in traces for v in t["y"] if v is not None and v > 0), default=None)
    if top is not None:
        hi = float(np.log10(top)) + 0.5
        layout["yaxis"]["range"] = [hi - decades - 0.5, hi]


def _vs_speed(data: StudyData, cond: str, quantity: str, points: tuple[str, ...],
              d: str, bodies: tuple[str, ...] = (FLEX, RIGID)) -> list[dict[str, Any]]:
    traces = []
    for body in bodies:
        speeds = data.speeds(cond, body)
        for p in points:
            est = [data.value(cond, v, body, p, d, quantity) for v in speeds]
            traces.append(_trace(speeds, [e.mean for e in est], f"{p} {body}", COLORS[p],
                                 None if body == FLEX else "dot", "lines+markers",
                                 [e.ci95 for e in est]))
    return traces


def _speed_panels(data: StudyData, cond: str, quantity: str, y: str,
                  limit: bool = False) -> list[dict[str, Any]]:
    return [_panel(DIRS[d], _vs_speed(data, cond, quantity, THREE, d),
                   _layout("speed (km/h)", y, hlines=[SPERLING_LIMIT] if limit else None))
            for d in DIRS]


def _table1(data: StudyData) -> list[dict[str, Any]]:
    if data.modal is None:
        raise NotComparable("no modal analysis")
    modes = list(range(1, len(TABLE1_HZ) + 1))
    ours = data.modal["frequencies_hz"][: len(modes)]
    bars = [{"type": "bar", "x": modes, "y": list(TABLE1_HZ), "name": "paper"},
            {"type": "bar", "x": modes, "y": ours, "name": "flexride",
             "text": data.modal["classification"][: len(modes)], "hoverinfo": "y+text"}]
    return [_panel("elastic modes of the car body", bars, _layout("mode", "frequency (Hz)"))]


def _fig10(data: StudyData) -> list[dict[str, Any]]:
    return _psd_panels(data, RS, ("PR",), lines={"z": list(FIG10_PEAKS_HZ)}, dirs=("z",))


def _fig18(data: StudyData) -> list[dict[str, Any]]:
    v = data.example_speed(CO)
    rec = data.first(CO, v, FLEX)
    x, y = _series(rec, "PR.z")
    f0 = v / 3.6 / shortest_wavelength(CO)
    psd = [_psd_trace(rec, "PR", "z", "PR", COLORS["PR"])]
    zoom = [x[0], x[0] + 1.0] if x else None  # one second; zoom out to see the run
    return [_panel(f"PR vertical, {v:g} km/h", [_trace(x, y, "PR", COLORS["PR"])],
                   _layout("time (s)", _UNIT["z"], x_range=zoom)),
            _panel("PR vertical PSD", psd, _psd_layout([f0], psd))]


def _psd_layout(lines: list[float], traces: list[dict[str, Any]]) -> dict[str, Any]:
    layout = _layout("frequency (Hz)", "PSD ((m/s²)²/Hz)", log_x=True, log_y=True, lines=lines)
    _psd_range(layout, traces)
    return layout


def _fig19(data: StudyData) -> list[dict[str, Any]]:
    return [_panel("vertical peak", _vs_speed(data, CO, "peak", THREE, "z"),
                   _layout("speed (km/h)", "peak |a| (m/s²)"))]


def _fig20(data: StudyData) -> list[dict[str, Any]]:
    traces = []
    for v in data.speeds(SE):
        x, y = _series(data.first(SE, v, FLEX), "PR.z", distance=True)
        traces.append(_trace(x, y, f"{v:g} km/h"))
    return [_panel("PR vertical, flexible", traces,
                   _layout("position of the vehicle centre (m)", _UNIT["z"]))]


def _fig21(data: StudyData) -> list[dict[str, Any]]:
    traces = _vs_speed(data, SE, "peak", THREE, "z", (FLEX,))
    speeds = data.speeds(SE)
    if len(speeds) >= 2:
        for p in THREE:
            vals = [data.mean(SE, v, FLEX, p, "z", "peak") for v in speeds]
            fit = line_fit(speeds, vals)
            traces.append(_trace(speeds, [fit["slope"] * v + fit["intercept"] for v in speeds],
                                 f"{p} fit, R² = {fit['r_squared']:.4f}", COLORS[p], "dash"))
    return [_panel("vertical peak and fitted lines", traces,
                   _layout("speed (km/h)", "peak |a| (m/s²)"))]


def _fig_sperling(data: StudyData) -> list[dict[str, Any]]:
    panels = []
    for d in DIRS:
        traces = []
        for cond in (RS, RC, CO, SE):
            for body in (FLEX, RIGID):
                speeds = data.speeds(cond, body)
                if not speeds:
                    continue
                est = [data.value(cond, v, body, "PC", d, "sperling") for v in speeds]
                traces.append(_trace(speeds, [e.mean for e in est], f"{cond} {body}",
                                     COLORS[cond], None if body == FLEX else "dot",
                                     "lines+markers", [e.ci95 for e in est]))
        panels.append(_panel(f"{DIRS[d]} Sperling index at PC", traces,
                             _layout("speed (km/h)", "Sperling index (-)",
                                     hlines=[SPERLING_LIMIT])))
    return panels


def _fig24(data: StudyData) -> list[dict[str, Any]]:
    v = data.example_speed(RS)
    panel = _time_panels(data, RS, SIX)[0]
    rms = {p: data.value(RS, v, FLEX, p, "z", "rms") for p in SIX}
    bars = [{"type": "bar", "x": list(SIX), "y": [rms[p].mean for p in SIX], "name": "rms",
             "error_y": {"type": "data", "array": [rms[p].ci95 or 0.0 for p in SIX]}}]
    return [panel, _panel(f"rms, vertical, {v:g} km/h", bars, _layout("point", "rms (m/s²)"))]


def _fig25(data: StudyData) -> list[dict[str, Any]]:
    v = data.example_speed(RS)
    sg = data.first(RS, v, FLEX).get("spectrogram")
    if not sg:
        raise NotComparable("no spectrogram of PRB")
    z = [[None if x is None or x <= 0 else round(float(np.log10(x)), 3) for x in row]
         for row in sg["values"]]
    heat = {"type": "heatmap", "x": sg["t"], "y": sg["f"], "z": z, "colorscale": "Viridis",
            "colorbar": {"title": {"text": "log10 PSD"}}}
    return [_panel(f"PRB vertical, {v:g} km/h", [heat], _layout("time (s)", "frequency (Hz)"))]


def _fig26(data: StudyData) -> list[dict[str, Any]]:
    v = data.example_speed(RS)
    rec = data.first(RS, v, FLEX)
    traces = [_trace(c["curve"]["lag_s"], c["curve"]["normalised"], f"PRB–{c['other']}",
                     COLORS.get(c["other"]))
              for c in rec.get("correlations", []) if c["direction"] == "z" and "curve" in c]
    if not traces:
        raise NotComparable("no correlation curves")
    return [_panel(f"vertical, {v:g} km/h (normalised)", traces,
                   _layout("lag (s)", "R(PRB, point) / √(E_a E_b)", lines=[FIG26_PR_LAG_S]))]


_FIGURES: list[tuple[str, str, str, Callable[[StudyData], list[dict[str, Any]]]]] = [
    ("fig4", "Secondary suspension force against the car body's element size "
     "(extrapolated values dotted)", "Fig. 4", fig4_panels),
    ("table1", "Natural frequencies of the car body", "Table 1", _table1),
    ("fig6", "Car body accelerations at PC, rigid and flexible model", "Fig. 6",
     lambda d: _time_panels(d, RS, ("PC",), (RIGID, FLEX))),
    ("fig7", "Spectra at PC, rigid and flexible model", "Fig. 7",
     lambda d: _psd_panels(d, RS, ("PC",), (RIGID, FLEX))),
    ("fig9", "Car body accelerations on straight track", "Fig. 9",
     lambda d: _time_panels(d, RS, THREE)),
    ("fig10", "Vertical acceleration at PR in frequency domain (paper's peaks dotted)",
     "Fig. 10", _fig10),
    ("fig11", "Vertical accelerations at the three points in frequency domain", "Fig. 11",
     lambda d: _psd_panels(d, RS, THREE, dirs=("z",))),
    ("fig12", "Lateral accelerations in frequency domain (0.95 Hz dotted)", "Fig. 12",
     lambda d: _psd_panels(d, RS, THREE, lines={"y": [FIG12_LATERAL_HZ]}, dirs=("y",))),
    ("fig13", "Peak accelerations against speed (flexible solid, rigid dotted)", "Fig. 13",
     lambda d: _speed_panels(d, RS, "peak", "peak |a| (m/s²)")),
    ("fig14", "Sperling index on straight track", "Fig. 14",
     lambda d: _speed_panels(d, RS, "sperling", "Sperling index (-)", limit=True)),
    ("fig15", "Car body accelerations on the curve", "Fig. 15",
     lambda d: _time_panels(d, RC, THREE)),
    ("fig16", "Accelerations on the curve in frequency domain", "Fig. 16",
     lambda d: _psd_panels(d, RC, THREE)),
    ("fig17", "Sperling index on the curve", "Fig. 17",
     lambda d: _speed_panels(d, RC, "sperling", "Sperling index (-)", limit=True)),
    ("fig18", "Vertical acceleration at PR under corrugation (V/λ dotted)", "Fig. 18", _fig18),
    ("fig19", "Accelerations under corrugation against speed", "Fig. 19", _fig19),
    ("fig20", "Vertical acceleration at PR under settlement", "Fig. 20", _fig20),
    ("fig21", "Peak accelerations under settlement with fitted lines", "Fig. 21", _fig21),
    ("fig22", "Sperling index under settlement", "Fig. 22",
     lambda d: _speed_panels(d, SE, "sperling", "Sperling index (-)", limit=True)),
    ("fig-sperling", "Sperling index against speed per condition (PC)", "Figs. 14, 17, 22",
     _fig_sperling),
    ("fig24", "Vertical accelerations at the six points", "Fig. 24", _fig24),
    ("fig25", "Vertical acceleration at PRB in time–frequency domain", "Fig. 25", _fig25),
    ("fig26", "Cross-correlations with PRB (paper's −0.57 s dotted)", "Fig. 26", _fig26),
]


def build_figures(data: StudyData) -> list[Figure]:
    """Every figure the study can draw (the others with a note saying what is missing)."""
    out = []
    for fid, title, paper, build in _FIGURES:
        fig: Figure = {"id": fid, "title": title, "paper": paper, "panels": [], "note": ""}
        try:
            fig["panels"] = build(data)
        except NotComparable as exc:
            fig["note"] = f"not drawn: {exc}"
        out.append(fig)
    return out

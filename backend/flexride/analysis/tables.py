"""Terminal tables of a :class:`~flexride.analysis.summary.Summary` (rich): the comfort results
(:func:`summary_table`) and the running-safety indices (:func:`safety_table`), what
``flexride analyze`` and ``flexride run`` print. Both take a Summary or its
:meth:`~flexride.analysis.summary.Summary.to_dict` (e.g. a stored summary).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from flexride.analysis.safety import SAFETY_SYMBOLS
from flexride.analysis.summary import ISO_WEIGHTINGS, Summary
from flexride.errors import AnalysisError

if TYPE_CHECKING:
    from rich.console import JustifyMethod
    from rich.table import Table

__all__ = ["safety_table", "summary_table"]


def _fmt(v: float | None, digits: int = 3) -> str:
    """``v`` with ``digits`` significant digits (whole numbers from 1000 on); a dash for None
    and non-finite values.
    """
    if v is None or not math.isfinite(v):
        return "–"
    return f"{v:.{digits}g}" if abs(v) < 1000 else f"{v:.0f}"


def _as_dict(summary: Summary | dict[str, Any]) -> dict[str, Any]:
    """The JSON form of a summary (a :class:`Summary` or already its ``to_dict()``)."""
    if isinstance(summary, Summary):
        return summary.to_dict()
    if isinstance(summary, dict) and "points" in summary and "settings" in summary:
        return summary
    raise AnalysisError("expected a Summary or the dictionary of Summary.to_dict()")


def summary_table(summary: Summary | dict[str, Any]) -> Table:
    """A :class:`rich.table.Table` of the comfort results.

    Per point and direction: the Sperling index (default form) and its GB 5599 grade, the
    weighted rms a_w (Wb for z, Wd for y/x) with its ISO 2631 comfort band, the largest EN 12299
    C_c, the peak acceleration and, per point, N_MV (``*``: run shorter than 5 min).

    Parameters
    ----------
    summary : Summary or dict
        The result of :func:`analyze`, or its :meth:`Summary.to_dict`.
    """
    from rich.table import Table

    d = _as_dict(summary)
    run = d.get("run", {})
    title = "flexride analysis"
    if run.get("scenario"):
        title += f" — {run['scenario']}"
    if run.get("speed_kmh") is not None:
        title += f", {run['speed_kmh']:.4g} km/h"
    form = d["settings"]["sperling"]["default_form"]
    caption = (f"W: Sperling {form} form (dynamic part), grade GB 5599 · a_w: ISO 2631 rms, "
               "Wb (z) / Wd (y, x) · C_c: EN 12299 5 s · N_MV: EN 12299 standard method · "
               "peak: max |a| raw")
    table = Table(title=title)
    columns: tuple[tuple[str, JustifyMethod], ...] = (
        ("point", "left"), ("dir", "center"), ("W", "right"), ("grade", "left"),
        ("a_w m/s²", "right"), ("ISO 2631 comfort", "left"), ("C_c max m/s²", "right"),
        ("peak m/s²", "right"), ("N_MV", "right"))
    for col, just in columns:
        table.add_column(col, justify=just)
    short = False
    for name, p in d["points"].items():
        first = True
        mc = p.get("mean_comfort")
        for direction in ("z", "y", "x"):
            ds = p["directions"].get(direction)
            if ds is None:
                continue
            w = ds.get("sperling")
            iso = ds.get("iso2631", {}).get(ISO_WEIGHTINGS[direction][0])
            cc = ds.get("continuous_comfort")
            grade = w["grade"] if w and isinstance(w.get("grade"), str) else "–"
            style = {"excellent": "green", "good": "green", "qualified": "yellow",
                     "fails": "bold red"}.get(grade, "")
            nmv = ""
            if first and mc and mc.get("value") is not None:
                nmv = f"{mc['value']:.2f}" + ("*" if mc.get("short_run") else "")
                short = short or bool(mc.get("short_run"))
            table.add_row(
                name if first else "", direction,
                _fmt(w["value"]) if w else "–",
                f"[{style}]{grade}[/]" if style else grade,
                _fmt(iso["a_w"]) if iso else "–", iso["comfort"] if iso else "–",
                _fmt(cc["maximum"]) if cc else "–",
                _fmt(ds["peaks"]["max_abs"]), nmv)
            first = False
    if short:
        caption += " · * run shorter than 5 min (see docs/analysis.md)"
    table.caption = caption
    return table


def safety_table(summary: Summary | dict[str, Any]) -> Table | None:
    """A :class:`rich.table.Table` of the running-safety indices (None without wheel forces).

    Parameters
    ----------
    summary : Summary or dict
        The result of :func:`analyze`, or its :meth:`Summary.to_dict`.
    """
    from rich.table import Table

    d = _as_dict(summary)
    safety = d.get("safety")
    if not safety:
        return None
    table = Table(title="running safety", caption=(
        "EN 14363 names: Q vertical, Y lateral wheel force (GB 5599: P vertical, Q lateral; its "
        "Q/P = Y/Q, ΔP/P = ΔQ/Q) · Y/Q, ΔQ/Q: GB 5599 limits 1.2, 0.65 · ΣY: EN 14363 "
        "10 + 2Q0/3 kN · 20 Hz low pass, 2 m sliding mean (Y/Q, ΣY), maximum"))
    columns: tuple[tuple[str, JustifyMethod], ...] = (
        ("location", "left"), ("quantity", "left"), ("value", "right"), ("limit", "right"),
        ("use", "right"), ("", "left"))
    for col, just in columns:
        table.add_column(col, justify=just)
    for idx in safety["indices"]:
        use = idx.get("utilisation")
        symbol = SAFETY_SYMBOLS.get(idx["name"], (idx["name"], ""))[0]
        unit = "" if idx.get("unit") in (None, "-") else f" {idx['unit']}"
        table.add_row(idx["location"], f"{symbol}{unit}", _fmt(idx["value"]),
                      _fmt(idx["limit"]), f"{use:.0%}" if use is not None else "–",
                      "[green]ok[/]" if idx["passed"] else "[bold red]exceeded[/]")
    nadal = safety.get("nadal")
    if nadal:
        table.add_row(nadal["location"], f"Y/Q (Nadal, γ {nadal['flange_angle_deg']:.1f}°, "
                      f"μ {nadal['friction']:.2f})", _fmt(nadal["worst"]), _fmt(nadal["limit"]),
                      f"{nadal['utilisation']:.0%}",
                      "[green]ok[/]" if nadal["passed"] else "[bold red]exceeded[/]")
    return table

"""The report page: one self-contained HTML file with Plotly inlined from the installed plotly
package (no network), the study's settings, and per section of the paper flexride's figures
beside the paper's claims with their verdicts and notes.
"""

from __future__ import annotations

import html
import json
import math
from collections.abc import Sequence
from typing import Any

__all__ = ["finite", "render_html"]

SECTIONS: list[tuple[str, str, tuple[str, ...], tuple[str, ...]]] = [
    ("table1", "Table 1 — natural frequencies of the car body", ("table1.",), ("table1",)),
    ("s3", "§3 — flexible against rigid model (Figs. 6–7, Table 2)",
     ("table2.", "s3.", "s9.c1."), ("fig6", "fig7")),
    ("s5-1", "§5.1 — random irregularity on straight track (Figs. 9–14)", ("s5.1.",),
     ("fig9", "fig10", "fig11", "fig12", "fig13", "fig14")),
    ("s5-2", "§5.2 — random irregularity on the curve (Figs. 15–17)", ("s5.2.",),
     ("fig15", "fig16", "fig17")),
    ("s6", "§6 — short-wave excitation: corrugation (Figs. 18–19)", ("s6.",),
     ("fig18", "fig19")),
    ("s7", "§7 — long-wave excitation: settlement (Figs. 20–22)", ("s7.",),
     ("fig20", "fig21", "fig22", "fig-sperling")),
    ("s8", "§8 — six points, time–frequency plot, cross-correlations (Figs. 23–26)",
     ("s8.", "s9.c2."), ("fig24", "fig25", "fig26")),
    ("s9", "§9 — conclusions across conditions", ("s9.c3.", "s9.c4."), ()),
]
"""(anchor, title, claim id prefixes, figure ids) of each section of the report."""

VERDICT_TEXT = {
    "reproduced": "flexride's result satisfies the claim's stated rule (tolerance on a number, "
                  "or the trend or ordering holds).",
    "not reproduced": "flexride's result breaks the rule; the note gives the reason: an input "
                      "the paper does not give, or a modelling difference, with flexride's "
                      "documented measurements.",
    "not comparable": "the paper's value cannot be compared (no unit, a quantity flexride's "
                      "model does not resolve) or this study lacks the runs it needs (e.g. "
                      "R² with fewer than three speeds).",
}

_CSS = """
body{font-family:system-ui,sans-serif;margin:0 auto;max-width:1200px;padding:1em 2em;color:#222}
h1{font-size:1.6em}h2{margin-top:2em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;width:100%;font-size:.88em;margin:.6em 0}
th,td{border:1px solid #ddd;padding:4px 6px;vertical-align:top;text-align:left}
th{background:#f3f3f3}.v{font-weight:600;white-space:nowrap;border-radius:3px;padding:1px 5px}
.reproduced{background:#d8f0d8}.not-reproduced{background:#f7d6d6}.not-comparable{background:#eee}
.banner{background:#fff3cd;border:1px solid #e0c060;padding:.6em 1em;margin:1em 0}
.rule{color:#666;font-size:.9em}.grid{display:grid;grid-template-columns:1fr 1fr;gap:8px}
.panel{min-height:340px}.fig{margin:1.2em 0}.fig h3{font-size:1.05em;margin:.3em 0}
.note{color:#555;font-size:.9em}code{font-size:.95em}
"""

_JS = """
const FIGS = JSON.parse(document.getElementById('figure-data').textContent);
const todo = new Map();
for (const fig of FIGS) fig.panels.forEach((p, i) => todo.set(fig.id + '-' + i, p));
function draw(el) {
  const p = todo.get(el.id); if (!p) return; todo.delete(el.id);
  const layout = Object.assign({title: {text: p.title, font: {size: 13}}}, p.layout);
  Plotly.newPlot(el, p.data, layout, {responsive: true, displaylogo: false});
}
const obs = new IntersectionObserver((es) => es.forEach((e) => {
  if (e.isIntersecting) { draw(e.target); obs.unobserve(e.target); } }), {rootMargin: '400px'});
document.querySelectorAll('.panel').forEach((el) => obs.observe(el));
"""


def finite(obj: Any) -> Any:
    """``obj`` with every non-finite float replaced by None (strict JSON), recursively."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: finite(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [finite(v) for v in obj]
    return obj


def _e(text: Any) -> str:
    return html.escape(str(text), quote=True)


def _fmt_paper(claim: dict[str, Any]) -> str:
    p = claim["paper"]
    if isinstance(p, dict) and "value" in p:
        unit = p.get("unit", "")
        return f"{p['value']:g} {unit if unit != '-' else ''}".strip()
    return str(p)


def _fmt_flexride(claim: dict[str, Any]) -> str:
    f = claim.get("flexride") or {}
    if f.get("words"):
        return str(f["words"])
    if f.get("value") is not None:
        ci = f" ± {f['ci95']:.2g}" if f.get("ci95") is not None else ""
        unit = f.get("unit", "")
        return f"{f['value']:.4g}{ci} {unit if unit != '-' else ''}".strip()
    return "—"


def _claims_table(claims: list[dict[str, Any]]) -> str:
    rows = []
    for c in claims:
        cls = c["verdict"].replace(" ", "-")
        rows.append(
            f"<tr id='{_e(c['id'])}'><td><code>{_e(c['id'])}</code><br>{_e(c['source'])}</td>"
            f"<td>{_e(c['statement'])}</td><td>{_e(_fmt_paper(c))}</td>"
            f"<td>{_e(_fmt_flexride(c))}</td>"
            f"<td><span class='v {cls}'>{_e(c['verdict'])}</span></td>"
            f"<td>{_e(c['note'])}<div class='rule'>rule: {_e(c['rule'])}</div></td></tr>")
    head = ("<tr><th>claim</th><th>the paper says</th><th>paper</th><th>flexride</th>"
            "<th>verdict</th><th>note</th></tr>")
    return f"<table>{head}{''.join(rows)}</table>"


def _figure_html(fig: dict[str, Any]) -> str:
    panels = "".join(f"<div class='panel' id='{_e(fig['id'])}-{i}'></div>"
                     for i in range(len(fig["panels"])))
    note = f"<p class='note'>{_e(fig['note'])}</p>" if fig.get("note") else ""
    grid = f"<div class='grid'>{panels}</div>" if panels else ""
    return (f"<div class='fig' id='fig-{_e(fig['id'])}'><h3>flexride's {_e(fig['paper'])}: "
            f"{_e(fig['title'])}</h3>{grid}{note}</div>")


def _wall_text(meta: dict[str, Any]) -> str:
    """The report's wall time: the command's, or the service's runs and then the report's."""
    runs = meta.get("runs_wall_time_s")
    if runs is None:
        return f"wall time {meta['wall_time_s']:.0f} s"
    return (f"wall time of the runs (the service's jobs) {runs:.0f} s, of the report "
            f"{meta['wall_time_s']:.0f} s")


def _header(meta: dict[str, Any]) -> str:
    opts = meta["options"]
    banner = ""
    if opts.get("quick") or (opts.get("distance_scale") or 1.0) < 1.0:
        banner += (f"<div class='banner'><b>Shortened study (--quick or --distance-scale):</b> "
                   f"speeds {', '.join(f'{v:g}' for v in opts['speeds'])} km/h, evaluated "
                   f"stretches × {opts['distance_scale']:g} (at least {opts['min_eval_s']:g} s). "
                   "Trends over speed and R² are weaker or not comparable; run without --quick "
                   "for the paper's study.</div>")
    if opts.get("overrides"):
        banner += ("<div class='banner'><b>Model overrides (tests only), not the paper's "
                   f"study:</b> <code>{_e(json.dumps(opts['overrides']))}</code></div>")
    counts = ", ".join(f"{n} {_e(k)}" for k, n in meta["counts"].items())
    runs = meta["runs"]
    fails = "".join(f"<li>{_e(f['label'])}: {_e(f['error'])}</li>" for f in meta["failures"])
    fails_html = f"<p>Failed runs:</p><ul>{fails}</ul>" if fails else ""
    verdicts = "".join(f"<li><span class='v {k.replace(' ', '-')}'>{_e(k)}</span>: "
                       f"{_e(v)}</li>" for k, v in VERDICT_TEXT.items())
    settings = "".join(f"<li>{_e(s)}</li>" for s in meta["settings"])
    return (f"<h1>The paper, reproduced by flexride {_e(meta['flexride_version'])}</h1>"
            f"<p><i>{_e(meta['paper'])}</i></p>{banner}"
            f"<p>Generated {_e(meta['generated'])}; {runs['total']} runs ({runs['computed']} "
            f"computed, {runs['reused']} from the cache, {runs['failed']} failed), "
            f"{_e(opts['seeds'])} irregularity realisation(s) per random condition, "
            f"{_wall_text(meta)}. Claims: {counts}.</p>{fails_html}"
            f"<h2>Verdicts</h2><ul>{verdicts}</ul><h2>How the study was run</h2>"
            f"<ul>{settings}</ul>")


def render_html(meta: dict[str, Any], claims: list[dict[str, Any]],
                figures: list[dict[str, Any]], plotly_js: str,
                appendix: Sequence[str] = ()) -> str:
    """The report page.

    Parameters
    ----------
    meta : dict
        Report facts: ``paper``, ``flexride_version``, ``generated``, ``wall_time_s``,
        ``options``, ``runs`` (total, computed, reused, failed), ``failures``, ``counts`` (by
        verdict) and ``settings`` (lines of text).
    claims : list of dict
        Judged claims (``summary.json``'s entries).
    figures : list of dict
        :func:`flexride.paper.figures.build_figures`.
    plotly_js : str
        The Plotly library, inlined.
    appendix : sequence of str
        Sections (HTML) after the paper's sections, e.g.
        :func:`flexride.paper.carbody_map.section_html`; their panels are drawn from
        ``figures`` like the others.
    """
    by_id = {f["id"]: f for f in figures}
    body = [_header(meta)]
    for anchor, title, prefixes, fig_ids in SECTIONS:
        mine = [c for c in claims if c["id"].startswith(prefixes)]
        body.append(f"<h2 id='{anchor}'>{_e(title)}</h2>")
        body += [_figure_html(by_id[f]) for f in fig_ids if f in by_id]
        body.append(_claims_table(mine))
    body += list(appendix)
    data = json.dumps(finite([f for f in figures if f["panels"]]), separators=(",", ":"),
                      allow_nan=False).replace("</", "<\\/")
    return ("<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
            "<title>flexride: the paper reproduced</title>"
            f"<style>{_CSS}</style><script>{plotly_js}</script></head><body>"
            + "".join(body)
            + f"<script type='application/json' id='figure-data'>{data}</script>"
            f"<script>{_JS}</script></body></html>")

"""The car-body map in the paper report: which admissible inputs the paper does not give
reproduce its claims about the floor centre (PC), and which do not.

The paper's claims about PC — the quietest point, vertical Sperling +3.5 % and "RMS index"
+6.5 % flexible over rigid (Table 2, §5.1, §8) — are judged on the report's own runs (the
default FE car body). Whether another admissible car body would meet them is an input question:
Table 1 gives the frequencies but not the mode shapes, and the paper gives no mass distribution.
The map (issue 26 §3) answers it for the random straight case at 80 and 50 km/h over the
assignments of mode types to Table 1 the FE body can produce and over the beam car body's first
bending frequency, by the frequency engine and, at the corners, by the time-domain solver over
several irregularity seeds. It is computed by :data:`PRODUCER` and stored as
:data:`MAP_FILE` (reference data kept with the script that produced it); this module only reads
and renders it: the claims keep their verdicts, the map adds the evidence for their reason.

:func:`load_map` reads and checks the file (:class:`CarbodyMapError` with the file and the
command that makes it when it is missing or malformed), :func:`evidence` decides each claim for
each input, :func:`section_html`, :func:`figures` and :func:`annotate` are the report's hooks.
"""

from __future__ import annotations

import html
import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from flexride.paper.measures import Estimate, mean_ci
from flexride.paper.plan import ReportError

__all__ = [
    "ANCHOR",
    "CLAIMS",
    "MAP_FILE",
    "PRODUCER",
    "CarbodyMap",
    "CarbodyMapError",
    "annotate",
    "evidence",
    "figures",
    "load_map",
    "section_html",
    "together",
]

MAP_FILE = Path(__file__).resolve().parent / "data" / "carbody_map.json"
"""The stored map."""
PRODUCER = "tools/studies/carbody_map_time_domain.py"
"""The script that writes :data:`MAP_FILE` (named in the file's provenance)."""
ANCHOR = "carbody-map"
"""HTML anchor of the report's section."""
FORMAT = 1
SIX = ("PR", "PFB", "PC", "PRB", "PLA", "PRA")


@dataclass(frozen=True)
class PcClaim:
    """One of the paper's claims about PC, as the map judges it.

    Attributes
    ----------
    key : str
        Short name.
    text : str
        The claim.
    claim_ids : tuple of str
        The report's claims it stands for (their notes get a pointer to the map).
    quantity : str or None
        Vertical quantity whose flexible/rigid change is compared (None: the ordering).
    paper : float or None
        The paper's change (fraction).
    rule : str
        How the map decides it.
    """

    key: str
    text: str
    claim_ids: tuple[str, ...]
    quantity: str | None
    paper: float | None
    rule: str


CLAIMS: tuple[PcClaim, ...] = (
    PcClaim("quietest", "PC is the quietest point (vertical rms)",
            ("s8.fig24.pc-smallest", "s9.c2.pr-largest-pc-smallest", "s5.1.fig9.vertical"),
            None, None, "PC's vertical rms is the smallest of PR, PFB, PC, PRB, PLA, PRA "
            "(time domain: the mean over seeds)"),
    PcClaim("sperling", "vertical Sperling at PC +3.5 %, flexible over rigid",
            ("table2.sperling_z.difference",), "sperling", 0.035,
            "the change has the paper's sign and lies between half and twice its size "
            "(the report's claim: positive and within 5 percentage points)"),
    PcClaim("rms_index", "vertical 'RMS index' at PC +6.5 % (read as Sperling's filter form, "
            "as the report does)", ("table2.rms_z.difference",), "sperling_filter", 0.065,
            "as above"),
    PcClaim("rms", "vertical rms at PC +6.5 % (the plain rms reading of the same row)",
            ("table2.rms_z.difference",), "rms", 0.065, "as above"),
)
"""The claims the map speaks to."""


class CarbodyMapError(ReportError):
    """The stored map is missing or malformed."""


@dataclass(frozen=True)
class CarbodyMap:
    """The stored map (the JSON of :data:`PRODUCER`) and where it was read from."""

    data: dict[str, Any]
    path: Path

    @property
    def speeds(self) -> list[str]:
        """Speeds (km/h) as the JSON's keys."""
        return [str(v) for v in self.data["settings"]["speeds_kmh"]]

    @property
    def corners(self) -> list[dict[str, Any]]:
        """The corners (key, label, kind, source, first_bending_hz, beam_mass)."""
        return list(self.data["corners"])

    def time(self, speed: str, key: str) -> dict[str, Any]:
        """Per-seed time-domain values of a corner: ``{"seeds", "values"}``."""
        return dict(self.data["time_domain"][speed][key])

    def engine(self, speed: str, key: str) -> dict[str, dict[str, float]]:
        """The frequency engine's values of a corner: point → quantity → value."""
        return dict(self.data["frequency"][speed]["corners"][key])

    def sweep(self, speed: str, mass: str) -> dict[str, Any]:
        """The frequency engine along a beam's first bending frequency."""
        return dict(self.data["frequency"][speed]["beam_sweep"][mass])

    def ratio(self, speed: str, key: str, point: str, quantity: str) -> tuple[Estimate,
                                                                               list[int]]:
        """Flexible/rigid of a corner in the time domain, seed by seed on the same track:
        mean ± 95 % CI, and the seeds paired.
        """
        rigid = self.time(speed, "rigid")
        body = self.time(speed, key)
        ref = dict(zip(rigid["seeds"], rigid["values"][point][quantity], strict=True))
        pairs = [(s, x / ref[s]) for s, x in zip(body["seeds"], body["values"][point][quantity],
                                                 strict=True) if s in ref]
        if not pairs:
            raise CarbodyMapError(f"{self.path}: no seed of {key!r} at {speed} km/h has a "
                                  "rigid run on the same track")
        return mean_ci([r for _, r in pairs]), [s for s, _ in pairs]


def _fail(path: Path, what: str) -> CarbodyMapError:
    return CarbodyMapError(f"the car-body map {path} {what}; make it with "
                           f"'python {PRODUCER}'")


def load_map(path: str | Path | None = None) -> CarbodyMap:
    """Read and check the stored map.

    Parameters
    ----------
    path : str or pathlib.Path, optional
        The JSON (default :data:`MAP_FILE`).

    Returns
    -------
    CarbodyMap

    Raises
    ------
    CarbodyMapError
        The file is missing, is not JSON, was not made by :data:`PRODUCER`, or lacks a part
        the section needs (the message names it).
    """
    p = Path(path) if path is not None else MAP_FILE
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise _fail(p, "is missing") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise _fail(p, f"cannot be read as JSON ({exc})") from None
    if not isinstance(data, dict):
        raise _fail(p, "is not a JSON object")
    if data.get("format") != FORMAT:
        raise _fail(p, f"has format {data.get('format')!r}, not {FORMAT}")
    script = (data.get("provenance") or {}).get("script")
    if script != PRODUCER:
        raise _fail(p, f"names {script!r} as its producer, not {PRODUCER}")
    try:
        _check(CarbodyMap(data, p))
    except (KeyError, TypeError, ValueError, IndexError) as exc:
        raise _fail(p, f"is malformed ({type(exc).__name__}: {exc})") from None
    return CarbodyMap(data, p)


def _check(m: CarbodyMap) -> None:
    """Every part the section reads is there, with one value per seed."""
    keys = [c["key"] for c in m.corners]
    if "rigid" not in keys:
        raise ValueError("no rigid corner")
    for v in m.speeds:
        for key in keys:
            t = m.time(v, key)
            n = len(t["seeds"])
            if n == 0:
                raise ValueError(f"no seed of {key} at {v} km/h")
            for p in SIX:
                m.engine(v, key)[p]
                for q in ("rms", "sperling", "sperling_filter"):
                    if len(t["values"][p][q]) != n:
                        raise ValueError(f"{key} {v} km/h {p} {q}: {len(t['values'][p][q])} "
                                         f"values for {n} seeds")
                    float(m.engine(v, key)[p][q])
        for mass in ("pitch_inertia", "uniform"):
            s = m.sweep(v, mass)
            if len(s["values"]["PC"]["rms"]) != len(s["first_bending_hz"]):
                raise ValueError(f"beam sweep {mass} at {v} km/h: lengths differ")


# --- judging ----------------------------------------------------------------------------------

def agrees(change: float, paper: float) -> bool:
    """Whether a change agrees with the paper's: its sign, between half and twice its size."""
    return 0.5 * paper <= change <= 2.0 * paper


def report_rule(change: float, paper: float) -> bool:
    """The report's own rule for Table 2's differences: positive, within 5 points."""
    return change > 0.0 and abs(change - paper) <= 0.05


def _quietest(rms: dict[str, float]) -> bool:
    return all(rms["PC"] < rms[p] for p in SIX if p != "PC")


def evidence(m: CarbodyMap) -> list[dict[str, Any]]:
    """Each claim at each speed for each input of the map.

    Returns
    -------
    list of dict
        ``{"claim", "speed_kmh", "input", "kind", "time": {"value", "ci95", "n", "seeds",
        "seeds_agreeing"} or None, "engine": float, "reproduced": bool, "report_rule": bool
        or None, "range": [lo, hi] (beam sweeps)}``; changes are flexible/rigid − 1, the
        ordering's value is PC's rank among the six points (1 = quietest).
    """
    rows: list[dict[str, Any]] = []
    labels = {c["key"]: c["label"] for c in m.corners}
    for claim in CLAIMS:
        for v in m.speeds:
            eng_rigid = m.engine(v, "rigid")
            for key in labels:
                rows.append(_corner_row(m, claim, v, key, labels[key], eng_rigid))
            for mass in ("pitch_inertia", "uniform"):
                rows.append(_sweep_row(m, claim, v, mass, eng_rigid))
    return rows


def _rank(rms: dict[str, float]) -> int:
    return sorted(SIX, key=lambda p: rms[p]).index("PC") + 1


def _corner_row(m: CarbodyMap, claim: PcClaim, v: str, key: str, label: str,
                eng_rigid: dict[str, dict[str, float]]) -> dict[str, Any]:
    eng = m.engine(v, key)
    row: dict[str, Any] = {"claim": claim.key, "speed_kmh": float(v), "input": label,
                           "key": key, "kind": "corner", "report_rule": None, "range": None}
    if claim.quantity is None:
        t = m.time(v, key)
        mean = {p: sum(t["values"][p]["rms"]) / len(t["seeds"]) for p in SIX}
        eng_rms = {p: eng[p]["rms"] for p in SIX}
        row |= {"time": {"value": _rank(mean), "ci95": None, "n": len(t["seeds"]),
                         "seeds": list(t["seeds"])},
                "engine": _rank(eng_rms), "reproduced": _quietest(mean)}
        return row
    q, paper = claim.quantity, float(claim.paper or 0.0)
    change_eng = eng["PC"][q] / eng_rigid["PC"][q] - 1.0
    if key == "rigid":
        return row | {"time": None, "engine": 0.0, "reproduced": False}
    est, seeds = m.ratio(v, key, "PC", q)
    change = est.mean - 1.0
    rigid = dict(zip(m.time(v, "rigid")["seeds"], m.time(v, "rigid")["values"]["PC"][q],
                     strict=True))
    body = m.time(v, key)
    each = sum(agrees(x / rigid[s] - 1.0, paper)
               for s, x in zip(body["seeds"], body["values"]["PC"][q], strict=True)
               if s in rigid)
    return row | {"time": {"value": change, "ci95": est.ci95, "n": est.n, "seeds": seeds,
                           "seeds_agreeing": each},
                  "engine": change_eng, "reproduced": agrees(change, paper),
                  "report_rule": report_rule(change, paper)}


def _sweep_row(m: CarbodyMap, claim: PcClaim, v: str, mass: str,
               eng_rigid: dict[str, dict[str, float]]) -> dict[str, Any]:
    s = m.sweep(v, mass)
    f = [float(x) for x in s["first_bending_hz"]]
    label = (f"beam, first bending {f[0]:g}–{f[-1]:g} Hz ("
             + ("mass where the pitch inertia puts it" if mass == "pitch_inertia"
                else "uniform mass") + "), frequency engine")
    row: dict[str, Any] = {"claim": claim.key, "speed_kmh": float(v), "input": label,
                           "key": f"beam-sweep-{mass}", "kind": "sweep", "time": None,
                           "report_rule": None}
    if claim.quantity is None:
        ranks = [_rank({p: s["values"][p]["rms"][k] for p in SIX}) for k in range(len(f))]
        hits = [fk for fk, r in zip(f, ranks, strict=True) if r == 1]
        return row | {"engine": None, "range": [min(ranks), max(ranks)],
                      "reproduced": bool(hits), "where_hz": hits}
    q, paper = claim.quantity, float(claim.paper or 0.0)
    changes = [x / eng_rigid["PC"][q] - 1.0 for x in s["values"]["PC"][q]]
    hits = [fk for fk, c in zip(f, changes, strict=True) if agrees(c, paper)]
    return row | {"engine": None, "range": [min(changes), max(changes)],
                  "reproduced": bool(hits), "where_hz": hits}


# --- rendering --------------------------------------------------------------------------------

def _e(text: Any) -> str:
    return html.escape(str(text), quote=True)


def _pct(x: float) -> str:
    return f"{100.0 * x:+.1f} %"


def _time_text(claim: PcClaim, row: dict[str, Any]) -> str:
    t = row["time"]
    if t is None:
        return "—"
    if claim.quantity is None:
        return f"PC rank {t['value']} of 6 (mean of {t['n']} seeds)"
    ci = f" ± {100.0 * t['ci95']:.1f}" if t["ci95"] is not None else ""
    return (f"{100.0 * t['value']:+.1f}{ci} % ({t['n']} seeds, {t['seeds_agreeing']} of them "
            "agreeing)")


def _engine_text(claim: PcClaim, row: dict[str, Any]) -> str:
    if row["kind"] == "sweep":
        lo, hi = row["range"]
        where = row.get("where_hz") or []
        at = f"; met at {_ranges(where)}" if where else "; met nowhere"
        if claim.quantity is None:
            return f"PC rank {lo}{'' if lo == hi else f'–{hi}'} of 6{at}"
        return f"{_pct(lo)} to {_pct(hi)}{at}"
    if claim.quantity is None:
        return f"PC rank {row['engine']} of 6"
    return "—" if row["key"] == "rigid" else _pct(row["engine"])


def _verdict(row: dict[str, Any]) -> str:
    ok = row["reproduced"]
    text = "reproduces" if ok else "does not"
    if row.get("report_rule"):
        text += " (meets the report's looser rule)" if not ok else ""
    cls = "reproduced" if ok else "not-reproduced"
    return f"<span class='v {cls}'>{_e(text)}</span>"


def _ranges(freqs: Sequence[float], step: float = 0.5) -> str:
    """``5–7, 9 Hz``: the frequencies as runs of consecutive sweep steps."""
    runs: list[list[float]] = []
    for f in sorted(freqs):
        if runs and f - runs[-1][-1] <= step * 1.01:
            runs[-1].append(f)
        else:
            runs.append([f])
    return ", ".join(f"{r[0]:g}" if len(r) == 1 else f"{r[0]:g}–{r[-1]:g}" for r in runs) + " Hz"


def _summary(m: CarbodyMap, rows: Sequence[dict[str, Any]]) -> str:
    """Per claim and speed: what the FE bodies (which match Table 1) give, and which beams
    reproduce it.
    """
    out = []
    for claim in CLAIMS:
        parts = []
        for v in m.speeds:
            mine = [r for r in rows if r["claim"] == claim.key and f"{r['speed_kmh']:g}" == v]
            fe = [r for r in mine if r["key"] in _fe_keys(m)]
            if claim.quantity is None:
                got = ", ".join(f"rank {r['time']['value']}" for r in fe)
                fe_text = f"the FE bodies put PC at {got} of 6"
            else:
                vals = [r["time"]["value"] for r in fe]
                fe_text = f"the FE bodies give {_pct(min(vals))} to {_pct(max(vals))}"
            fe_yes = [r["input"] for r in fe if r["reproduced"]]
            fe_text += (" (reproduced by " + ", ".join(fe_yes) + ")" if fe_yes
                        else ", none reproduces it")
            beams = [r["input"] for r in mine if r["kind"] == "corner" and r["reproduced"]
                     and r["key"] not in _fe_keys(m) and r["key"] != "rigid"]
            sweeps = [f"{'pitch-inertia' if 'pitch' in r['input'] else 'uniform'} beam at "
                      f"{_ranges(r['where_hz'])}" for r in mine
                      if r["kind"] == "sweep" and r["where_hz"]]
            beam_text = "; beams reproducing it: " + (", ".join(beams + sweeps) or "none")
            parts.append(f"{v} km/h: {fe_text}{beam_text}")
        out.append(f"<li><b>{_e(claim.text)}</b> — {_e('. '.join(parts))}.</li>")
    out.append(f"<li><b>Together</b> — {_e(together(m, rows))}</li>")
    return "<ul>" + "".join(out) + "</ul>"


def together(m: CarbodyMap, rows: Sequence[dict[str, Any]],
             keys: Sequence[str] = ("quietest", "sperling", "rms_index")) -> str:
    """Which beam first-bending frequencies of the sweeps meet the claims ``keys`` at every
    speed at once (the report's reading of the "RMS index" by default).
    """
    texts = []
    for mass, name in (("pitch_inertia", "pitch-inertia"), ("uniform", "uniform")):
        sets = [set(r["where_hz"]) for r in rows if r["kind"] == "sweep"
                and r["key"] == f"beam-sweep-{mass}" and r["claim"] in keys]
        both = sorted(set.intersection(*sets)) if sets else []
        texts.append(f"the {name} beam at {_ranges(both)}" if both else f"no {name} beam")
    return (f"PC quietest, Sperling and RMS index (filter form) agreeing at "
            f"{' and '.join(m.speeds)} km/h at once: " + "; ".join(texts)
            + " (frequency engine, 0.5 Hz steps); no FE body that meets Table 1.")


def _fe_keys(m: CarbodyMap) -> set[str]:
    return {c["key"] for c in m.corners if c["kind"] == "fe"}


def section_html(m: CarbodyMap) -> str:
    """The report's section: what was tried, the claims by input, provenance and the figure's
    panels (drawn from :func:`figures`).
    """
    rows = evidence(m)
    prov, st = m.data["provenance"], m.data["settings"]
    cost = prov.get("cost") or {}
    intro = (
        "The claims above keep their verdicts from this report's runs (the default FE car "
        "body). Which car body the paper's vehicle has is an input the paper does not give: "
        "Table 1 lists frequencies without mode shapes, and no mass distribution is given. "
        "This map varies it over what is admissible — the assignments of mode types to "
        "Table 1 the FE car body can produce (the calibrated default; first vertical bending "
        f"sixth by the classifier's name; the paper's §5.1 reading, within 10 %), FE at "
        f"{st['element_size_m']:g} m, modes to {st['fe_cutoff_hz']:g} Hz — and a beam car body "
        "whose first bending frequency runs from 5 to 15 Hz, with its mass where the "
        "vehicle's pitch inertia puts it or uniform. Only the FE bodies match Table 1 (six "
        "modes in 5–9 Hz); a beam has one mode there, so the beams show what the first "
        "bending and the mass distribution do, not a car body that meets Table 1. Random "
        "straight case (German high "
        "disturbance), car body flexible, bogie frames rigid, 2 % modal damping. Frequency "
        "engine over the whole map; at its corners the time-domain solver over seeds "
        f"{', '.join(str(s) for s in st['seeds'])}, each flexible run on the same track as "
        "the rigid one, flexible/rigid − 1 as mean ± 95 % CI over seeds.")
    source = (f"Stored map: {m.path.name}, made by <code>{_e(prov.get('command', PRODUCER))}"
              f"</code> ({_e(prov.get('generated', '?'))}, commit "
              f"{_e((prov.get('git_commit') or '?')[:10])}; {cost.get('runs', '?')} solver runs "
              f"in {cost.get('wall_s', '?')} s). Docs: docs/fem.md, 'The car-body map'.")
    head = ("<tr><th>claim</th><th>km/h</th><th>input</th><th>time domain</th>"
            "<th>frequency engine</th><th>the claim</th></tr>")
    body = []
    for r in rows:
        claim = next(c for c in CLAIMS if c.key == r["claim"])
        if claim.quantity is not None and r["key"] == "rigid":
            continue
        body.append(f"<tr><td>{_e(claim.text)}</td><td>{r['speed_kmh']:g}</td>"
                    f"<td>{_e(r['input'])}</td><td>{_e(_time_text(claim, r))}</td>"
                    f"<td>{_e(_engine_text(claim, r))}</td><td>{_verdict(r)}</td></tr>")
    rules = "".join(f"<li>{_e(c.text)}: {_e(c.rule)}</li>" for c in CLAIMS)
    panels = "".join(f"<div class='panel' id='{ANCHOR}-{i}'></div>"
                     for i in range(len(_panels(m))))
    return (f"<h2 id='{ANCHOR}'>The car-body map — which admissible inputs reproduce the "
            f"paper's claims about PC</h2><p>{_e(intro)}</p><p class='note'>{source}</p>"
            f"{_summary(m, rows)}<div class='grid'>{panels}</div>"
            f"<p class='rule'>Rules: </p><ul class='rule'>{rules}</ul>"
            f"<table>{head}{''.join(body)}</table>")


def _panels(m: CarbodyMap) -> list[dict[str, Any]]:
    """One Plotly panel per speed and compared quantity: the change at PC against the beam's
    first bending (frequency engine), the corners' time-domain means ± CI, the paper's band.
    """
    labels = {c["key"]: c for c in m.corners}
    fe = [k for k, c in labels.items() if c["kind"] == "fe"]
    fe_x = {k: 16.5 + i for i, k in enumerate(fe)}
    out = []
    for v in m.speeds:
        rigid = m.engine(v, "rigid")
        for claim in (c for c in CLAIMS if c.quantity is not None):
            q, paper = claim.quantity, float(claim.paper or 0.0)
            assert q is not None
            data: list[dict[str, Any]] = []
            for mass, dash in (("pitch_inertia", "solid"), ("uniform", "dash")):
                s = m.sweep(v, mass)
                data.append({"type": "scatter", "mode": "lines", "x": s["first_bending_hz"],
                             "y": [100.0 * (x / rigid["PC"][q] - 1.0)
                                   for x in s["values"]["PC"][q]],
                             "name": f"beam ({mass.replace('_', ' ')}), engine",
                             "line": {"dash": dash, "color": "#1f77b4", "width": 1.2}})
            xs, ys, es, names = [], [], [], []
            for key, c in labels.items():
                if key == "rigid":
                    continue
                est, _ = m.ratio(v, key, "PC", q)
                x = fe_x.get(key, c["first_bending_hz"])
                xs.append(x + (0.15 if c.get("beam_mass") == "uniform" else 0.0))
                ys.append(100.0 * (est.mean - 1.0))
                es.append(100.0 * (est.ci95 or 0.0))
                names.append(c["label"])
            data.append({"type": "scatter", "mode": "markers", "x": xs, "y": ys, "text": names,
                         "name": "time domain, mean ± 95 % CI",
                         "error_y": {"type": "data", "array": es, "visible": True},
                         "marker": {"color": "#d62728"}})
            data.append({"type": "scatter", "mode": "markers",
                         "x": [fe_x[k] for k in fe],
                         "y": [100.0 * (m.engine(v, k)["PC"][q] / rigid["PC"][q] - 1.0)
                               for k in fe], "text": [labels[k]["label"] for k in fe],
                         "name": "FE bodies, engine",
                         "marker": {"symbol": "square", "color": "#1f77b4"}})
            layout = {
                "xaxis": {"title": {"text": "beam first bending (Hz); FE bodies at 16.5+"},
                          "tickvals": [5, 7.5, 10, 12.5, 15, *fe_x.values()],
                          "ticktext": ["5", "7.5", "10", "12.5", "15", *fe]},
                "yaxis": {"title": {"text": "flexible/rigid − 1 (%)"}},
                "shapes": [{"type": "rect", "xref": "paper", "x0": 0, "x1": 1,
                            "y0": 50.0 * paper, "y1": 200.0 * paper, "line": {"width": 0},
                            "fillcolor": "rgba(44,160,44,0.25)"}],
                "margin": {"l": 60, "r": 10, "t": 30, "b": 45}, "height": 340,
                "legend": {"orientation": "h", "y": -0.3}}
            out.append({"title": f"PC {q}, {v} km/h (green: the paper's +"
                                 f"{100 * paper:.1f} %, ½–2×)", "data": data,
                        "layout": layout})
    return out


def figures(m: CarbodyMap) -> list[dict[str, Any]]:
    """The map as a report figure (``{"id", "title", "paper", "panels", "note"}``; its panels
    sit in :func:`section_html`).
    """
    return [{"id": ANCHOR, "title": "the flexible effect at PC over the car-body map",
             "paper": "Table 2, §5.1", "panels": _panels(m),
             "note": f"from {m.path.name} ({PRODUCER})"}]


def annotate(claims: list[dict[str, Any]], m: CarbodyMap) -> list[dict[str, Any]]:
    """The report's claims with, in the notes of those the map speaks to, one sentence on
    what the map found (the verdicts are unchanged).
    """
    rows = evidence(m)
    ids: dict[str, list[PcClaim]] = {}
    for c in CLAIMS:
        for i in c.claim_ids:
            ids.setdefault(i, []).append(c)
    out = []
    for claim in claims:
        extra = []
        for c in ids.get(claim["id"], []):
            yes = [r for r in rows if r["claim"] == c.key and r["reproduced"]
                   and r["key"] != "rigid"]
            tried = len({r["input"] for r in rows if r["claim"] == c.key})
            found = ("; reproduced by " + ", ".join(sorted({r["input"] for r in yes}))
                     if yes else ": none reproduces it")
            extra.append(f"The car-body map ({ANCHOR}) tried {tried} admissible car bodies "
                         f"for '{c.text}'{found}.")
        out.append(claim | {"note": " ".join([claim["note"], *extra]).strip()}
                   if extra else claim)
    return out

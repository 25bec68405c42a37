"""Study: the car-body map of issue 26 §3 — the frequency engine over the open inputs, and the
time-domain solver at the map's corners with several irregularity seeds.

The map (docs/fem.md, "The car-body map: frequency engine and time-domain corners") is the
flexible/rigid change of the vertical comfort at the floor centre (PC) and the other points on
the paper's random straight case (``paper-random-straight-80`` and ``-50``) over the inputs the
paper leaves open:

* the assignment of mode types to Table 1 (:mod:`carbody_mode_assignments`): the bodies that
  hold — the calibrated default, first vertical bending sixth by name (``vb6``) — and the one
  that nearly holds (the paper's §5.1 reading, ``paper-5.1``, 6.7 %), FE car body at 0.5 m as
  in that study;
* the beam car body's first bending frequency f_b from 5 to 15 Hz (:mod:`beam_bending_sweep`),
  with the mass where the vehicle's pitch inertia puts it (``beam_mass: pitch_inertia``, the
  scenario's default) and uniform (the literature's beam).

The frequency engine (:func:`flexride.frequency.estimate`; linear) gives the whole map. At its
corners — rigid, the three FE bodies, and both beams at 5 and 15 Hz — the time-domain solver
(:func:`flexride.solver.simulate`; nonlinear contact) runs ``--seeds`` irregularity
realisations (:func:`flexride.study.seeds.seed_overrides`, the rule of the paper report), each
body on the same track as the rigid body, and the flexible/rigid ratio is taken seed by seed
(mean and 95 % CI, Student t: :func:`flexride.paper.measures.mean_ci`). The evaluated stretch is
the paper report's (:func:`flexride.paper.plan.full_window`: from 30 m to the preset's 400 m)
and the analysis its (:func:`flexride.analysis.analyze`): vertical rms of the raw record,
Sperling (spectral form, and the filter form the report reads the paper's "RMS index" as) and
the ISO 2631 Wk weighted rms.

Nothing is tuned: the FE bodies' variable values come from the seeded search of
:mod:`carbody_mode_assignments` (reproduced here with its own functions and seeds, then kept in
the output JSON and reused by later runs), the beams from the scenario schema.

Output: the JSON ``--out`` (default ``backend/flexride/paper/data/carbody_map.json``, read by
the paper report, :mod:`flexride.paper.carbody_map`), Markdown tables on stdout and, with
matplotlib, the figure ``--figure`` (default ``docs/img/carbody_map.png``).

Usage::

    python tools/studies/carbody_map_time_domain.py [--seeds 8] [--speeds 80 50] \
        [--element-size 0.5] [--workers 2] [--out PATH] [--figure PATH] [--search]

(``--search`` repeats the FE bodies' search even when the output JSON holds their values;
``--replot`` prints the tables and draws the figure from the stored JSON without running.)
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = "tools/studies/carbody_map_time_domain.py"
DEFAULT_OUT = ROOT / "backend/flexride/paper/data/carbody_map.json"
DEFAULT_FIGURE = ROOT / "docs/img/carbody_map.png"
FORMAT = 1

POINTS = ("PR", "PFB", "PC", "PRB", "PLA", "PRA")
#: Quantities (vertical): unweighted rms (m/s²), Sperling spectral form, Sperling filter form
#: (the report's reading of the paper's "RMS index"), ISO 2631 Wk weighted rms (m/s²).
QUANTITIES = ("rms", "sperling", "sperling_filter", "Wk")
FE_CUTOFF_HZ = 40.0
BEAM_CUTOFF_HZ = 80.0
ZETA = 0.02
BEAM_SWEEP_HZ = tuple(float(f) for f in np.arange(5.0, 15.01, 0.5))
#: The paper's claims about PC (Table 2 and §5.1), flexible over rigid.
PAPER = {"sperling": 0.035, "rms_index": 0.065}


@dataclass(frozen=True)
class Corner:
    """One car body at a corner of the map.

    Attributes
    ----------
    key : str
        Short name (the JSON's key).
    label : str
        Text for tables.
    kind : {"rigid", "fe", "beam"}
        Rigid car body, FE car body (variable values of :mod:`carbody_mode_assignments`) or
        beam car body (:mod:`flexride.fem.beam`).
    source : str
        Where the body comes from.
    first_bending_hz : float or None
        The beam's first vertical bending (Hz).
    beam_mass : str or None
        The beam's ``beam_mass``.
    """

    key: str
    label: str
    kind: str
    source: str
    first_bending_hz: float | None = None
    beam_mass: str | None = None


CORNERS: tuple[Corner, ...] = (
    Corner("rigid", "rigid", "rigid", "the rigid car body (6 rigid modes)"),
    Corner("default", "FE default", "fe", "CARBODY_CALIBRATED: Table 1 by rank, any type"),
    Corner("vb6", "FE, 1VB sixth by name", "fe", "carbody_mode_assignments 'vb6' (holds, "
           "by the classifier's name)"),
    Corner("paper-5.1", "FE, paper §5.1 (near)", "fe", "carbody_mode_assignments "
           "'paper-5.1' (types right, 6.7 % off Table 1)"),
    Corner("beam-5", "beam 5 Hz (pitch Iyy)", "beam", "bodies.carbody.model: beam",
           5.0, "pitch_inertia"),
    Corner("beam-15", "beam 15 Hz (pitch Iyy)", "beam", "bodies.carbody.model: beam",
           15.0, "pitch_inertia"),
    Corner("beam-uniform-5", "beam 5 Hz (uniform)", "beam", "bodies.carbody.model: beam, "
           "beam_mass: uniform", 5.0, "uniform"),
    Corner("beam-uniform-15", "beam 15 Hz (uniform)", "beam", "bodies.carbody.model: beam, "
           "beam_mass: uniform", 15.0, "uniform"),
)
"""The corners of the map run in the time domain."""

#: The FE bodies found by the search of carbody_mode_assignments (its ASSIGNMENTS keys).
SEARCHED = ("vb6", "paper-5.1")


# --- the FE bodies' variable values ------------------------------------------------------------

def _study_module() -> Any:
    """:mod:`carbody_mode_assignments` (a sibling script)."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    return importlib.import_module("carbody_mode_assignments")


def search_bodies(element_size: float, workers: int) -> dict[str, dict[str, Any]]:
    """The variable values of the default FE body and of the bodies of :data:`SEARCHED`, by
    the search of :mod:`carbody_mode_assignments` with its seeds (its reach survey, seed 7,
    200 samples; its (1 + 8) strategy, seed 11 + the assignment's index, 20 generations; its
    least-squares polish): the same points as its run.

    Returns
    -------
    dict
        By key: ``variables`` (dict), ``error`` (largest |error| against Table 1, -),
        ``types_ok`` (bool), ``modes_hz`` and ``types`` of modes 1–6.
    """
    cma = _study_module()
    ev = cma._evaluator(element_size)
    default = ev({n: float(getattr(ev.base, n)) for n in cma.NAMES})
    pts = cma.reach(ev, 200, workers)
    out = {"default": _body_entry(None, default)}
    index = [k for key in SEARCHED for k, a in enumerate(cma.ASSIGNMENTS) if a.key == key]
    n = len(index)
    with ProcessPoolExecutor(workers) as pool:
        found = list(pool.map(cma._search_one, index, [element_size] * n,
                              [[*pts, default]] * n, [20] * n))
    for key, k, (p, _) in zip(SEARCHED, index, found, strict=True):
        out[key] = _body_entry(cma.ASSIGNMENTS[k], p)
    return out


def _body_entry(assignment: Any, p: Any) -> dict[str, Any]:
    return {"variables": {k: float(f"{v:.6g}") for k, v in p.x.items()},
            "error": round(float(p.error()), 5),
            "types_ok": assignment is None or not assignment.failures(p),
            "modes_hz": [round(float(f), 3) for f in p.f[:6]], "types": list(p.types[:6])}


# --- bodies -----------------------------------------------------------------------------------

def car_body(corner: Corner, bodies: dict[str, dict[str, Any]], element_size: float) -> Any:
    """The ModalBody of a corner (None for the rigid body)."""
    from flexride.fem.beam import beam_carbody
    from flexride.fem.carbody import CarBodyParams
    from flexride.fem.defaults import default_carbody_params
    from flexride.fem.flexible import build_flexible_body
    from flexride.fem.vehicle_models import carbody_params_for
    from flexride.scenario.presets import load_preset

    vehicle = load_preset("paper-metro").vehicle
    if corner.kind == "rigid":
        return None
    if corner.kind == "beam":
        assert corner.first_bending_hz is not None and corner.beam_mass is not None
        return beam_carbody(vehicle, corner.first_bending_hz, BEAM_CUTOFF_HZ, ZETA,
                            CarBodyParams().length, corner.beam_mass)  # type: ignore[arg-type]
    base = carbody_params_for(vehicle, default_carbody_params())
    params = base.with_values(**bodies[corner.key]["variables"])
    return build_flexible_body("carbody", vehicle, "modal", FE_CUTOFF_HZ, ZETA, element_size,
                               params=params).body


def vehicle_with(body: Any) -> Any:
    """The paper vehicle with the car body ``body`` (None: the rigid vehicle, which the solver
    builds from the scenario). Built once per body: building adds the suspension's markers to
    the body, and the vehicle serves every run of the body (both speeds share the vehicle data
    and the output points).
    """
    from flexride.scenario.presets import load_preset
    from flexride.vehicle.topology import build_vehicle

    sc = load_preset("paper-random-straight-80")
    return None if body is None else build_vehicle(sc.vehicle, sc.output, carbody=body)


# --- the frequency engine ---------------------------------------------------------------------

def engine(sc: Any, vehicle: Any) -> dict[str, dict[str, float]]:
    """Vertical comfort of :data:`POINTS` by the frequency engine (``vehicle`` from
    :func:`vehicle_with`): point → quantity → value.
    """
    from flexride.frequency import estimate

    table = estimate(sc, points=list(POINTS), vehicle=vehicle).comfort
    out = {}
    for p in POINTS:
        d = table.point(p).directions["z"]
        out[p] = {"rms": d.rms, "sperling": d.sperling, "sperling_filter": d.sperling_filter,
                  "Wk": d.iso["Wk"]}
    return out


def frequency_map(speeds: Sequence[int], corners: dict[str, Any]) -> dict[str, Any]:
    """The frequency engine at every corner and along both beams' f_b from 5 to 15 Hz."""
    from flexride.fem.beam import beam_carbody
    from flexride.fem.carbody import CarBodyParams
    from flexride.scenario.presets import load_preset

    out: dict[str, Any] = {}
    for v in speeds:
        sc = load_preset(f"paper-random-straight-{v}")
        at = {key: _round(engine(sc, veh)) for key, veh in corners.items()}
        sweep: dict[str, Any] = {}
        for mass in ("pitch_inertia", "uniform"):
            rows = [_round(engine(sc, vehicle_with(beam_carbody(
                sc.vehicle, f, BEAM_CUTOFF_HZ, ZETA, CarBodyParams().length, mass))))
                    for f in BEAM_SWEEP_HZ]
            print(f"  engine: {v} km/h, beam {mass}, {len(rows)} f_b", file=sys.stderr,
                  flush=True)
            sweep[mass] = {"first_bending_hz": list(BEAM_SWEEP_HZ),
                           "values": {p: {q: [r[p][q] for r in rows] for q in QUANTITIES}
                                      for p in POINTS}}
        out[str(v)] = {"corners": at, "beam_sweep": sweep}
    return out


def _round(d: dict[str, dict[str, float]], digits: int = 5) -> dict[str, dict[str, float]]:
    return {p: {q: float(f"{x:.{digits}g}") for q, x in qs.items()} for p, qs in d.items()}


# --- the time domain --------------------------------------------------------------------------

def _time_run(job: tuple[int, int, str, Any]) -> tuple[int, int, str, dict[str, Any]]:
    """One solver run (speed km/h, seed, corner key, vehicle from :func:`vehicle_with`): the
    window's vertical comfort, wall time and step.
    """
    from flexride.analysis import analyze
    from flexride.paper.plan import full_window
    from flexride.paper.record import window_results
    from flexride.scenario.presets import PAPER_CONDITIONS, load_preset
    from flexride.solver.simulate import simulate
    from flexride.study.seeds import seed_overrides

    v, seed, key, vehicle = job
    t0 = time.perf_counter()
    exc = PAPER_CONDITIONS["random-straight"][2]
    sc = load_preset(f"paper-random-straight-{v}", seed_overrides(exc, seed))
    res = simulate(sc, vehicle=vehicle)
    start, end, _ = full_window("random-straight")
    summary = analyze(window_results(res, (start, end)))
    vals: dict[str, dict[str, float]] = {}
    for p in POINTS:
        d = summary.points[p].directions["z"]
        assert d.sperling is not None and d.sperling_alternative is not None
        vals[p] = {"rms": float(d.peaks.rms), "sperling": float(d.sperling.value),
                   "sperling_filter": float(d.sperling_alternative.value),
                   "Wk": float(d.iso2631["Wk"].a_w)}
    return v, seed, key, {"values": _round(vals), "wall_s": time.perf_counter() - t0,
                          "dt": float(res.meta["dt"]), "n_steps": int(res.meta["n_steps"]),
                          "window_m": [start, end]}


def time_domain(speeds: Sequence[int], seeds: Sequence[int], corners: dict[str, Any]
                ) -> tuple[dict[str, Any], dict[str, Any]]:
    """Every corner at every speed and seed, one run after the other (the machine is shared):
    per-seed values and the run cost.
    """
    jobs = [(v, s, key, veh) for v in speeds for s in seeds for key, veh in corners.items()]
    out: dict[str, Any] = {str(v): {key: {"seeds": [], "values": {p: {q: [] for q in QUANTITIES}
                                                                   for p in POINTS}}
                                    for key in corners} for v in speeds}
    walls: list[float] = []
    steps: dict[str, int] = {}
    window: list[float] = []
    t0 = time.perf_counter()
    done = []
    for job in jobs:
        done.append(_time_run(job))
        v, s, key, r = done[-1]
        print(f"  {v} km/h seed {s} {key}: {r['wall_s']:.1f} s", file=sys.stderr, flush=True)
    for v, s, key, r in sorted(done, key=lambda d: (d[0], d[1])):
        entry = out[str(v)][key]
        entry["seeds"].append(s)
        for p in POINTS:
            for q in QUANTITIES:
                entry["values"][p][q].append(r["values"][p][q])
        walls.append(r["wall_s"])
        steps[str(v)] = r["n_steps"]
        window = r["window_m"]
        dt = r["dt"]
    cost = {"runs": len(jobs), "workers": 1, "wall_s": round(time.perf_counter() - t0, 1),
            "run_wall_s_mean": round(float(np.mean(walls)), 2),
            "run_wall_s_max": round(float(np.max(walls)), 2), "dt_s": dt,
            "steps_per_run": steps, "window_m": window}
    return out, cost


def paired(td: dict[str, Any], key: str, point: str, q: str) -> Any:
    """Flexible/rigid ratio of one quantity, seed by seed (same track): mean ± 95 % CI."""
    from flexride.paper.measures import mean_ci

    rigid = dict(zip(td["rigid"]["seeds"], td["rigid"]["values"][point][q], strict=True))
    body = td[key]
    ratios = [x / rigid[s] for s, x in zip(body["seeds"], body["values"][point][q],
                                           strict=True) if s in rigid]
    return mean_ci(ratios)


# --- output -----------------------------------------------------------------------------------

def _git_commit() -> str | None:
    """The commit of the code that ran: ``$FLEXRIDE_SOURCE_COMMIT`` (a run from an exported
    tree), else ``git rev-parse HEAD`` beside the script.
    """
    if os.environ.get("FLEXRIDE_SOURCE_COMMIT"):
        return os.environ["FLEXRIDE_SOURCE_COMMIT"]
    try:
        return subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None


def _pct(x: float) -> str:
    return f"{100.0 * x:+.1f} %"


def print_tables(data: dict[str, Any]) -> None:
    """Markdown: time domain (mean ± CI of the paired ratio) against the frequency engine."""
    for v, td in data["time_domain"].items():
        fm = data["frequency"][v]["corners"]
        n = len(td["rigid"]["seeds"])
        print(f"\n### {v} km/h: flexible/rigid − 1, time domain ({n} seeds, mean ± 95 % CI) "
              "/ frequency engine\n")
        cols = [("PC", "rms"), ("PC", "sperling"), ("PC", "sperling_filter"), ("PC", "Wk"),
                ("PFB", "rms"), ("PR", "rms"), ("PRB", "rms"), ("PLA", "rms")]
        print("| car body | " + " | ".join(f"{p} {q}" for p, q in cols) + " | PC quietest |")
        print("| --- " * (len(cols) + 2) + "|")
        for key in td:
            if key == "rigid":
                cells = [f"{np.mean(td['rigid']['values'][p][q]):.4g} / {fm['rigid'][p][q]:.4g}"
                         for p, q in cols]
            else:
                cells = []
                for p, q in cols:
                    e = paired(td, key, p, q)
                    f = fm[key][p][q] / fm["rigid"][p][q] - 1.0
                    cells.append(f"{_pct(e.mean - 1)} ± {100 * (e.ci95 or 0):.1f} / {_pct(f)}")
            quiet = quietest(td[key]["values"])
            print(f"| {key} | " + " | ".join(cells) + f" | {quiet} |")


def quietest(values: dict[str, dict[str, list[float]]]) -> str:
    """How many seeds have PC's rms below PR, PFB and PRB's (e.g. ``0/8``)."""
    n = len(values["PC"]["rms"])
    k = sum(all(values["PC"]["rms"][i] < values[p]["rms"][i] for p in ("PR", "PFB", "PRB"))
            for i in range(n))
    return f"{k}/{n}"


def figure(data: dict[str, Any], path: Path) -> bool:
    """The map as one PNG (matplotlib; False when it is not installed)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return False
    speeds = list(data["frequency"])
    qs = [("sperling", "PC Sperling W (spectral)", PAPER["sperling"]),
          ("sperling_filter", "PC Sperling filter form ('RMS index')", PAPER["rms_index"]),
          ("rms", "PC rms", PAPER["rms_index"])]
    fig, axes = plt.subplots(len(speeds), len(qs), figsize=(12, 3.4 * len(speeds)),
                             squeeze=False)
    fe_keys = [c.key for c in CORNERS if c.kind == "fe"]
    fe_x = {k: 17.0 + 1.5 * i for i, k in enumerate(fe_keys)}
    for r, v in enumerate(speeds):
        fm = data["frequency"][v]
        td = data["time_domain"][v]
        for c, (q, title, claim) in enumerate(qs):
            ax = axes[r][c]
            rig = fm["corners"]["rigid"]["PC"][q]
            for mass, style in (("pitch_inertia", "-"), ("uniform", "--")):
                sw = fm["beam_sweep"][mass]
                y = 100.0 * (np.asarray(sw["values"]["PC"][q]) / rig - 1.0)
                ax.plot(sw["first_bending_hz"], y, style, color="C0", lw=1.2,
                        label=f"beam ({mass.replace('_', ' ')}), engine")
            for k in fe_keys:
                ax.plot(fe_x[k], 100.0 * (fm["corners"][k]["PC"][q] / rig - 1.0), "s",
                        color="C0", ms=6, label="FE bodies, engine" if k == fe_keys[0]
                        else None)
            for corner in CORNERS:
                if corner.key == "rigid":
                    continue
                e = paired(td, corner.key, "PC", q)
                x = fe_x.get(corner.key, corner.first_bending_hz)
                x = x + (0.15 if corner.beam_mass == "uniform" else 0.0) if x else x
                ax.errorbar(x, 100.0 * (e.mean - 1.0), yerr=100.0 * (e.ci95 or 0.0), fmt="o",
                            color="C3", ms=4, capsize=3,
                            label="time domain, mean ± 95 % CI" if corner.key == "default"
                            else None)
            ax.axhspan(50.0 * claim, 200.0 * claim, color="C2", alpha=0.25,
                       label="the paper's change, ½–2× (W +3.5 %; RMS index, rms +6.5 %)")
            ax.axhline(0.0, color="k", lw=0.6)
            ax.set_yscale("symlog", linthresh=5.0)
            ax.set_xticks([5, 7.5, 10, 12.5, 15, *fe_x.values()],
                          ["5", "7.5", "10", "12.5", "15", *fe_keys], fontsize=7)
            for label in ax.get_xticklabels()[5:]:
                label.set_rotation(35)
                label.set_horizontalalignment("right")
            ax.set_title(f"{title}, {v} km/h", fontsize=9)
            ax.set_xlabel("beam first bending (Hz) | FE bodies", fontsize=8)
            ax.set_ylabel("flexible/rigid − 1 (%)", fontsize=8)
            ax.tick_params(labelsize=7)
    handles, names = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, names, loc="lower center", ncol=len(names), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0.0, 0.04, 1.0, 1.0))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return True


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=8, help="irregularity realisations")
    ap.add_argument("--speeds", type=int, nargs="+", default=[80, 50],
                    help="speeds (km/h) of paper-random-straight-<speed>")
    ap.add_argument("--element-size", type=float, default=0.5, help="FE shell size (m)")
    ap.add_argument("--workers", type=int, default=1,
                    help="processes for the FE bodies' search (the solver runs are serial)")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT, help="output JSON")
    ap.add_argument("--figure", type=Path, default=DEFAULT_FIGURE, help="output PNG")
    ap.add_argument("--search", action="store_true",
                    help="repeat the FE bodies' search even if --out holds their values")
    ap.add_argument("--replot", action="store_true",
                    help="only print the tables and draw the figure from --out (no runs)")
    args = ap.parse_args()
    if args.replot:
        data = json.loads(args.out.read_text())
        print_tables(data)
        figure(data, args.figure)
        return
    t0 = time.perf_counter()
    old = json.loads(args.out.read_text()) if args.out.exists() else {}
    same_mesh = old.get("settings", {}).get("element_size_m") == args.element_size
    if not args.search and same_mesh and set(SEARCHED) <= set(old.get("bodies", {})):
        bodies, searched_s = old["bodies"], old["provenance"]["cost"]["search_wall_s"]
        print("FE bodies: reused from " + str(args.out), file=sys.stderr)
    else:
        t = time.perf_counter()
        bodies = search_bodies(args.element_size, max(1, args.workers))
        searched_s = round(time.perf_counter() - t, 1)
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(json.dumps({  # kept at once: the search is the long part
            "settings": {"element_size_m": args.element_size}, "bodies": bodies,
            "provenance": {"cost": {"search_wall_s": searched_s}}}) + "\n")
    for key, b in bodies.items():
        print(f"{key}: error {100 * b['error']:.1f} %, types ok {b['types_ok']}: "
              + ", ".join(f"{n} {x:.4g}" for n, x in b["variables"].items()), file=sys.stderr)
    corners = {c.key: vehicle_with(car_body(c, bodies, args.element_size)) for c in CORNERS}
    t = time.perf_counter()
    freq = frequency_map(args.speeds, corners)
    freq_s = round(time.perf_counter() - t, 1)
    seeds = list(range(1, args.seeds + 1))
    td, cost = time_domain(args.speeds, seeds, corners)
    cost |= {"search_wall_s": searched_s, "frequency_wall_s": freq_s,
             "total_wall_s": round(time.perf_counter() - t0, 1), "cpus": os.cpu_count()}
    data = {
        "format": FORMAT,
        "provenance": {
            "script": SCRIPT,
            "command": "python " + SCRIPT + " " + " ".join(sys.argv[1:]),
            "generated": datetime.now(UTC).strftime("%Y-%m-%d %H:%M UTC"),
            "git_commit": _git_commit(), "cost": cost},
        "settings": {
            "case": "paper-random-straight-<speed> (German high disturbance, straight, "
                    "real profiles), car body only flexible (frames rigid)",
            "speeds_kmh": args.speeds, "seeds": seeds, "element_size_m": args.element_size,
            "fe_cutoff_hz": FE_CUTOFF_HZ, "beam_cutoff_hz": BEAM_CUTOFF_HZ,
            "damping_ratio": ZETA, "points": list(POINTS), "quantities": list(QUANTITIES),
            "direction": "z", "paper": PAPER},
        "corners": [{"key": c.key, "label": c.label, "kind": c.kind, "source": c.source,
                     "first_bending_hz": c.first_bending_hz, "beam_mass": c.beam_mass}
                    for c in CORNERS],
        "bodies": bodies,
        "frequency": freq,
        "time_domain": td,
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(data, indent=None, separators=(",", ":")) + "\n")
    print_tables(data)
    drawn = figure(data, args.figure)
    where = f"written to {args.figure}" if drawn else "not drawn: no matplotlib"
    print(f"\n(cost: {json.dumps(cost)}; figure {where})")


if __name__ == "__main__":
    main()

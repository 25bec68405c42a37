"""Study: ride comfort and running safety with real wheel/rail profiles against the conical tread.

Runs the paper's random straight and random curve conditions (German high disturbance,
50–80 km/h, the presets' 400 m) with the car body rigid and flexible, once with the conical
tread of the first releases (conicity 0.05, flange contact as a dead-band spring, Δt 1e-4 s:
``presets.CONICAL_TREAD``) and once as the presets run: real profiles (S1002 on 60E1 at 1:40,
flange-back distance 1.36 m, Δt 1/12000 s: docs/model.md), and prints

* lateral and vertical Sperling indices (spectral form) at PC, PFB and PR,
* on the curve, the running-safety maxima: derailment coefficient Q/P, wheel unloading ΔP/P
  and wheelset lateral force ΣY with their limits.

The reading of the figures is in docs/model.md ("Real profiles on the paper's case"). Nothing
here is tuned to the paper: the inputs are the presets' own.

Usage: ``python tools/studies/profiles_vs_conical.py [--speeds 50 60 70 80] [--distance M]
[--jobs 1] [--json FILE]``
"""

from __future__ import annotations

import argparse
import json
from concurrent.futures import ProcessPoolExecutor
from typing import Any

from flexride.analysis import analyze
from flexride.scenario.presets import CONICAL_TREAD, load_preset
from flexride.solver.simulate import simulate

POINTS = ("PC", "PFB", "PR")
SAFETY = ("derailment_coefficient", "wheel_unloading", "wheelset_lateral_force")


def _case(condition: str, speed: int, body: str, geometry: str,
          distance: float | None) -> dict[str, Any]:
    overrides: dict[str, Any] = {"bodies.carbody.model": body}
    if distance is not None:
        overrides["distance_m"] = distance
    if geometry == "conical":  # the presets run S1002/60E1; the cone of the first releases
        overrides.update(CONICAL_TREAD)
    sc = load_preset(f"paper-random-{condition}-{speed}", overrides)
    summary = analyze(simulate(sc))
    row: dict[str, Any] = {"condition": condition, "speed_kmh": speed, "body": body,
                           "geometry": geometry}
    for p in POINTS:
        for d, key in (("y", "lat"), ("z", "vert")):
            s = summary.points[p].directions[d].sperling
            row[f"{p}_{key}"] = None if s is None else float(s.value)
    if summary.safety is not None:
        for name in SAFETY:
            worst = summary.safety.worst(name)
            if worst is not None:
                row[name] = {"value": worst.value, "limit": worst.limit,
                             "location": worst.location}
    return row


def _fmt(value: float | None) -> str:
    return f"{'—':>10s}" if value is None else f"{value:10.3f}"


def _print(rows: list[dict[str, Any]]) -> None:
    head = "".join(f"{p + ' ' + k:>10s}" for p in POINTS for k in ("lat", "vert"))
    print(f"{'condition':<8s}{'km/h':>5s} {'body':<9s}{'geometry':<10s}{head}")
    for r in rows:
        vals = "".join(_fmt(r[f"{p}_{k}"]) for p in POINTS for k in ("lat", "vert"))
        print(f"{r['condition']:<8s}{r['speed_kmh']:>5d} {r['body']:<9s}{r['geometry']:<10s}"
              f"{vals}")
    print("\nrunning safety on the curve (worst wheel or wheelset; value / limit)")
    for r in rows:
        if r["condition"] != "curve":
            continue
        parts = [f"{n}: {r[n]['value']:.3f}/{r[n]['limit']:.3g} at {r[n]['location']}"
                 for n in SAFETY if n in r]
        print(f"  {r['speed_kmh']:>3d} km/h {r['body']:<8s} {r['geometry']:<9s} "
              + "; ".join(parts))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speeds", type=int, nargs="+", default=[50, 60, 70, 80])
    ap.add_argument("--distance", type=float, help="run length (m; default the presets' 400 m)")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes")
    ap.add_argument("--json", help="also write the rows to this JSON file")
    args = ap.parse_args()
    cases = [(c, v, b, g, args.distance) for c in ("straight", "curve") for v in args.speeds
             for b in ("rigid", "flexible") for g in ("conical", "profiles")]
    with ProcessPoolExecutor(args.jobs) as pool:
        rows = list(pool.map(_case, *zip(*cases, strict=True)))
    _print(rows)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()

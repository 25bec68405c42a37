"""Frequency-domain estimate performance (prints figures; not a timed test).

* building the linear models of the paper's eight random conditions (straight and curve at
  50/60/70/80 km/h; the curves are flagged — flange contact of the leading wheelsets at
  equilibrium — and built with ``strict=False``);
* the response PSDs and comfort tables of all eight conditions at the six paper points once
  the models are built (target ≤ 1 s on one core);
* a 100-value sweep of the secondary vertical stiffness (target ≤ 5 s on one core; wall and
  CPU time are printed, and what the rebuilds reused), and its first values against
  rebuilds from scratch: the largest relative difference of any comfort index, ≤ 1e-3 with
  the presets' statistically linearised profile contact (each value's σ iteration starts
  from the previous value's and stops within 0.1 % of the fixed point) and ≤ 1e-9 with the
  local linearisation (every reuse exact);
* the ratio to the equivalent time-domain runs (measured on the 80 km/h straight run, per
  simulated second, times the simulated time of the eight conditions; ``--full`` runs all
  eight instead).

BLAS runs on one thread (the targets are per core). Usage:
``python benchmarks/bench_frequency.py [--full] [--sweep-values N] [--sweep-only]``
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

TARGET_SET_S = 1.0
TARGET_SWEEP_S = 5.0
SPEEDS = (50, 60, 70, 80)


def _conditions() -> list[str]:
    return [f"paper-random-{line}-{v}" for line in ("straight", "curve") for v in SPEEDS]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="run all eight time-domain cases")
    parser.add_argument("--sweep-values", type=int, default=100)
    parser.add_argument("--sweep-only", action="store_true",
                        help="only the sweep (and its check against rebuilds)")
    args = parser.parse_args()
    if args.sweep_only:
        _sweep(args.sweep_values)
        return

    from flexride.frequency import comfort, linear_model, response
    from flexride.scenario.presets import load_preset
    from flexride.solver.simulate import simulate

    print("flexride frequency-domain benchmark (one BLAS thread)")
    scenarios = [load_preset(n) for n in _conditions()]
    linear_model(scenarios[0])  # compile / warm the numba cache
    t = time.perf_counter()
    models = [linear_model(sc, strict=False) for sc in scenarios]
    t_models = time.perf_counter() - t
    print(f"linear models of the 8 conditions          : {t_models:7.2f} s "
          f"({t_models / 8:.2f} s each, {models[0].system.n} coordinates)")
    for m in models:
        if m.flags:
            print(f"  {m.scenario.name}: flagged — {m.flags[0][:90]}…")
    best = np.inf
    for _ in range(3):
        t = time.perf_counter()
        tables = [comfort(response(m, points=["PR", "PFB", "PC", "PRB", "PLA", "PRA"]))
                  for m in models]
        best = min(best, time.perf_counter() - t)
    print(f"response + comfort, 8 conditions × 6 points: {best:7.3f} s (target ≤ "
          f"{TARGET_SET_S:g} s) {'OK' if best <= TARGET_SET_S else 'MISSED'}")

    _sweep(args.sweep_values)

    names = _conditions() if args.full else ["paper-random-straight-80"]
    t_sim = sum(sc.duration for sc in scenarios)
    wall = 0.0
    simulated = 0.0
    for n in names:
        sc = load_preset(n)
        t = time.perf_counter()
        simulate(sc)
        wall += time.perf_counter() - t
        simulated += sc.duration
    td = wall if args.full else wall / simulated * t_sim
    print(f"time domain, 8 conditions ({t_sim:.0f} s simulated): {td:7.1f} s "
          f"({'measured' if args.full else 'scaled from the 80 km/h straight run'})")
    print(f"ratio time domain / frequency domain (after the models): {td / best:7.0f}×; "
          f"including the model builds: {td / (best + t_models):5.1f}×")
    pc = tables[3].point("PC").directions["z"]
    print(f"check: PC vertical at 80 km/h, rms {pc.rms:.3f} m/s², Wb {pc.iso['Wb']:.3f} m/s², "
          f"Sperling {pc.sperling:.2f}")


def _indices(table) -> dict:
    """Every comfort index of a table by (point, direction, name)."""
    out = {}
    for p in table.points:
        for d, dc in p.directions.items():
            out.update({(p.name, d, q): getattr(dc, q)
                        for q in ("rms", "sperling", "sperling_filter", "a_p95", "peak")})
            out.update({(p.name, d, w): v for w, v in dc.iso.items()})
    return out


def _sweep(n_values: int, n_check: int = 5) -> None:
    """The sweep of the secondary vertical stiffness at 80 km/h, timed, and its first values
    against rebuilds from scratch.
    """
    from flexride.frequency import linear_model, sweep
    from flexride.scenario.presets import load_preset

    scenario = load_preset("paper-random-straight-80")
    linear_model(scenario)  # numba kernels loaded
    values = np.linspace(2.0e5, 5.0e5, n_values).tolist()
    cpu = time.process_time()
    res = sweep(scenario, "vehicle.secondary.kz", values, points=["PC"])
    cpu = time.process_time() - cpu
    ok = cpu <= TARGET_SWEEP_S
    print(f"sweep of {len(values)} values (vehicle.secondary.kz): {res.seconds:7.2f} s wall, "
          f"{cpu:.2f} s CPU (target ≤ {TARGET_SWEEP_S:g} s on one core) "
          f"{'OK' if ok else 'MISSED'}; {1e3 * cpu / len(values):.0f} ms CPU per value")
    print(f"  reused: {dict(sorted(res.reuse.items()))}")
    for method, limit in (("statistical", 1e-3), ("local", 1e-9)):
        fast = res if method == "statistical" else sweep(
            scenario, "vehicle.secondary.kz", values[:n_check], points=["PC"],
            linearisation=method)
        ref = sweep(scenario, "vehicle.secondary.kz", values[:n_check], points=["PC"],
                    reuse=False, linearisation=method)
        worst = _worst_difference(fast.tables[:n_check], ref.tables)
        print(f"  first {n_check} values against rebuilds from scratch, {method} "
              f"linearisation ({ref.seconds:.2f} s): largest relative difference {worst:.1e} "
              f"(≤ {limit:g})")


def _worst_difference(tables, reference) -> float:
    """Largest relative difference of any comfort index between two lists of tables."""
    worst = 0.0
    for a, b in zip(tables, reference, strict=True):
        ia, ib = _indices(a), _indices(b)
        worst = max(worst, max(abs(ia[k] - ib[k]) / abs(ib[k]) for k in ia if ib[k]))
    return worst


if __name__ == "__main__":
    main()

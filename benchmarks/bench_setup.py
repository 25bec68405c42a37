"""Set-up of a run (assembly, static equilibrium, stability check) for the paper vehicle,
rigid and flexible, at every paper condition: computed, and from the set-up cache.

A command that prints figures, not a test. Per condition and body model it times, in this
process with compiled kernels and the FE bodies already built (their cached load is timed on
its own line):

* ``miss``: the set-up with an empty set-up cache (computed), wall and CPU time;
* ``hit``: the same scenario again (static equilibrium, steady states and step limits from
  memory);
* ``disk``: from the cache file, as another worker process would get it.

The targets (issue 25) are ≤ 3 s computed and ≤ 0.3 s from the cache for every condition
(:data:`TARGET_S`); the ratio to them is printed for the worst of each kind. CPU times are
printed beside wall times because other work on the machine inflates the wall times (the load
average is printed). Repeats take the best.

Usage::

    .venv/bin/python benchmarks/bench_setup.py [--repeat 3] [--conical]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

TARGET_S = {"miss": 3.0, "hit": 0.3, "disk": 0.3}
CONDITIONS = ("random-straight", "random-curve", "corrugation", "settlement")
SPEEDS = (50, 80)


def _load() -> str:
    one, five, _ = os.getloadavg()
    return f"load average {one:.2f} (1 min), {five:.2f} (5 min)"


def _setup_time(scenario, vehicle, cache) -> tuple[float, float, str]:
    """Wall and CPU time (s) of the set-up of ``scenario`` (assembly, static equilibrium, the
    time-step limit over its operating points, the step) and where it came from."""
    from flexride.solver.assemble import assemble
    from flexride.solver.simulate import CONTACT_TABLES, prepare_run, small_dense_problems

    t, c = time.perf_counter(), time.process_time()
    with small_dense_problems():
        asm = assemble(scenario, vehicle=vehicle, contact_tables=CONTACT_TABLES)
        _asm, ready = prepare_run(scenario, asm, cache, check=True)
    return time.perf_counter() - t, time.process_time() - c, ready.source


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--conical", action="store_true",
                    help="with flexride.scenario.presets.CONICAL_TREAD (the presets' own real "
                    "profiles otherwise)")
    args = ap.parse_args()

    from flexride.scenario.presets import CONICAL_TREAD, load_preset
    from flexride.solver.assemble import vehicle_for
    from flexride.solver.setup_cache import SetupCache
    from flexride.solver.simulate import simulate

    extra = dict(CONICAL_TREAD) if args.conical else {}
    base = {**extra, "duration_s": 20.0, "distance_m": None}
    geometry = load_preset("paper-metro", extra).contact.geometry
    print(f"flexride set-up benchmark (contact geometry {geometry}); {_load()}")
    simulate(load_preset("paper-metro", {**extra, "duration_s": 0.01}), setup_cache=None)
    flex = {"bodies.carbody.model": "flexible", "bodies.frames.model": "flexible"}
    t = time.perf_counter()
    flex_vehicle = vehicle_for(load_preset("paper-random-straight-80", {**base, **flex}))
    print(f"flexible vehicle (car body and frames to 100 Hz) from the FE cache: "
          f"{time.perf_counter() - t:.3f} s")
    worst = {"miss": 0.0, "hit": 0.0, "disk": 0.0}
    print(f"{'condition':<22} {'model':<9} {'miss wall/CPU (s)':>18} {'hit (s)':>9} "
          f"{'disk (s)':>9}")
    for model in ("rigid", "flexible"):
        vehicle = flex_vehicle if model == "flexible" else None
        over = {**base, **(flex if model == "flexible" else {})}
        for cond in CONDITIONS:
            for v in SPEEDS:
                scenario = load_preset(f"paper-{cond}-{v}", over)
                best: dict[str, tuple[float, float]] = {}
                for _ in range(args.repeat):
                    with tempfile.TemporaryDirectory() as d:
                        cache = SetupCache(directory=d)
                        for kind in ("miss", "hit", "disk"):
                            if kind == "disk":
                                cache.clear()
                            wall, cpu, source = _setup_time(scenario, vehicle, cache)
                            assert source == {"miss": "computed", "hit": "memory",
                                              "disk": "disk"}[kind], source
                            if kind not in best or wall < best[kind][0]:
                                best[kind] = (wall, cpu)
                for kind in worst:
                    worst[kind] = max(worst[kind], best[kind][0])
                print(f"{cond + ' ' + str(v) + ' km/h':<22} {model:<9} "
                      f"{best['miss'][0]:8.3f} / {best['miss'][1]:6.3f}  {best['hit'][0]:9.3f} "
                      f"{best['disk'][0]:9.3f}")
    for kind, value in worst.items():
        target = TARGET_S[kind]
        status = "met" if value <= target else "MISSED"
        print(f"worst {kind:<4}: {value:.3f} s (target ≤ {target} s: {status}, ratio "
              f"{value / target:.2f})")
    print(_load())


if __name__ == "__main__":
    main()

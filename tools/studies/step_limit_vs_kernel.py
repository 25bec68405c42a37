"""Study: the time-step check's predicted limit against the kernel's own, found by bisection on
the kernel (:func:`flexride.solver.probe.kernel_limit`), for rigid and flexible bodies, conical
and S1002/60E1 contact, straight and curved track (at the check's operating point: steady
rolling, steady curving at mid-arc) and several speeds.

Prints one row per case: the predicted limit of that operating point (s; its margin below the
crossing, ``stability.LIMIT_MARGIN``, depends on the kind of point), the kernel's bracket
[largest stable, smallest growing] to 0.5 %, the prediction over the bracket's middle, and the
set-up's time. The test ``tests/solver/test_step_limit.py`` checks the same cases at ±3 %.

Usage::

    python tools/studies/step_limit_vs_kernel.py [--speeds 20 50 80] [--bodies rigid flexible]
"""

from __future__ import annotations

import argparse
import time

CONTACTS = ("conical", "profiles")
LINES = ("straight", "curve")
FLEX = {"bodies.carbody.model": "flexible", "bodies.carbody.element_size_m": 0.5,
        "bodies.carbody.cutoff_hz": 30.0, "bodies.frames.model": "flexible",
        "bodies.frames.element_size_m": 0.5, "bodies.frames.cutoff_hz": 100.0}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speeds", type=float, nargs="+", default=[20.0, 50.0, 80.0])
    ap.add_argument("--bodies", nargs="+", default=["rigid", "flexible"])
    args = ap.parse_args()

    from flexride.scenario.presets import load_preset
    from flexride.solver.assemble import assemble, vehicle_for
    from flexride.solver.probe import kernel_limit, operating_start
    from flexride.solver.setup_cache import run_setup
    from flexride.solver.stability import OperatingPoint

    flexible = vehicle_for(load_preset("paper-metro", FLEX)) if "flexible" in args.bodies \
        else None
    print(f"{'case':<34} {'predicted (s)':>13} {'kernel: stable … grows (s)':>28} "
          f"{'ratio':>6} {'check (s)':>9}")
    for body in args.bodies:
        for contact in CONTACTS:
            for line in LINES:
                for speed in args.speeds:
                    over = {"excitation": [], "distance_m": 300.0, "speed_kmh": speed,
                            "contact.geometry": contact, **(FLEX if body == "flexible" else {})}
                    sc = load_preset(f"paper-random-{line}-80", over)
                    asm = assemble(sc, vehicle=flexible if body == "flexible" else None)
                    curving = line == "curve"
                    start, s, s_win0, _x, _v = operating_start(sc, asm, curving)
                    t = time.perf_counter()
                    info = run_setup(start, s, s_win0, True, None, steady=True,
                                     point=OperatingPoint(s, curving)).stability
                    took = time.perf_counter() - t
                    assert info is not None
                    dt = info["dt_max"]
                    lo, hi = kernel_limit(sc, asm, 0.9 * dt, 1.1 * dt, curving)
                    case = f"{body} {contact} {line} {speed:g} km/h"
                    print(f"{case:<34} {dt:13.4e} {lo:13.4e} … {hi:11.4e} "
                          f"{dt / (0.5 * (lo + hi)):6.3f} {took:9.2f}", flush=True)


if __name__ == "__main__":
    main()

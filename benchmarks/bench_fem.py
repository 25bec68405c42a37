"""Time and memory to build, solve and reduce the 0.2 m car-body model, and the cached load.

A command that prints figures, not a test. Each stage runs in this process; its wall time and
CPU time (``time.process_time``, all threads of the process: the figure the targets are judged
by, as other work on the machine inflates the wall time), and memory as the peak resident set
size (``resource.getrusage``) after the stage (``tracemalloc`` is off: it slows SciPy down).

Usage::

    .venv/bin/python benchmarks/bench_fem.py [--element-size 0.2] [--cutoff 100]
        [--methods modal,craig-bampton,guyan] [--cache-dir DIR]

The cache directory defaults to a fresh temporary one, so the first build of each method is
timed without the cache and the second load with it.
"""

from __future__ import annotations

import argparse
import os
import resource
import tempfile
import time

TARGET_BUILD_S = 60.0
TARGET_RSS_MB = 1024.0
TARGET_LOAD_S = 0.1


def _clock() -> tuple[float, float]:
    """Wall and CPU clocks (s)."""
    return time.perf_counter(), time.process_time()


def _since(t: float, c: float) -> tuple[float, float]:
    """Wall and CPU time (s) since :func:`_clock` gave ``t``, ``c``."""
    return time.perf_counter() - t, time.process_time() - c


def _rss_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--element-size", type=float, default=0.2)
    ap.add_argument("--cutoff", type=float, default=100.0)
    ap.add_argument("--methods", default="modal,craig-bampton,guyan")
    ap.add_argument("--cache-dir", default=None)
    args = ap.parse_args()
    os.environ["FLEXRIDE_CACHE_DIR"] = args.cache_dir or tempfile.mkdtemp(prefix="flexride-fem-")

    from flexride.fem.eigen import free_free_modes
    from flexride.fem.flexible import build_flexible_body
    from flexride.fem.rigid import rigid_body_vectors
    from flexride.fem.vehicle_models import build_fe_model
    from flexride.scenario.presets import load_preset

    vehicle = load_preset("paper-metro").vehicle
    rows: list[tuple[str, float, float, float, str]] = []

    t, c = _clock()
    model, _ = build_fe_model("carbody", vehicle, args.element_size)
    rows.append(
        (
            "mesh + mass matching",
            *_since(t, c),
            _rss_mb(),
            f"{model.mesh.n_nodes} nodes, {len(model.mesh.quads)} shells, "
            f"{len(model.mesh.beams)} beams, {model.n_dof} DOFs",
        )
    )
    t, c = _clock()
    K, M = model.assemble(force=True)
    rows.append(("assembly (pyfe3d)", *_since(t, c), _rss_mb(), f"nnz K {K.nnz}, M {M.nnz}"))
    t, c = _clock()
    modes = free_free_modes(K, M, rigid_body_vectors(model.nodes), n_elastic=6)
    f = ", ".join(f"{v:.2f}" for v in modes.frequencies[6:12])
    rows.append(("eigen: first 6 elastic modes", *_since(t, c), _rss_mb(), f + " Hz"))
    del model, K, M, modes

    for method in [m.strip() for m in args.methods.split(",") if m.strip()]:
        t, c = _clock()
        fb = build_flexible_body(
            "carbody", vehicle, method=method, cutoff_hz=args.cutoff, element_size=args.element_size
        )
        rows.append(
            (
                f"{method}: build + reduce + report",
                *_since(t, c),
                _rss_mb(),
                f"{fb.body.n_elastic} elastic modes <= {args.cutoff:g} Hz, "
                f"{fb.report.n_reduced_dof} reduced DOFs",
            )
        )
        t, c = _clock()
        fb2 = build_flexible_body(
            "carbody", vehicle, method=method, cutoff_hz=args.cutoff, element_size=args.element_size
        )
        assert fb2.from_cache
        rows.append((f"{method}: cached load", *_since(t, c), _rss_mb(), ""))

    print(
        f"car body, element size {args.element_size:g} m, cut-off {args.cutoff:g} Hz, "
        f"cache {os.environ['FLEXRIDE_CACHE_DIR']}"
    )
    print(f"{'stage':38s} {'wall (s)':>9} {'CPU (s)':>9} {'peak RSS (MB)':>14}  notes")
    for name, sec, cpu, mem, note in rows:
        print(f"{name:38s} {sec:9.3f} {cpu:9.3f} {mem:14.0f}  {note}")
    _targets(rows)


def _verdict(value: float, target: float, unit: str) -> str:
    ok = "met" if value <= target else "MISSED"
    return f"≤ {target:g} {unit}: {ok} (ratio {value / target:.2f})"


def _targets(rows: list[tuple[str, float, float, float, str]]) -> None:
    """Each method's build and cached load against the targets (≤ 60 s CPU and ≤ 1 GB peak
    RSS for the build, ≤ 0.1 s for the load), with the load average.
    """
    for name, sec, cpu, mem, _ in rows:
        method = name.split(":")[0]
        if name.endswith("build + reduce + report"):
            print(f"target {method} build {_verdict(cpu, TARGET_BUILD_S, 's CPU')}; peak RSS "
                  f"{_verdict(mem, TARGET_RSS_MB, 'MB')}")
        elif name.endswith("cached load"):
            print(f"target {method} cached load {_verdict(sec, TARGET_LOAD_S, 's')}")
    one, five, _ = os.getloadavg()
    print(f"load average {one:.2f} (1 min), {five:.2f} (5 min)")


if __name__ == "__main__":
    main()

"""Cost of the mesh-convergence study (the paper's Fig. 4 pre-calculation) on this machine.

A command that prints figures, not a test. It runs the study preset ``mesh-convergence``
(smooth and random straight track at 80 km/h, the car body at 0.5 … 0.1 m) in this process, as
``flexride fe convergence carbody --response`` does, and prints per job the set-up time (FE
build or load, reduction, assembly, stability check), the solve time and the process's peak
memory so far, then the totals: the study's wall and CPU time and its peak memory. With
``--cold`` the FE bodies are built anew in a temporary cache directory (what a first study
costs); without it the usual cache is used (what a repeated study costs).

Usage::

    .venv/bin/python benchmarks/bench_mesh_study.py [--cold] [--sizes 0.5,0.4,0.3,0.2,0.15,0.1]
        [--conditions smooth-straight,random-straight]
"""

from __future__ import annotations

import argparse
import os
import resource
import tempfile
import time


def _peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cold", action="store_true", help="build the FE bodies anew")
    parser.add_argument("--sizes", default="0.5,0.4,0.3,0.2,0.15,0.1")
    parser.add_argument("--conditions", default="smooth-straight,random-straight")
    args = parser.parse_args()
    tmp = tempfile.TemporaryDirectory(prefix="flexride-bench-mesh-") if args.cold else None
    if tmp is not None:
        os.environ["FLEXRIDE_CACHE_DIR"] = tmp.name  # read when the FE cache is first used

    from flexride.study.aggregate import study_tables
    from flexride.study.expand import expand_study
    from flexride.study.local_run import run_plan
    from flexride.study.mesh_convergence import study_request

    sizes = [float(v) for v in args.sizes.split(",")]
    conditions = [c for c in args.conditions.split(",") if c]
    plan = expand_study(study_request("carbody", sizes, conditions), max_jobs=200)
    print(f"mesh-convergence study: {len(plan.jobs)} jobs ({len(conditions)} conditions x "
          f"{len(sizes)} sizes), {os.cpu_count()} cores, FE cache "
          f"{'cold (temporary)' if args.cold else 'as it is'}")
    print(f"{'job':<52} {'setup s':>8} {'solve s':>8} {'peak MB':>8}")
    peaks: dict[int, float] = {}

    def progress(index: int, n: int, fraction: float, message: str) -> None:
        if fraction >= 1.0:
            peaks[index] = _peak_mb()

    t0, c0 = time.perf_counter(), time.process_time()
    jobs = run_plan(plan, progress)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    for planned, job in zip(plan.jobs, jobs, strict=True):
        meta = job["run_meta"]
        print(f"{planned.name:<52} {meta['wall_time_setup_s']:8.1f} "
              f"{meta['wall_time_solve_s']:8.1f} {peaks.get(planned.index, 0.0):8.0f}")
    setup = sum(j["run_meta"]["wall_time_setup_s"] for j in jobs)
    solve = sum(j["run_meta"]["wall_time_solve_s"] for j in jobs)
    print(f"total: wall {wall:.1f} s, CPU {cpu:.1f} s (this process; FE eigen solutions use "
          f"threads), set-up {setup:.1f} s, solve {solve:.1f} s, peak memory "
          f"{_peak_mb():.0f} MB, load average {os.getloadavg()[0]:.2f}")
    tables = study_tables(jobs)["mesh_convergence"]
    for t in tables:
        print(f"{t['group'].get('condition')}: {t['claim']['text']}")
    if tmp is not None:
        tmp.cleanup()


if __name__ == "__main__":
    main()

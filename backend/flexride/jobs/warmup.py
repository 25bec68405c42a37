"""Compile (or load from the on-disk cache) the solver's numba kernels before a worker takes
jobs, so the first job does not pay for it and forked children inherit compiled code.
"""

from __future__ import annotations

import logging
import os
import time

log = logging.getLogger(__name__)

_THREAD_VARS = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                "NUMBA_NUM_THREADS")


def single_threaded_env() -> None:
    """Ask BLAS and numba for one thread per process (worker processes run one job each, so
    threads would only oversubscribe the cores); variables already set are kept. Takes effect
    in processes that import NumPy afterwards.
    """
    for var in _THREAD_VARS:
        os.environ.setdefault(var, "1")


def limit_blas_threads(n: int = 1) -> list[str]:
    """Set the thread count of the BLAS libraries already loaded in this process (NumPy's
    and SciPy's wheels bundle their own OpenBLAS), for processes that imported NumPy before
    :func:`single_threaded_env` could act (threadpoolctl). Returns the libraries changed.

    On a shared or loaded machine one thread per process is much faster: the solver's setup
    (eigen-decompositions, solves of a few hundred unknowns) slowed down up to 6x with
    competing BLAS threads in our measurements.
    """
    from threadpoolctl import threadpool_info, threadpool_limits

    threadpool_limits(limits=n, user_api="blas")
    return sorted(str(lib["filepath"]) for lib in threadpool_info()
                  if lib.get("user_api") == "blas")


def warm_numba() -> float:
    """Run a tiny simulation (a few steps) to compile or load every kernel; return seconds.

    Failures are logged, not raised: a worker still starts and the first job compiles.
    """
    t0 = time.perf_counter()
    try:
        from flexride.scenario.presets import load_preset
        from flexride.solver import simulate

        scenario = load_preset("paper-random-straight-80",
                               {"duration_s": 0.02, "distance_m": None})
        simulate(scenario)
    except Exception as exc:  # pragma: no cover - depends on the installation
        log.warning("numba warm-up failed (%s); the first job will compile", exc)
    dt = time.perf_counter() - t0
    log.info("numba kernels ready in %.1f s", dt)
    return dt

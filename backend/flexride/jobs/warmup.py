"""Compile (or load from the on-disk cache) the solver's numba kernels before a worker takes
jobs, so the first job does not pay for it and forked children inherit compiled code; and say
whether they are compiled (``GET /health``: ``solver.state``).

* One process compiles, the others wait and load: :func:`warm_numba` holds a file lock in the
  numba cache directory while it compiles and records the state in ``flexride-solver.json``
  there (``compiling`` with its start, then ``ready`` with the compile time, for a *stamp* of
  the kernels' sources: :func:`solver_stamp`).
* The API never compiles in a request. :data:`SOLVER` loads the two kernels the submission
  check needs from the on-disk cache (never compiling them) in a background thread started
  with the runner; until they are loaded, a submission is queued without the in-request
  stability check (the worker checks the time step before it runs). Without a local worker
  pool (Celery, or no runner) it compiles them first in a child process.

Run as ``python -m flexride.jobs.warmup`` to compile (or load) the kernels once.
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import logging
import os
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

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


def _warm_run() -> None:
    """A few steps of the paper's case: compiles (or loads) every kernel of a run; and their
    analysis, which imports what the first job's would (a second or more on a busy machine).
    """
    from flexride.errors import FlexrideError
    from flexride.scenario.presets import load_preset
    from flexride.solver import simulate

    scenario = load_preset("paper-random-straight-80", {"duration_s": 0.02, "distance_m": None})
    results = simulate(scenario, setup_cache=None)
    try:
        from flexride.analysis import analyze

        analyze(results)
    except FlexrideError:  # too short for some indices: the imports are done
        pass


DEFAULT_COMPILE_S = 60.0
"""Expected cold compile time (s) before one was measured on this machine (2 cores)."""

STATE_FILE = "flexride-solver.json"
LOCK_FILE = "flexride-solver.lock"


def numba_cache_dir() -> Path:
    """The numba cache directory in use (:mod:`flexride._numba_env` sets it at import)."""
    import flexride  # noqa: F401  (configures NUMBA_CACHE_DIR)

    return Path(os.environ.get("NUMBA_CACHE_DIR") or ".")


_STAMP: str | None = None


def solver_stamp() -> str:
    """What the compiled kernels depend on: the numba cache directory (keyed by the flexride
    and numba versions) and the size and modification time of every source file of the
    solver and contact packages (what numba's cache checks). Computed once per process.
    """
    global _STAMP
    if _STAMP is None:
        import hashlib

        pkg = Path(__file__).resolve().parent.parent
        parts = [str(numba_cache_dir())]
        for sub in ("solver", "contact"):
            for path in sorted((pkg / sub).rglob("*.py")):
                st = path.stat()
                parts.append(f"{path.relative_to(pkg).as_posix()}:{st.st_size}:{st.st_mtime_ns}")
        parts.append(str((pkg / "_numba_env.py").stat().st_mtime_ns))
        _STAMP = hashlib.sha256("\n".join(parts).encode()).hexdigest()[:32]
    return _STAMP


def read_state() -> dict[str, Any]:
    """The recorded compile state of the current kernels (``{}`` when unknown)."""
    try:
        data = json.loads((numba_cache_dir() / STATE_FILE).read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


def _write_state(**values: Any) -> None:
    from flexride.fileio import write_bytes_atomic

    try:
        write_bytes_atomic(numba_cache_dir() / STATE_FILE, json.dumps(values).encode())
    except OSError as exc:  # a read-only cache: the state is only not reported
        log.warning("cannot record the solver's compile state: %s", exc)


@contextlib.contextmanager
def _compile_lock() -> Iterator[None]:
    """An exclusive lock on the numba cache directory (one compiling process at a time)."""
    directory = numba_cache_dir()
    try:
        directory.mkdir(parents=True, exist_ok=True)
        fh = open(directory / LOCK_FILE, "a")
    except OSError:  # no writable cache: nothing to share, compile unlocked
        yield
        return
    try:
        fcntl.flock(fh, fcntl.LOCK_EX)
        yield
    finally:
        fh.close()


def warm_numba() -> float:
    """Compile the kernels (one process at a time, recording the state) or load them from the
    on-disk cache by running a tiny simulation; return seconds.

    Failures are logged, not raised: a worker still starts and the first job compiles.
    """
    t0 = time.perf_counter()
    try:
        if cache_ready():
            _warm_run()  # load: no lock needed
        else:
            with _compile_lock():
                _compile_once()
    except Exception as exc:  # pragma: no cover - depends on the installation
        log.warning("numba warm-up failed (%s); the first job will compile", exc)
    dt = time.perf_counter() - t0
    log.info("numba kernels ready in %.1f s", dt)
    return dt


def cache_ready() -> bool:
    """Whether the on-disk cache holds the current kernels (recorded by a warm-up)."""
    state = read_state()
    return state.get("stamp") == solver_stamp() and state.get("state") == "ready"


def _compile_once() -> None:
    """Under the compile lock: compile unless another process did meanwhile, recording the
    state (start and expected duration, then the compile time).
    """
    if cache_ready():
        _warm_run()
        return
    previous = read_state().get("compile_s")
    _write_state(stamp=solver_stamp(), state="compiling", started_at=time.time(),
                 expected_s=float(previous or DEFAULT_COMPILE_S), compile_s=previous)
    t1 = time.perf_counter()
    _warm_run()
    _write_state(stamp=solver_stamp(), state="ready", finished_at=time.time(),
                 compile_s=round(time.perf_counter() - t1, 2))


def _check_kernels() -> list[tuple[Any, tuple[Any, ...]]]:
    """The kernels the submission check calls, with example arguments of their one
    signature (every scenario gives the same types, :mod:`flexride.solver.system`).
    """
    import numpy as np

    from flexride.scenario.presets import load_preset
    from flexride.solver.assemble import assemble
    from flexride.solver.forces import evaluate
    from flexride.solver.linearise import (
        state_jacobian_columns,
        step_jacobian_columns,
        workspace,
    )

    sysarr = assemble(load_preset("paper-metro", {"duration_s": 0.01})).sys
    n = sysarr.minv.shape[0]
    F, A, aux, sn, cst = workspace(sysarr)
    X, V = np.zeros(n), np.zeros(n)
    cols = np.zeros(1, dtype=np.int64)
    out, out_aux = np.zeros((n, 1)), np.zeros((aux.size, 1))
    step_out = np.zeros((n + cst.size, 2 * n + cst.size))
    return [(evaluate, (sysarr, X, V, 0.0, 0.0, F, A, aux, sn, cst, 0.0)),
            (state_jacobian_columns, (sysarr, X, V, 0.0, 0.0, False, np.ones(1), cols, out,
                                      out_aux)),
            (step_jacobian_columns, (sysarr, X, V, cst, 0.0, 0.0, 0.0, 0.0, 0.0, step_out))]


def load_cached_kernels() -> bool:
    """Load the submission check's kernels from numba's on-disk cache into this process,
    never compiling them; whether they are loaded (False: not in the cache).
    """
    import numba
    from numba.core.compiler_lock import global_compiler_lock

    try:
        if not _indexed():
            return False
        with global_compiler_lock:
            return _load_overloads(_check_kernels(), numba.typeof)
    except Exception as exc:  # numba internals changed: report not loaded (never compile)
        log.warning("cannot load the solver's kernels from the cache: %s", exc)
        return False


def _indexed() -> bool:
    """Whether numba's cache has index files for the check's kernels (a quick look before
    assembling example arguments; whether an entry fits is for the load to tell).
    """
    from flexride.solver.forces import evaluate
    from flexride.solver.linearise import state_jacobian_columns, step_jacobian_columns

    kernels: tuple[Any, ...] = (evaluate, state_jacobian_columns, step_jacobian_columns)
    return all(Path(d._cache._cache_file._index_path).is_file() for d in kernels)


def _load_overloads(kernels: list[tuple[Any, tuple[Any, ...]]], typeof: Any) -> bool:
    """Add each dispatcher's overload for its example arguments from the on-disk cache (what
    numba's dispatcher does before it would compile); False at the first one missing.
    """
    for disp, args in kernels:
        if disp.signatures:
            continue
        sig = tuple(typeof(a) for a in args)
        cres = disp._cache.load_overload(sig, disp.targetctx)
        if cres is None:
            return False
        disp.targetctx.insert_user_function(cres.entry_point, cres.fndesc, [cres.library])
        disp.add_overload(cres)
    return True


class SolverState:
    """Whether this (API) process can run the submission check without compiling, and what
    ``GET /health`` says about the solver.
    """

    def __init__(self) -> None:
        self._loaded = threading.Event()
        self._first_try = threading.Event()  # the first load from the cache has finished
        self._started = False
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._child: subprocess.Popen[bytes] | None = None
        self._stopping = threading.Event()

    def start(self, compile_here: bool) -> None:
        """Load the kernels in a background thread (unless loaded or loading); with
        ``compile_here`` a child process compiles them first if the cache lacks them, else
        the thread waits for the workers to compile them.
        """
        with self._lock:
            if self._loaded.is_set() or (self._thread is not None and self._thread.is_alive()):
                self._started = True
                return
            self._started = True
            self._stopping.clear()
            self._thread = threading.Thread(target=self._run, args=(compile_here,),
                                            name="flexride-solver-load", daemon=True)
            self._thread.start()

    def _run(self, compile_here: bool) -> None:
        compiled = False
        while not self._stopping.is_set() and not self._try_load():
            if compile_here and not compiled:
                compiled = True
                self._compile_in_child()
                continue
            self._stopping.wait(1.0)

    def _compile_in_child(self) -> None:
        """Compile the kernels in a child process (this one keeps serving requests)."""
        with self._lock:
            if self._stopping.is_set():
                return
            self._child = subprocess.Popen([sys.executable, "-m", "flexride.jobs.warmup"],
                                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self._child.wait()

    def stop(self) -> None:
        """Stop waiting for the kernels and end a compiling child process."""
        self._stopping.set()
        with self._lock:
            child = self._child
        if child is not None and child.poll() is None:
            child.terminate()
            try:
                child.wait(5.0)
            except subprocess.TimeoutExpired:
                child.kill()

    def _try_load(self) -> bool:
        try:
            ok = load_cached_kernels()
        finally:
            self._first_try.set()
        if ok:
            self._loaded.set()
        return ok

    def usable(self, wait_s: float = 10.0) -> bool:
        """Whether the submission check can run now without compiling: the kernels are loaded,
        or the background thread's first attempt to load them from the cache (a second or so)
        succeeds within ``wait_s``. False while they are being compiled. A process that never
        started the thread (the command line, library use) compiles as needed: True.
        """
        if self._loaded.is_set() or not self._started:
            return True
        self._first_try.wait(wait_s)
        return self._loaded.is_set()

    def status(self) -> dict[str, Any]:
        """``{"state": "ready" | "compiling", "estimate_s": seconds left or None}``."""
        if self._loaded.is_set() or cache_ready():
            return {"state": "ready", "estimate_s": None}
        state = read_state()
        expected = float(state.get("expected_s") or state.get("compile_s") or DEFAULT_COMPILE_S)
        started = state.get("started_at") if state.get("stamp") == solver_stamp() else None
        left = expected if started is None else max(1.0, expected - (time.time() - started))
        return {"state": "compiling", "estimate_s": round(left, 1)}


SOLVER = SolverState()
"""This process's solver state (the API's)."""


if __name__ == "__main__":  # pragma: no cover - run by SolverState in a child process
    logging.basicConfig(level="INFO")
    limit_blas_threads(1)
    warm_numba()

"""The set-up of a run — static equilibrium and time-step stability limit — cached by the
content it depends on, so that the runs of a study compute it once.

Key (:func:`setup_key`): a SHA-256 of exactly what :func:`~flexride.solver.static.
static_equilibrium` and :func:`~flexride.solver.stability.stability_limit` read:

* every field of :class:`~flexride.solver.system.SystemArrays` (taken from the NamedTuple, so
  a new field is in the key without anyone listing it), except those no set-up computation
  reads — :data:`NOT_READ`: recording layout, the time step (the limit does not depend on it;
  each run compares its own step, :func:`~flexride.solver.stability.check_step`) and scratch —
  and except the route tables, which enter through the values :func:`evaluate` can look up
  with the vehicle at ``s`` (:func:`~flexride.solver.forces.route_inputs`): the
  irregularities under the wheels and the line geometry at the bodies, not the whole route;
* the other inputs of the two computations on the :class:`~flexride.solver.assemble.Assembly`
  (:func:`_assembly_inputs`): static coordinates, names of the coordinates, total mass, step of
  the contact table;
* the position ``s`` and the rail-window start, the flexride version and a digest of the
  source of the solver and contact modules, the numba settings and the NumPy and numba
  versions (an edited kernel or another LAPACK never reuses old set-ups).

Tests (``tests/solver/test_setup_cache.py``) check that changing any of these changes the key,
and that changing what :data:`NOT_READ` leaves out changes neither the key nor the set-up.

Entries live in memory (least recently used out beyond :data:`MEMORY_ENTRIES`) and as files
``<cache dir>/setup-<version>/<key>.npz`` (written atomically, read without pickle, oldest out
beyond :data:`DISK_ENTRIES`), shared by the worker processes of a machine. Nothing of a request
reaches a path: file names are the hex digest.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import threading
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from flexride.fileio import atomic_path, cache_root
from flexride.solver.assemble import Assembly
from flexride.solver.stability import OperatingPoint

log = logging.getLogger(__name__)

SETUP_FORMAT = 1
"""Version of the key and the file layout; bump to drop every stored set-up."""

MEMORY_ENTRIES = 64
"""Set-ups a process keeps in memory (a few kB each)."""

DISK_ENTRIES = 2048
"""Set-up files kept in the cache directory (a few kB each); the oldest go first."""

NOT_READ: dict[str, frozenset[str]] = {
    "fields": frozenset({"body_line", "el_force", "pt_body", "pt_phi", "ch", "irr", "line"}),
    "par": frozenset({"dt", "n_dec", "n_points", "n_ch", "irr_s0", "irr_ds", "ln_s0", "ln_ds",
                      "chatter_force"}),
}
"""SystemArrays fields and scalars left out of the key: written before read (``body_line``,
``el_force``), recording layout, the step, the run-time watch's threshold, and the route
tables and their grids (in the key through ``route_inputs``)."""

ENV = "FLEXRIDE_SETUP_CACHE"
"""``off``: compute every set-up; ``memory``: no files; anything else (default): both."""


@dataclass(frozen=True)
class Setup:
    """A run's set-up.

    Attributes
    ----------
    X0 : numpy.ndarray
        Static equilibrium coordinates (m, rad).
    stability : dict or None
        :func:`~flexride.solver.stability.stability_limit` (``dt_max`` s, ...), None when not
        asked for.
    source : str
        ``computed``, ``memory`` or ``disk``.
    """

    X0: np.ndarray
    stability: dict[str, Any] | None
    source: str


def _source_digest() -> str:
    """SHA-256 of the code that computes a set-up: the solver's and the contact model's
    source files, the numba settings, and the NumPy and numba versions (cached per process).
    """
    global _SOURCE_DIGEST
    if _SOURCE_DIGEST is None:
        import numba

        pkg = Path(__file__).resolve().parent.parent
        h = hashlib.sha256(f"numpy {np.__version__} numba {numba.__version__}".encode())
        paths = [p for sub in ("solver", "contact") for p in sorted((pkg / sub).rglob("*.py"))]
        for path in [*paths, pkg / "_numba_env.py"]:
            h.update(path.relative_to(pkg).as_posix().encode())
            h.update(path.read_bytes())
        _SOURCE_DIGEST = h.hexdigest()
    return _SOURCE_DIGEST


_SOURCE_DIGEST: str | None = None


def _assembly_inputs(asm: Assembly) -> dict[str, Any]:
    """What the set-up reads from an Assembly besides ``asm.sys``."""
    return {"static_dofs": np.asarray(asm.static_dofs, dtype=np.int64).tolist(),
            "dof_names": list(asm.dof_names),
            "total_mass": repr(float(asm.vehicle.total_mass)),
            "contact_dy": repr(float(asm.contact.dy))}


def _hash_array(h: Any, name: str, a: np.ndarray) -> None:
    a = np.ascontiguousarray(a)
    h.update(f"{name}:{a.dtype.str}:{a.shape}".encode())
    h.update(a.tobytes())


def setup_key(asm: Assembly, s: float, s_win0: float, steady: bool = False,
              margin: float = 0.0) -> str:
    """Content key of the set-up of ``asm`` at position ``s`` (m) with the rail window
    starting at ``s_win0`` (m), in static equilibrium or (``steady``) the steady state, with
    the stability limit ``margin`` below its crossing; see the module docs.
    """
    from flexride import __version__
    from flexride.solver.forces import route_inputs

    sysarr = asm.sys
    h = hashlib.sha256()
    h.update(json.dumps({"format": SETUP_FORMAT, "flexride": __version__,
                         "source": _source_digest(), "s": repr(float(s)),
                         "s_win0": repr(float(s_win0)), "asm": _assembly_inputs(asm),
                         "steady": steady, "margin": repr(float(margin))},
                        sort_keys=True).encode())
    par = {k: repr(v) for k, v in sysarr.par._asdict().items() if k not in NOT_READ["par"]}
    h.update(json.dumps(par, sort_keys=True).encode())
    for name in sysarr._fields:
        if name != "par" and name not in NOT_READ["fields"]:
            _hash_array(h, name, getattr(sysarr, name))
    _hash_array(h, "route", route_inputs(sysarr, s))
    return h.hexdigest()


class SetupCache:
    """Set-ups by :func:`setup_key`, in memory and (unless ``disk`` is False) in files under
    ``<cache dir>/setup-<version>`` (thread-safe; processes share the files).

    Parameters
    ----------
    disk : bool
        Keep set-ups as files too.
    directory : path-like, optional
        Where; default ``cache_root() / "setup-<version>"``, read at each use (a worker sets
        ``FLEXRIDE_CACHE_DIR`` after import).
    """

    def __init__(self, disk: bool = True, directory: str | os.PathLike[str] | None = None):
        self.disk = disk
        self._directory = None if directory is None else Path(directory)
        self._items: OrderedDict[str, tuple[np.ndarray, dict[str, Any] | None]] = OrderedDict()
        self._lock = threading.Lock()

    def directory(self) -> Path:
        """The directory of the set-up files."""
        from flexride import __version__

        return self._directory or cache_root() / f"setup-{__version__}"

    def clear(self) -> None:
        """Forget the set-ups held in memory (files stay)."""
        with self._lock:
            self._items.clear()

    def get(self, key: str, need_stability: bool) -> Setup | None:
        """The set-up of ``key`` if known (with its stability limit when ``need_stability``)."""
        with self._lock:
            hit = self._items.get(key)
            if hit is not None:
                self._items.move_to_end(key)
        source = "memory"
        if hit is None and self.disk:
            hit, source = self._read(key), "disk"
            if hit is not None:
                self._remember(key, hit)
        if hit is None or (need_stability and hit[1] is None):
            return None
        return Setup(hit[0].copy(), _copy(hit[1]), source)

    def put(self, key: str, X0: np.ndarray, stability: dict[str, Any] | None) -> None:
        """Keep a computed set-up (in memory and, if enabled, as a file)."""
        entry = (np.array(X0, dtype=np.float64, copy=True), _copy(stability))
        self._remember(key, entry)
        if self.disk:
            self._write(key, entry)

    def _remember(self, key: str, entry: tuple[np.ndarray, dict[str, Any] | None]) -> None:
        with self._lock:
            self._items[key] = entry
            self._items.move_to_end(key)
            while len(self._items) > MEMORY_ENTRIES:
                self._items.popitem(last=False)

    def _path(self, key: str) -> Path:
        if len(key) != 64 or any(c not in "0123456789abcdef" for c in key):
            raise ValueError("a set-up key is a SHA-256 hex digest")
        return self.directory() / f"{key}.npz"

    def _read(self, key: str) -> tuple[np.ndarray, dict[str, Any] | None] | None:
        path = self._path(key)
        try:
            with np.load(path, allow_pickle=False) as f:
                X0 = np.array(f["X0"], dtype=np.float64)
                stab = json.loads(str(f["stability"]))
        except FileNotFoundError:
            return None
        except Exception as exc:  # a damaged or foreign file: recompute (and overwrite it)
            log.warning("set-up cache: ignoring %s (%s)", path.name, exc)
            return None
        return X0, stab

    def _write(self, key: str, entry: tuple[np.ndarray, dict[str, Any] | None]) -> None:
        path = self._path(key)
        try:
            with atomic_path(path) as tmp, open(tmp, "wb") as fh:
                np.savez(fh, X0=entry[0], stability=np.array(json.dumps(entry[1])))
            self._prune(path.parent)
        except OSError as exc:  # a read-only or full cache: the run goes on uncached
            log.warning("set-up cache: cannot write %s (%s)", path.name, exc)

    @staticmethod
    def _prune(directory: Path) -> None:
        files = list(directory.glob("*.npz"))
        if len(files) <= DISK_ENTRIES:
            return
        def mtime(p: Path) -> float:
            try:
                return p.stat().st_mtime
            except OSError:
                return 0.0
        for p in sorted(files, key=mtime)[: len(files) - DISK_ENTRIES]:
            p.unlink(missing_ok=True)


def _copy(stab: dict[str, Any] | None) -> dict[str, Any] | None:
    return None if stab is None else dict(stab)


def default_cache() -> SetupCache | None:
    """The process-wide cache as configured by ``$FLEXRIDE_SETUP_CACHE`` (None: ``off``)."""
    mode = os.environ.get(ENV, "").strip().lower()
    if mode == "off":
        return None
    _DEFAULT.disk = mode != "memory"
    return _DEFAULT


_DEFAULT = SetupCache()


def run_setup(asm: Assembly, s: float, s_win0: float, stability: bool,
              cache: SetupCache | None, steady: bool = False,
              point: OperatingPoint | None = None) -> Setup:
    """Static equilibrium — or with ``steady`` the steady state — and (if
    ``stability``) the stability limit of ``asm`` at ``s`` (m), from ``cache`` when known, else
    computed (and kept there).

    Parameters
    ----------
    asm : Assembly
        The assembled system.
    s, s_win0 : float
        Vehicle-centre position and rail-window start (m).
    stability : bool
        Also estimate the stability limit.
    cache : SetupCache or None
        Where set-ups are kept; None computes without keeping.
    steady : bool
        The steady state (:func:`~flexride.solver.steady.steady_state`: rolling, or curving on
        a curve, at the spin rates that balance the longitudinal creep forces; ``asm`` on
        smooth track, :func:`~flexride.solver.steady.smooth_assembly`) instead of the static
        equilibrium.
    point : OperatingPoint, optional
        The operating point the limit is for (its name and margin, in the key); default a
        static equilibrium or steady rolling.

    Returns
    -------
    Setup
    """
    from flexride.solver.stability import stability_limit

    point = point or OperatingPoint(s, False)
    key = setup_key(asm, s, s_win0, steady, point.margin) if cache is not None else ""
    known = None
    if cache is not None:
        hit = cache.get(key, stability)
        if hit is not None:
            return hit
        known = None if steady else cache.get(key, False)
    X0, V0 = ((known.X0, np.zeros_like(known.X0)) if known is not None
              else _state(asm, s, s_win0, steady))
    stab = None
    if stability:
        label = point.label if steady else "static equilibrium"
        stab = stability_limit(asm, X0, s, s_win0, V0, label, point.margin)
    if cache is not None:
        cache.put(key, X0, stab)
    return Setup(X0, stab, "computed")


def _state(asm: Assembly, s: float, s_win0: float, steady: bool
           ) -> tuple[np.ndarray, np.ndarray]:
    """Coordinates (m, rad) and velocities (m/s, rad/s) of the set-up's state."""
    from flexride.solver.static import static_equilibrium
    from flexride.solver.steady import steady_state

    X0 = static_equilibrium(asm, s, s_win0)
    return steady_state(asm, s, s_win0, X0) if steady else (X0, np.zeros_like(X0))

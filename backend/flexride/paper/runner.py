"""Run the study's runs in a process pool, each record cached on disk under the report
directory (``DIR/runs/<key>.json``, written atomically), so that a re-run with the same inputs
reuses them and an interrupted report resumes where it stopped.
"""

from __future__ import annotations

import json
import multiprocessing
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from flexride.fileio import write_bytes_atomic
from flexride.paper.plan import RECORD_VERSION, RunSpec
from flexride.paper.record import execute

__all__ = ["RunCache", "RunOutcome", "prepare_bodies", "run_study"]

Progress = Callable[[str, int, int], None]
"""Called as ``progress(message, done, total)`` after every finished run."""


class RunCache:
    """Run records stored as ``<directory>/<key>.json``.

    Parameters
    ----------
    directory : pathlib.Path
        Where the records live (created on the first store).
    """

    def __init__(self, directory: Path) -> None:
        self.directory = directory

    def path(self, key: str) -> Path:
        """File of the record with cache key ``key``."""
        return self.directory / f"{key}.json"

    def load(self, spec: RunSpec) -> dict[str, Any] | None:
        """The stored record of ``spec``, or None when absent, unreadable or stale."""
        key = spec.key()
        try:
            rec = json.loads(self.path(key).read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        if not isinstance(rec, dict) or rec.get("version") != RECORD_VERSION or (
                rec.get("key") != key):
            return None
        return rec

    def store(self, record: dict[str, Any]) -> None:
        """Write ``record`` atomically under its key."""
        text = json.dumps(record, separators=(",", ":"), allow_nan=False)
        write_bytes_atomic(self.path(record["key"]), text.encode("utf-8"))


@dataclass
class RunOutcome:
    """What :func:`run_study` did.

    Attributes
    ----------
    records : list of dict
        One record per successful run, in plan order.
    failures : list of dict
        ``{"spec", "error"}`` of each run that raised.
    reused : int
        Runs taken from the cache.
    computed : int
        Runs simulated now.
    runs_wall_time_s : float or None
        Wall time of the runs when they ran elsewhere before the report (the service's jobs:
        first start to last finish, s); None when they ran in :func:`run_study`.
    """

    records: list[dict[str, Any]] = field(default_factory=list)
    failures: list[dict[str, Any]] = field(default_factory=list)
    reused: int = 0
    computed: int = 0
    runs_wall_time_s: float | None = None


def prepare_bodies(specs: Sequence[RunSpec], progress: Progress | None = None) -> None:
    """Build (or load from the FE cache) the flexible bodies of ``specs`` once, in this
    process, before the pool starts: workers then only load them and never build the same body
    side by side.
    """
    from flexride.solver.assemble import vehicle_for

    seen: set[tuple[float | None, float | None]] = set()
    for spec in specs:
        body = (spec.cutoff_hz, spec.element_size_m)
        if spec.body != "flexible" or body in seen:
            continue
        seen.add(body)
        if progress is not None:
            mesh = "" if spec.element_size_m is None else f", {spec.element_size_m:g} m mesh"
            progress(f"flexible car body and frames, modes to {spec.cutoff_hz:g} Hz{mesh} "
                     "(built once, then cached)", 0, 0)
        vehicle_for(spec.scenario())


def _finish(outcome: RunOutcome, cache: RunCache, spec: RunSpec,
            result: dict[str, Any] | BaseException) -> str:
    if isinstance(result, BaseException):
        outcome.failures.append({"spec": spec.to_dict(), "label": spec.label,
                                 "error": f"{type(result).__name__}: {result}"})
        return f"{spec.label}: failed ({result})"
    cache.store(result)
    outcome.computed += 1
    return f"{spec.label}: {result['run']['wall_time_s']:.1f} s"


def _run_inline(todo: list[RunSpec], outcome: RunOutcome, cache: RunCache,
                done: list[dict[str, Any] | None], index: dict[int, int],
                report: Callable[[str], None]) -> None:
    for spec in todo:
        try:
            result: dict[str, Any] | BaseException = execute(spec)
        except Exception as exc:  # one failed run must not cost the whole report
            result = exc
        report(_finish(outcome, cache, spec, result))
        if not isinstance(result, BaseException):
            done[index[id(spec)]] = result


def _run_pool(todo: list[RunSpec], jobs: int, outcome: RunOutcome, cache: RunCache,
              done: list[dict[str, Any] | None], index: dict[int, int],
              report: Callable[[str], None]) -> None:
    ctx = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=min(jobs, len(todo)), mp_context=ctx) as pool:
        futures: dict[Future[dict[str, Any]], RunSpec] = {
            pool.submit(execute, spec): spec for spec in todo}
        for fut in as_completed(futures):
            spec = futures[fut]
            exc = fut.exception()
            result: dict[str, Any] | BaseException = exc if exc is not None else fut.result()
            report(_finish(outcome, cache, spec, result))
            if not isinstance(result, BaseException):
                done[index[id(spec)]] = result


def run_study(specs: Sequence[RunSpec], cache: RunCache, jobs: int,
              progress: Progress | None = None) -> RunOutcome:
    """Every run of ``specs``: from the cache where stored, else simulated (in ``jobs`` worker
    processes, or in this process for ``jobs`` = 1) and stored as soon as it finishes.

    A run that raises (e.g. a diverging simulation, a worker killed for memory) is listed in
    ``failures`` with its error; the report then judges the claims that need it "not
    comparable".
    """
    outcome = RunOutcome()
    done: list[dict[str, Any] | None] = [None] * len(specs)
    todo: list[RunSpec] = []
    index: dict[int, int] = {}
    for i, spec in enumerate(specs):
        rec = cache.load(spec)
        if rec is not None:
            done[i] = rec
            outcome.reused += 1
        else:
            index[id(spec)] = i
            todo.append(spec)
    total = len(specs)
    count = [outcome.reused]

    def report(message: str) -> None:
        count[0] += 1
        if progress is not None:
            progress(message, count[0], total)

    if progress is not None:
        progress(f"{outcome.reused} of {total} runs from the cache", outcome.reused, total)
    if todo:
        prepare_bodies(todo, progress)
        if jobs <= 1 or len(todo) == 1:
            _run_inline(todo, outcome, cache, done, index, report)
        else:
            _run_pool(todo, jobs, outcome, cache, done, index, report)
    outcome.records = [r for r in done if r is not None]
    return outcome

"""From a request to a validated scenario: presets and overrides, the content hash used to
reuse results, and the submission check (assembly, statics, time-step stability).

The submission check is cached by a *stability key*: the scenario without the fields that do
not change the linearised one-step map or the step chosen for it (name, description,
excitation) and with rigid bodies. Speed enters the map (the creep damping ∝ 1/V), the length
whether the run reaches a curve, the outputs the interval an automatic step divides
(:mod:`flexride.solver.stability`); the elastic modes of flexible bodies (≤ 100 Hz by default)
lie far below the rail and contact modes that set the limit. The worker checks the full
scenario again before it runs (``solver.check_stability``), so a miss still ends as a failed
job with the step to use.
"""

from __future__ import annotations

import hashlib
import importlib.util
import json
import threading
from collections import OrderedDict
from typing import Any

from flexride.errors import FlexrideError, ScenarioError, StabilityError
from flexride.scenario.scenario import Scenario
from flexride.track.measured import LIBRARY, MeasuredSources


def canonical_json(data: Any) -> str:
    """Deterministic JSON text (sorted keys, no spaces)."""
    return json.dumps(data, sort_keys=True, separators=(",", ":"), allow_nan=False)


def scenario_hash(scenario: Scenario) -> str:
    """Content hash of what determines a run's numbers (name and description left out; the
    flexride version included, so an upgrade never reuses old results).
    """
    from flexride import __version__

    data = scenario.model_dump(mode="json")
    data.pop("name", None)
    data.pop("description", None)
    return hashlib.sha256(
        canonical_json({"flexride": __version__, "scenario": data}).encode()
    ).hexdigest()


def stability_key(scenario: Scenario) -> str:
    """Hash of the parts of a scenario that the submission check depends on (module docs)."""
    data = scenario.model_dump(mode="json")
    for key in ("name", "description", "excitation"):
        data.pop(key, None)
    for body in ("carbody", "frames"):
        data.get("bodies", {}).get(body, {}).update(model="rigid")
    return hashlib.sha256(canonical_json(data).encode()).hexdigest()


def flexible_available() -> bool:
    """Whether this installation can build flexible bodies (``flexride.fem.flexible``)."""
    try:
        return importlib.util.find_spec("flexride.fem.flexible") is not None
    except (ImportError, ValueError):
        return False


def rigid_proxy(scenario: Scenario) -> Scenario:
    """What the submission check assembles: the scenario with rigid car body and frames and
    without measured irregularities (the stability limit does not depend on the excitation;
    measured data are checked on admission, :mod:`flexride.study.admission`).
    """
    data = scenario.model_dump(mode="json")
    data["bodies"]["carbody"]["model"] = "rigid"
    data["bodies"]["frames"]["model"] = "rigid"
    data["excitation"] = [e for e in data["excitation"] if e.get("kind") != "measured"]
    return Scenario.model_validate(data)


class PreflightCache:
    """Submission checks by stability key (thread-safe, least recently used first out)."""

    def __init__(self, size: int = 128):
        self.size = size
        self._items: OrderedDict[str, dict[str, Any] | StabilityError] = OrderedDict()
        self._lock = threading.Lock()
        self._key_locks: dict[str, threading.Lock] = {}

    def clear(self) -> None:
        """Forget every cached check."""
        with self._lock:
            self._items.clear()

    def check(self, scenario: Scenario, sources: MeasuredSources = LIBRARY) -> dict[str, Any]:
        """Check ``scenario`` for submission (see :func:`check_submission`), cached; uploaded
        profiles are read from ``sources`` (their ids are content hashes, so the key holds).
        """
        key = stability_key(scenario)
        with self._lock:
            key_lock = self._key_locks.setdefault(key, threading.Lock())
        with key_lock:  # one computation per key, concurrent requests wait for it
            with self._lock:
                hit = self._items.get(key)
                if hit is not None:
                    self._items.move_to_end(key)
            if hit is None:
                try:
                    hit = _preflight(scenario, sources)
                except StabilityError as exc:
                    hit = exc
                with self._lock:
                    self._items[key] = hit
                    while len(self._items) > self.size:
                        self._items.popitem(last=False)
        if isinstance(hit, StabilityError):
            raise hit
        return hit


def _preflight(scenario: Scenario, sources: MeasuredSources) -> dict[str, Any]:
    from flexride.solver import preflight

    try:
        info = preflight(rigid_proxy(scenario), sources=sources)
    except FlexrideError:
        raise
    except Exception as exc:  # a schema-valid scenario the solver cannot assemble
        raise ScenarioError(
            f"scenario: cannot be assembled: {type(exc).__name__}: {exc}"
        ) from None
    stab = info.get("stability") or {}
    return {"n_dof": info["n_dof"], "output_rate_hz": info["output_rate"],
            "stability": {k: stab[k] for k in ("dt_max", "dt_suggested", "dt", "margin", "auto",
                                               "critical_dof", "critical_frequency_hz",
                                               "point") if k in stab}}


PREFLIGHT = PreflightCache()
"""The process-wide submission-check cache."""


def check_installable(scenario: Scenario) -> None:
    """Refuse flexible bodies when this installation cannot build them (:class:`ScenarioError`
    at the field).
    """
    bodies = scenario.bodies
    flex = [f"bodies.{b}.model" for b in ("carbody", "frames")
            if getattr(bodies, b).finite_elements]
    if flex and not flexible_available():
        raise ScenarioError(
            f"scenario: {flex[0]}: flexible bodies are not available in this installation "
            "(module flexride.fem.flexible is missing); use 'rigid'"
        )


def check_submission(scenario: Scenario, *, cache: PreflightCache = PREFLIGHT,
                     sources: MeasuredSources = LIBRARY) -> dict[str, Any]:
    """Refuse a scenario that cannot run: flexible bodies not installed, assembly failure, or a
    time step beyond the stability limit (:class:`StabilityError` with ``dt_suggested``).
    Uploaded profiles are read from ``sources`` (the service: its upload store).

    Returns
    -------
    dict
        ``n_dof``, ``output_rate_hz`` and ``stability`` (``dt_max``, ``dt_suggested``...).
    """
    check_installable(scenario)
    if not scenario.solver.check_stability:
        return {"stability": None}
    return cache.check(scenario, sources)

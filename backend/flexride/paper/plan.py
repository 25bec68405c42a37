"""The runs of the paper's study: Table 3's conditions × speeds × rigid and flexible car body
(× irregularity realisations), each with the stretch of track it is evaluated on.

Study-fidelity rules (stated in the report):

* **Evaluation windows.** Random irregularity and corrugation on straight track: from 30 m on
  (the random profile fades in over its first 20 m and the wheelsets spread ±7.4 m about the
  vehicle centre; the run starts from static equilibrium). Curve: only while every wheelset is
  on the circular arc. Settlement: the whole run (smooth track before the dip; at 80 km/h the
  preset's 120 m last 5.4 s, just over one 5 s Sperling segment).
* **Shortened runs** (``--quick``, ``distance_scale``): the evaluated stretch is scaled, but
  kept at least ``min_eval_s`` long (the Sperling index needs 5 s segments) and, for the
  settlement, until 20 m after the last wheelset has left the dip. The random profile does not
  depend on the run length (synthesis over ≥ 960 m), so a shortened run sees the first part of
  the same track.
* **Same track for both models.** The rigid and the flexible run of a condition and speed use
  the same irregularity seed; ``seeds`` > 1 adds realisations 2, 3, … (seed 1 is the
  presets'; :mod:`flexride.study.seeds`, the rule of the service's studies too).
* **Flexible cut-off follows the excitation.** Elastic modes are kept up to
  max(the scenario's cut-off, 1.5 × the highest excitation frequency V/λ_min of the condition
  over the study's speeds, rounded up to 10 Hz; :mod:`flexride.scenario.fidelity`):
  corrugation of 0.5 m at 80 km/h excites 44 Hz, beyond the default 40 Hz. Car body and
  bogie frames alike; the rule changes the truncation of the modal model, not a physical
  parameter.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import asdict, dataclass, field
from typing import Any

from flexride.errors import FlexrideError
from flexride.scenario.fidelity import shortest_wavelength as condition_wavelength
from flexride.scenario.fidelity import sufficient_cutoff_hz
from flexride.scenario.presets import (
    PAPER_CONDITIONS,
    PAPER_SPEEDS_KMH,
    PAPER_VEHICLE,
    SMOOTH_CONDITION,
    STUDY_CONDITIONS,
    load_condition,
)
from flexride.scenario.presets import load_preset as _load_preset
from flexride.scenario.scenario import Scenario
from flexride.study.presets import MESH_SIZES_M, MESH_SPEED_KMH
from flexride.study.seeds import is_random, realisations, seed_overrides
from flexride.track.spectra import RANDOM_FADE_IN_M

__all__ = [
    "BODY_MODELS",
    "CONDITIONS",
    "RECORD_VERSION",
    "ReportError",
    "ReportOptions",
    "RunSpec",
    "Section",
    "build_plan",
    "mesh_plan",
    "section_of",
]

CONDITIONS: tuple[str, ...] = tuple(PAPER_CONDITIONS)
"""Table 3's conditions: random-straight, random-curve, corrugation, settlement."""

RANDOM_CONDITIONS = frozenset(c for c in CONDITIONS if is_random(PAPER_CONDITIONS[c][2]))
"""Conditions with a random irregularity (several realisations make sense)."""

BODY_MODELS: tuple[str, ...] = ("rigid", "flexible")
"""Car body and bogie frames both rigid, or both flexible (as in the paper)."""

QUICK_SPEEDS_KMH: tuple[float, ...] = (50.0, 80.0)
QUICK_DISTANCE_SCALE = 0.25
MIN_EVAL_S = 6.0
"""Shortest evaluated stretch of a shortened run (s): one 5 s Sperling segment and a margin."""

START_SKIP_M = 30.0
"""Start of the evaluated stretch on straight track (m): the 20 m fade-in of the random profile
plus the ±7.4 m spread of the wheelsets, rounded up."""

SETTLEMENT_START_M = 0.0
SETTLEMENT_DECAY_M = 20.0
FULL_SEEDS = 5
"""Irregularity realisations per random condition of the full report: every index of those
conditions is a mean with its 95 % confidence interval (at least five, as issue 14 asks)."""
QUICK_SEEDS = 1
"""Realisations of the quick report (a first look in a few minutes)."""
MESH_CONDITIONS: tuple[str, ...] = (SMOOTH_CONDITION, "random-straight")
"""Conditions of the element-size pre-calculation (§2.1, Fig. 4): the paper's smooth track, and
the random straight track its comfort results are about (first realisation)."""
QUICK_MESH_SIZES_M: tuple[float, ...] = (0.4, 0.3, 0.2)
"""Car-body element sizes of the quick report's pre-calculation (m): the three finest of the full
one's that cost no more than the 0.2 m body (:data:`flexride.study.presets.MESH_SIZES_M`)."""
RECORD_VERSION = 2
"""Version of the stored run record; part of every cache key (2: the air-spring forces and the
flexible bodies' frequencies)."""


class ReportError(FlexrideError):
    """Options of the paper report that cannot be run (the CLI prints one line, exit code 2)."""


def _half_extent() -> float:
    """Distance from the vehicle centre to the outer wheelsets (m), from the preset geometry."""
    g = PAPER_VEHICLE["geometry"]
    return float(g["bogie_centre_spacing"]) / 2.0 + float(g["wheelbase"]) / 2.0


@dataclass(frozen=True)
class ReportOptions:
    """What the report runs.

    Attributes
    ----------
    quick : bool
        Shortened study: two speeds (50, 80 km/h) and 1/4 of every evaluated stretch.
    seeds : int or None
        Irregularity realisations per random condition (1–50); default :data:`FULL_SEEDS`,
        or :data:`QUICK_SEEDS` with ``quick``.
    jobs : int or None
        Worker processes (default: the number of cores).
    distance_scale : float or None
        Factor on the evaluated stretch (0–1]; default 1, or 1/4 with ``quick``.
    speeds : tuple of float or None
        Speeds (km/h); default Table 3's 50–80 km/h, or 50 and 80 with ``quick``.
    conditions : tuple of str or None
        Subset of :data:`CONDITIONS` (default all).
    min_eval_s : float
        Shortest evaluated stretch of a shortened run (s).
    overrides : tuple of (str, value)
        Dotted-path scenario overrides applied to every run. For tests only (e.g. a coarse FE
        mesh); the report lists them as a deviation from the paper's study.
    mesh_sizes : tuple of float or None
        Car-body element sizes (m) of the element-size pre-calculation (Fig. 4; runs of
        :data:`MESH_CONDITIONS` at :data:`~flexride.study.presets.MESH_SPEED_KMH`); default
        :data:`~flexride.study.presets.MESH_SIZES_M`, or :data:`QUICK_MESH_SIZES_M` with
        ``quick``; empty: none.
    """

    quick: bool = False
    seeds: int | None = None
    jobs: int | None = None
    distance_scale: float | None = None
    speeds: tuple[float, ...] | None = None
    conditions: tuple[str, ...] | None = None
    min_eval_s: float = MIN_EVAL_S
    overrides: tuple[tuple[str, Any], ...] = ()
    mesh_sizes: tuple[float, ...] | None = None

    def seed_count(self) -> int:
        """Realisations per random condition: ``seeds``, or the default of the report's kind
        (:data:`FULL_SEEDS`, :data:`QUICK_SEEDS` with ``quick``).
        """
        return self.seeds if self.seeds is not None else (
            QUICK_SEEDS if self.quick else FULL_SEEDS)

    def checked(self) -> ReportOptions:
        """These options with defaults filled in; :class:`ReportError` for impossible ones."""
        seeds = self.seed_count()
        if not 1 <= seeds <= 50:
            raise ReportError(f"--seeds must be between 1 and 50, got {seeds}")
        jobs = self.jobs if self.jobs is not None else (os.cpu_count() or 1)
        if jobs < 1:
            raise ReportError(f"--jobs must be at least 1, got {jobs}")
        scale = self.distance_scale
        if scale is None:
            scale = QUICK_DISTANCE_SCALE if self.quick else 1.0
        if not 0.0 < scale <= 1.0:
            raise ReportError(f"--distance-scale must be in (0, 1], got {scale}")
        speeds = self.speeds or (QUICK_SPEEDS_KMH if self.quick else
                                 tuple(float(v) for v in PAPER_SPEEDS_KMH))
        if any(not 0.0 < v <= 200.0 for v in speeds) or len(set(speeds)) != len(speeds):
            raise ReportError(f"speeds must be distinct values in (0, 200] km/h, got {speeds}")
        conditions = self.conditions or CONDITIONS
        unknown = [c for c in conditions if c not in CONDITIONS]
        if unknown or len(set(conditions)) != len(conditions):
            raise ReportError(f"unknown or repeated condition(s) {', '.join(unknown) or conditions}"
                              f"; Table 3's conditions: {', '.join(CONDITIONS)}")
        if not self.min_eval_s > 0.0:
            raise ReportError(f"min_eval_s must be positive, got {self.min_eval_s}")
        return ReportOptions(quick=self.quick, seeds=seeds, jobs=jobs,
                             distance_scale=scale, speeds=tuple(sorted(speeds)),
                             conditions=tuple(c for c in CONDITIONS if c in conditions),
                             min_eval_s=self.min_eval_s, overrides=tuple(self.overrides),
                             mesh_sizes=self._mesh_sizes())

    def _mesh_sizes(self) -> tuple[float, ...]:
        sizes = self.mesh_sizes
        if sizes is None:
            sizes = QUICK_MESH_SIZES_M if self.quick else MESH_SIZES_M
        if len(sizes) == 1 or len(set(sizes)) != len(sizes) or any(
                not 0.05 <= h <= 1.0 for h in sizes):
            raise ReportError("mesh sizes must be none or at least two distinct element sizes "
                              f"in [0.05, 1] m, got {tuple(sizes)}")
        return tuple(sorted((float(h) for h in sizes), reverse=True))

    def to_dict(self) -> dict[str, Any]:
        """JSON form (for the report header and ``report.json``)."""
        d = asdict(self)
        d["overrides"] = dict(self.overrides)
        return d

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> ReportOptions:
        """The options of :meth:`to_dict`'s JSON form (a service study keeps them)."""
        d = dict(data)
        for key in ("speeds", "conditions", "mesh_sizes"):
            if d.get(key) is not None:
                d[key] = tuple(d[key])
        d["overrides"] = tuple((d.get("overrides") or {}).items())
        return cls(**d)


@dataclass(frozen=True)
class RunSpec:
    """One run of the study: everything that decides its result.

    Attributes
    ----------
    condition : str
        Key of Table 3's condition.
    speed_kmh : float
        Running speed (km/h).
    body : str
        ``rigid`` or ``flexible`` (car body and bogie frames).
    seed : int or None
        Irregularity seed (random conditions), else None.
    distance_m : float
        Length of the run (m).
    window_m : (float, float)
        Evaluated stretch, positions of the vehicle centre along the line (m).
    cutoff_hz : float or None
        Highest elastic mode kept (flexible runs, Hz).
    overrides : tuple of (str, value)
        Test overrides (see :class:`ReportOptions`).
    element_size_m : float or None
        Car-body element size of a run of the element-size pre-calculation (m); None for the
        runs of Table 3 (the scenario's size).
    """

    condition: str
    speed_kmh: float
    body: str
    seed: int | None
    distance_m: float
    window_m: tuple[float, float]
    cutoff_hz: float | None = None
    overrides: tuple[tuple[str, Any], ...] = field(default=())
    element_size_m: float | None = None

    @property
    def label(self) -> str:
        """Short text, e.g. ``random-straight 80 km/h flexible seed 1`` (``… 0.3 m mesh`` in
        the pre-calculation).
        """
        seed = f" seed {self.seed}" if self.seed is not None else ""
        mesh = f" {self.element_size_m:g} m mesh" if self.element_size_m is not None else ""
        return f"{self.condition} {self.speed_kmh:g} km/h {self.body}{seed}{mesh}"

    def scenario_overrides(self) -> dict[str, Any]:
        """Dotted-path overrides of the condition's 50 km/h preset that make this run."""
        out: dict[str, Any] = dict(self.overrides)
        out.update({"name": f"paper-{self.condition}-{self.speed_kmh:g}",
                    "speed_kmh": float(self.speed_kmh), "distance_m": float(self.distance_m),
                    "duration_s": None})
        if self.seed is not None:
            out.update(seed_overrides(STUDY_CONDITIONS[self.condition][2], self.seed))
        for part in ("carbody", "frames"):
            out[f"bodies.{part}.model"] = self.body
            if self.body == "flexible" and self.cutoff_hz is not None:
                out[f"bodies.{part}.cutoff_hz"] = float(self.cutoff_hz)
        if self.element_size_m is not None:
            out["bodies.carbody.element_size_m"] = float(self.element_size_m)
        return out

    def scenario(self) -> Scenario:
        """The validated scenario of this run."""
        return load_condition(self.condition, PAPER_SPEEDS_KMH[0], self.scenario_overrides())

    def key(self) -> str:
        """Cache key: hash of the scenario, the window, :data:`RECORD_VERSION` and, for a run
        of the pre-calculation, its element size (its record is its own even where the
        scenario is that of a Table 3 run).
        """
        data = {"scenario": self.scenario().model_dump(mode="json"),
                "window_m": list(self.window_m), "version": RECORD_VERSION}
        if self.element_size_m is not None:
            data["mesh"] = float(self.element_size_m)
        text = json.dumps(data, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:32]

    def to_dict(self) -> dict[str, Any]:
        """JSON form."""
        d = asdict(self)
        d["window_m"] = list(self.window_m)
        d["overrides"] = dict(self.overrides)
        return d

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> RunSpec:
        """The run of :meth:`to_dict`'s JSON form (same :meth:`key`)."""
        d = dict(data)
        d["window_m"] = (float(d["window_m"][0]), float(d["window_m"][1]))
        d["overrides"] = tuple((d.get("overrides") or {}).items())
        return cls(**d)


@dataclass(frozen=True)
class Section:
    """The stretch of a run its indices are evaluated on (positions of the vehicle centre
    along the line, m), and the rule that chose it.

    Attributes
    ----------
    start_m, end_m : float
        The section (m).
    min_end_m : float
        End it may not be shortened below (a shortened run, m).
    rule : str
        ``arc`` (every wheelset on the circular arc), ``curve`` (every wheelset on the curve,
        transitions included), ``settlement`` (smooth track before the dip to the end),
        ``after-fade-in`` (from :data:`START_SKIP_M` on) or ``run`` (the whole run).
    """

    start_m: float
    end_m: float
    min_end_m: float
    rule: str

    def label(self) -> str:
        """e.g. ``arc (every wheelset on the circular arc) 102.4–287.6 m``."""
        what = {"arc": "every wheelset on the circular arc",
                "curve": "every wheelset on the curve, transitions included",
                "settlement": "the whole run: smooth track, the dip and 20 m after it",
                "after-fade-in": f"from {START_SKIP_M:g} m on: after the random profile's "
                                 "fade-in and the wheelsets' spread",
                "run": "the whole run"}[self.rule]
        return f"{self.rule} ({what}) {self.start_m:.1f}–{self.end_m:.1f} m"


SECTION_CURVE_RULES = ("arc", "curve")
"""How a curve is evaluated: its circular arc only (the report's rule), or the whole curve."""


def section_of(line: dict[str, Any], excitation: list[dict[str, Any]], distance: float,
               half_extent: float, curve: str = "arc") -> Section:
    """The section a run of a line and excitation is evaluated on (the report's rules).

    Parameters
    ----------
    line : dict
        The scenario's ``line`` (JSON form).
    excitation : list of dict
        The scenario's ``excitation`` (JSON form).
    distance : float
        Length of the run (m).
    half_extent : float
        Distance from the vehicle centre to the outer wheelsets (m).
    curve : {"arc", "curve"}
        On a curve: the circular arc, or the whole curve with its transitions.
    """
    if line.get("kind") == "curve":
        s0 = float(line.get("start_m", 0.0))
        entry, arc = float(line["entry_transition_m"]), float(line["arc_length_m"])
        if curve == "arc":
            return Section(s0 + entry + half_extent, s0 + entry + arc - half_extent,
                           s0 + entry + half_extent, "arc")
        end = s0 + entry + arc + float(line.get("exit_transition_m", entry))
        return Section(s0 + half_extent, end - half_extent, s0 + half_extent, "curve")
    dips = [e for e in excitation if e.get("kind") == "settlement"]
    if dips:
        dip_end = max(float(e["position_m"]) + float(e["wavelength_m"]) for e in dips)
        return Section(SETTLEMENT_START_M, distance,
                       dip_end + half_extent + SETTLEMENT_DECAY_M, "settlement")
    if excitation:
        start = max(START_SKIP_M, RANDOM_FADE_IN_M + half_extent)
        return Section(start, distance, start, "after-fade-in")
    return Section(0.0, distance, 0.0, "run")


def full_window(condition: str) -> tuple[float, float, float]:
    """Evaluated stretch of a full run and the end it may not be shortened below (m).

    Returns
    -------
    (start, end, min_end) : float
        Positions of the vehicle centre along the line (m).
    """
    _, line, exc, distance = STUDY_CONDITIONS[condition]
    sec = section_of(line, exc, float(distance), _half_extent())
    return sec.start_m, sec.end_m, sec.min_end_m


def run_window(condition: str, speed_kmh: float, scale: float,
               min_eval_s: float) -> tuple[float, tuple[float, float]]:
    """Run length and evaluated stretch (m) of a condition at a speed, shortened by ``scale``.

    With ``scale`` = 1 the preset's run length is kept.
    """
    start, end, min_end = full_window(condition)
    distance = float(STUDY_CONDITIONS[condition][3])
    if scale >= 1.0:
        return distance, (start, end)
    length = end - start
    shortened = max(scale * length, min_eval_s * speed_kmh / 3.6, min_end - start)
    new_end = start + min(length, shortened)
    return min(distance, new_end), (start, new_end)


def shortest_wavelength(condition: str) -> float:
    """Shortest excitation wavelength of a condition (m)."""
    return condition_wavelength(PAPER_CONDITIONS[condition][2])


def flexible_cutoff(condition: str, speeds_kmh: tuple[float, ...], base_hz: float) -> float:
    """Elastic-mode cut-off for a condition (Hz): the scenario rule
    (:func:`flexride.scenario.fidelity.sufficient_cutoff_hz`) at the highest speed.
    """
    return sufficient_cutoff_hz(max(speeds_kmh) / 3.6 / shortest_wavelength(condition), base_hz)


def _base_cutoff(overrides: tuple[tuple[str, Any], ...]) -> float:
    sc = _load_preset("paper-metro", {**dict(overrides), "bodies.carbody.model": "flexible"})
    return float(sc.bodies.carbody.cutoff_hz)


def build_plan(options: ReportOptions) -> list[RunSpec]:
    """Every run of the study, in condition, speed, seed, body order.

    Parameters
    ----------
    options : ReportOptions
        Checked options (:meth:`ReportOptions.checked`).
    """
    assert options.speeds is not None and options.conditions is not None
    scale = options.distance_scale or 1.0
    base = _base_cutoff(options.overrides)
    specs = []
    for cond in options.conditions:
        cutoff = flexible_cutoff(cond, options.speeds, base)
        seeds: list[int | None] = (list(realisations(options.seed_count()))
                                   if cond in RANDOM_CONDITIONS else [None])
        for v in options.speeds:
            distance, window = run_window(cond, v, scale, options.min_eval_s)
            for seed in seeds:
                for body in BODY_MODELS:
                    specs.append(RunSpec(cond, float(v), body, seed, distance, window,
                                         cutoff if body == "flexible" else None,
                                         options.overrides))
    return specs + mesh_plan(options)


def mesh_plan(options: ReportOptions) -> list[RunSpec]:
    """The runs of the element-size pre-calculation (§2.1, Fig. 4): the flexible vehicle at
    :data:`~flexride.study.presets.MESH_SPEED_KMH` on each of :data:`MESH_CONDITIONS` (the
    random one's first realisation) with the car body at each of ``options.mesh_sizes``, modes
    to the random straight track's cut-off (the same model on both tracks), in condition, size
    (coarse to fine) order.
    """
    scale = options.distance_scale or 1.0
    cutoff = flexible_cutoff("random-straight", (MESH_SPEED_KMH,), _base_cutoff(options.overrides))
    specs = []
    for cond in MESH_CONDITIONS:
        distance, window = run_window(cond, MESH_SPEED_KMH, scale, options.min_eval_s)
        seed = 1 if is_random(STUDY_CONDITIONS[cond][2]) else None
        specs += [RunSpec(cond, MESH_SPEED_KMH, "flexible", seed, distance, window, cutoff,
                          options.overrides, element_size_m=h)
                  for h in options.mesh_sizes or ()]
    return specs

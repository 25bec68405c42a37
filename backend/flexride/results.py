"""Results of a run: time and distance axes, named channels with units, and their HDF5 file.

Channel names follow ``<body>.<point>.<quantity>.<direction>`` (DESIGN §4), for example
``carbody.PR.acc.z`` (car-body vertical acceleration at the roof point, m/s²),
``wheelset1.left.force.z`` (wheel-rail normal force of the left wheel of wheelset 1, N) or
``secondary.1L.force.z`` (vertical force of the left air spring of bogie 1 on the car body, N);
see :class:`Channel`.

The HDF5 layout is one file per run::

    /time                 float64 [n]   s
    /distance             float64 [n]   m
    /channels/<name>      float64 [n]   attribute ``unit``
    /points/body          str [p]       body of each recorded point (``carbody``, ``frame1``...)
    /points/name          str [p]       point name (``PR``, ``F3_2``, ``centre``...)
    /points/position      float64 [p, 3] m: x, y, z (attribute ``frame``, see below)
    root attributes: ``format`` = "flexride-results", ``format_version``,
                     ``flexride_version``, ``scenario_json``, ``meta_json``

``/points`` (format version 2) gives the position of every point whose accelerations are
recorded (channels ``<body>.<name>.acc.<y|z>``) in the nominal vehicle geometry: x from the
car-body centre, forward positive; y left positive; z above top of rail (m). It is derived from
the scenario with the rule the solver uses (:func:`flexride.vehicle.topology.recorded_points`),
at write time; for files without it (version 1) :func:`read_points` derives it the same way.

Files are written atomically: to a temporary name in the target directory, then renamed.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from flexride.errors import ResultsFileError
from flexride.fileio import atomic_path
from flexride.units import kmh_to_mps

if TYPE_CHECKING:
    import h5py

FORMAT_NAME = "flexride-results"
FORMAT_VERSION = 3
#: Description of the coordinates of ``/points/position``.
POINT_FRAME = ("nominal vehicle geometry: x from the car-body centre, forward positive; "
               "y left positive; z above top of rail (m)")

#: Suspension stages that name a channel's "body" (``<stage>.<element>.force.<direction>``,
#: :class:`Channel`); the solver records the ``secondary`` stage (the air springs).
SUSPENSION_STAGES = ("primary", "secondary")

TIMING_KEYS = ("setup_s", "solve_s", "write_s", "analyze_s")
"""The phases of a run timed in ``timings`` (``flexride run --json``, job records)."""


def run_timings(meta: dict[str, Any], write_s: float | None,
                analyze_s: float | None) -> dict[str, float | None]:
    """Wall time of each phase of a run (s): ``setup_s`` (assembly, static equilibrium,
    stability check) and ``solve_s`` (time loop) from the run's ``meta``, ``write_s`` (results
    file) and ``analyze_s`` (comfort and safety) as measured by the caller (None: not done).
    """
    values = (meta.get("wall_time_setup_s"), meta.get("wall_time_solve_s"), write_s, analyze_s)
    return {k: None if v is None else round(float(v), 4)
            for k, v in zip(TIMING_KEYS, values, strict=True)}


def time_step_record(meta: dict[str, Any]) -> dict[str, Any]:
    """The run's time step from its ``meta``: ``s`` (the step, s), ``auto`` (chosen by the
    solver), ``limit_s`` (the stability limit of the solver's one-step map, s), ``margin``
    (limit / step) and ``limited_by`` (the operating point and coordinate that set the limit);
    None where the run was not checked. Written as ``time_step_*`` attributes of a results file.
    """
    stab = meta.get("stability") or {}
    limited = (f"{stab['point']}: {stab['critical_dof']}"
               if stab.get("point") and stab.get("critical_dof") else None)
    return {"s": meta.get("dt"), "auto": stab.get("auto"), "limit_s": stab.get("dt_max"),
            "margin": stab.get("margin"), "limited_by": limited}


def time_step_text(record: dict[str, Any]) -> str:
    """:func:`time_step_record` in a few words: ``step 6.25e-05 s (auto, 1.30 × below the
    stability limit)``.
    """
    if record.get("s") is None:
        return "step unknown"
    text = f"step {record['s']:.3g} s"
    if record.get("margin") is None:
        return f"{text} (not checked)"
    how = "auto, " if record.get("auto") else ""
    return f"{text} ({how}{record['margin']:.2f} × below the stability limit)"


@dataclass(frozen=True)
class Channel:
    """The parts of a channel name ``<body>.<point>.<quantity>.<direction>``.

    This is the one naming rule of recorded channels:

    * ``carbody.PC.acc.z``: acceleration (m/s²) at a recorded point, direction ``y`` or ``z``;
    * ``wheelset1.left.force.z``: wheel–rail force (N) of a wheel, ``z`` vertical, ``y``
      lateral, ``n`` normal; ``wheelset1.left.rail_disp.z``: rail displacement under it (m);
    * ``frame1.cg.disp.x`` / ``rot.x`` / ``spin.y``: rigid coordinates of a body (m, rad);
    * ``secondary.1L.force.z``: force (N) of a suspension element, where "body" is the
      suspension stage (:data:`SUSPENSION_STAGES`) and "point" the element within it (``1L``:
      bogie 1, left; ``2R``: bogie 2, right), direction ``x``, ``y`` or ``z``. The value is the
      force the element's translational spring and damper exert on the car body (its body A),
      in the car body's track frame (x forward, y left, z up), averaged over each output
      interval like the wheel forces: vertical positive up, so an air spring's static value is
      its share of the car body's weight. The solver records the air springs
      (``secondary.<bogie><L|R>.force.<x|y|z>``) in every run.
    """

    body: str
    point: str
    quantity: str
    direction: str

    @property
    def name(self) -> str:
        """The channel name."""
        return f"{self.body}.{self.point}.{self.quantity}.{self.direction}"

    @classmethod
    def parse(cls, name: str) -> Channel | None:
        """The parts of ``name``, or None when it does not follow the rule."""
        parts = str(name).split(".")
        if len(parts) != 4 or not all(parts):
            return None
        return cls(*parts)


@dataclass
class Results:
    """Recorded output of one simulation.

    Attributes
    ----------
    time : numpy.ndarray
        Output time axis in s, uniformly sampled at :attr:`sample_rate`.
    distance : numpy.ndarray
        Distance of the vehicle centre along the line in m, same length as ``time``.
    channels : dict of str to numpy.ndarray
        Channel data, each the same length as ``time``.
    units : dict of str to str
        SI unit of every channel (``"m/s^2"``, ``"N"``, ``"m"``, ...).
    scenario : dict
        The full scenario that produced the run (JSON-compatible).
    meta : dict
        Run facts: ``speed_mps``, ``dt`` (s), ``output_rate`` (Hz), wall times, etc.;
        ``flexible_bodies``: per flexible body (``carbody``, ``frame1``, ``frame2``; rigid
        bodies absent) its ``model``, ``element_size_m`` (m) and retained
        ``elastic_frequencies_hz`` (Hz), see
        :func:`flexride.solver.assemble.flexible_body_facts`.
    points : list of dict, optional
        Recorded points (:meth:`flexride.vehicle.topology.RecordedPoint.to_dict`: ``body``,
        ``name``, ``description``, ``x``, ``y``, ``z`` in m, ``on_floor``), as the solver made
        them; derived from the scenario when omitted (:attr:`recorded_points`).
    """

    time: np.ndarray
    distance: np.ndarray
    channels: dict[str, np.ndarray]
    units: dict[str, str]
    scenario: dict[str, Any] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)
    points: list[dict[str, Any]] | None = None

    @property
    def recorded_points(self) -> list[dict[str, Any]]:
        """Recorded points (dicts of :class:`~flexride.vehicle.topology.RecordedPoint`):
        :attr:`points` when given, else derived from :attr:`scenario` (empty when the scenario
        does not describe a vehicle).
        """
        if self.points is not None:
            return self.points
        return points_from_scenario(self.scenario)

    @property
    def sample_rate(self) -> float:
        """Output sample rate in Hz."""
        if "output_rate" in self.meta:
            return float(self.meta["output_rate"])
        if self.time.size < 2:
            raise ResultsFileError("cannot infer the sample rate from fewer than two samples")
        return float(1.0 / (self.time[1] - self.time[0]))

    def channel(self, name: str) -> np.ndarray:
        """Return the data of channel ``name``; raise :class:`KeyError` naming close matches."""
        try:
            return self.channels[name]
        except KeyError:
            raise KeyError(
                f"no channel {name!r}; channels are: {', '.join(sorted(self.channels))}"
            ) from None

    def names(self, quantity: str | None = None, body: str | None = None) -> list[str]:
        """Channel names, optionally filtered by quantity (``acc``, ``force``...) and body."""
        return [c.name for c in self.parsed()
                if (quantity is None or c.quantity == quantity)
                and (body is None or c.body == body)]

    def parsed(self) -> list[Channel]:
        """Every channel that follows the naming rule, parsed (:class:`Channel`)."""
        return [c for c in map(Channel.parse, self.channels) if c is not None]

    def running_speed(self) -> float | None:
        """Running speed (m/s): from the run facts, else the scenario's ``speed_kmh``, else the
        distance and time axes; None when none of them tells.
        """
        v = self.meta.get("speed_mps")
        if v is not None:
            return float(v)
        kmh = self.scenario.get("speed_kmh") if isinstance(self.scenario, dict) else None
        if kmh is not None:
            return kmh_to_mps(kmh)
        d, t = np.asarray(self.distance), np.asarray(self.time)
        if d.size >= 2 and t[-1] > t[0]:
            return float((d[-1] - d[0]) / (t[-1] - t[0]))
        return None

    def write_hdf5(self, path: str | os.PathLike[str]) -> Path:
        """Write the results atomically to ``path`` (temporary file, then rename).

        Parameters
        ----------
        path : path-like
            Destination ``.h5`` file; parent directories are created.

        Returns
        -------
        pathlib.Path
            The written path.
        """
        from flexride import __version__

        dest = Path(path)
        import h5py  # on use: a run's import stays light (docs/architecture.md)

        with atomic_path(dest) as tmp_name, h5py.File(tmp_name, "w") as f:
            f.attrs["format"] = FORMAT_NAME
            f.attrs["format_version"] = FORMAT_VERSION
            f.attrs["flexride_version"] = __version__
            f.attrs["scenario_json"] = json.dumps(self.scenario)
            f.attrs["meta_json"] = json.dumps(self.meta)
            for key, value in time_step_record(self.meta).items():
                if value is not None:
                    f.attrs[f"time_step_{key}"] = value
            f.create_dataset("time", data=self.time).attrs["unit"] = "s"
            f.create_dataset("distance", data=self.distance).attrs["unit"] = "m"
            grp = f.create_group("channels")
            for name, data in self.channels.items():
                # Uncompressed: recorded float64 signals are noise-like, so gzip 4 + shuffle
                # saved 23 % of the size at 10× the write time (0.23 against 0.02 s for a
                # 20 s run of 122 channels), the largest cost of a study's job beside the
                # solver (docs/architecture.md, performance figures).
                ds = grp.create_dataset(name, data=data)
                ds.attrs["unit"] = self.units.get(name, "")
            _write_points(f, self.recorded_points)
        return dest

    @classmethod
    def read_hdf5(cls, path: str | os.PathLike[str]) -> Results:
        """Read a results file written by :meth:`write_hdf5`.

        Raises
        ------
        ResultsFileError
            If the file is missing, unreadable or not a flexride results file.
        """
        p = Path(path)
        if not p.is_file():
            raise ResultsFileError(f"results file not found: {p}")
        try:
            import h5py

            with h5py.File(p, "r") as f:
                if f.attrs.get("format") != FORMAT_NAME:
                    raise ResultsFileError(f"{p} is not a flexride results file")
                channels = {}
                units = {}
                for name, ds in f["channels"].items():
                    channels[name] = ds[()]
                    units[name] = str(ds.attrs.get("unit", ""))
                return cls(
                    time=f["time"][()],
                    distance=f["distance"][()],
                    channels=channels,
                    units=units,
                    scenario=json.loads(f.attrs["scenario_json"]),
                    meta=json.loads(f.attrs["meta_json"]),
                    points=read_points(f),
                )
        except ResultsFileError:
            raise
        except (OSError, KeyError, ValueError) as exc:
            raise ResultsFileError(f"cannot read results file {p}: {exc}") from exc


def points_from_scenario(scenario: dict[str, Any]) -> list[dict[str, Any]]:
    """Recorded points of a scenario (JSON form) by the solver's rule.

    Parameters
    ----------
    scenario : dict
        A full scenario as stored in a results file (``scenario_json``).

    Returns
    -------
    list of dict
        :meth:`~flexride.vehicle.topology.RecordedPoint.to_dict` in channel order; empty when
        ``scenario`` is not a valid scenario. Used only for results without points (files
        written before format 3, results made by hand).
    """
    from pydantic import ValidationError

    from flexride.scenario.scenario import Scenario
    from flexride.vehicle.topology import recorded_points

    try:
        sc = Scenario.model_validate(scenario)
        pts = recorded_points(sc.vehicle, sc.output)
    except (ValidationError, ValueError, TypeError):
        return []
    return [p.to_dict() for p in pts]


def _write_points(f: h5py.File, points: list[dict[str, Any]]) -> None:
    import h5py

    grp = f.create_group("points")
    text = h5py.string_dtype("utf-8")
    grp.create_dataset("body", data=[p["body"] for p in points], dtype=text)
    grp.create_dataset("name", data=[p["name"] for p in points], dtype=text)
    grp.create_dataset("description", data=[p.get("description", "") for p in points],
                       dtype=text)
    grp.create_dataset("kind", data=[p.get("kind", "") for p in points], dtype=text)
    floor = [-1 if p.get("on_floor") is None else int(bool(p["on_floor"])) for p in points]
    grp.create_dataset("on_floor", data=np.array(floor, dtype=np.int8)).attrs["meaning"] = (
        "1 on the car-body floor, 0 not, -1 off the car body")
    pos = np.array([[p["x"], p["y"], p["z"]] for p in points], dtype=np.float64).reshape(-1, 3)
    ds = grp.create_dataset("position", data=pos)
    ds.attrs["unit"] = "m"
    ds.attrs["frame"] = POINT_FRAME


def read_points(f: h5py.File) -> list[dict[str, Any]]:
    """Recorded points of an open results file: ``/points`` when present (format version 2 has
    positions, 3 also descriptions and ``on_floor``), else derived from its scenario
    (:func:`points_from_scenario`).

    Parameters
    ----------
    f : h5py.File
        A results file open for reading.

    Returns
    -------
    list of dict
        :meth:`~flexride.vehicle.topology.RecordedPoint.to_dict` of each point.
    """
    grp = f.get("points")
    if grp is None or "description" not in grp:
        try:
            scenario = json.loads(f.attrs.get("scenario_json", "{}"))
        except (TypeError, ValueError):
            scenario = None
        derived = points_from_scenario(scenario) if isinstance(scenario, dict) else []
        if grp is None or derived:
            return derived
    bodies = grp["body"].asstr()[()]
    names = grp["name"].asstr()[()]
    pos = np.asarray(grp["position"][()], dtype=np.float64).reshape(-1, 3)
    n = len(names)
    texts = grp["description"].asstr()[()] if "description" in grp else [""] * n
    kinds = grp["kind"].asstr()[()] if "kind" in grp else [""] * n
    floor = grp["on_floor"][()] if "on_floor" in grp else np.full(n, -1)
    return [{"body": str(b), "name": str(nm), "description": str(t), "x": float(p[0]),
             "y": float(p[1]), "z": float(p[2]), "on_floor": None if fl < 0 else bool(fl),
             "kind": str(k)}
            for b, nm, t, p, fl, k in zip(bodies, names, texts, pos, floor, kinds, strict=True)]

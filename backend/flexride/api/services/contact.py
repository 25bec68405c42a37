"""Contact geometry of a wheel and rail profile pair, as ``GET /contact/geometry`` answers it.

The same library calls as ``flexride contact table`` and ``flexride contact conicity``
(:mod:`flexride.cli.contact`): the profiles are built in or uploaded
(:func:`flexride.contact.scenario_table.load_profile` with the upload store's sources, never a
path), placed by :class:`~flexride.contact.placement.Placement`, searched by
:func:`~flexride.contact.search.search_contact`; the rows come from
:mod:`flexride.contact.table_rows` and the conicity from
:func:`~flexride.contact.conicity.equivalent_conicity` on the CLI's ±12 mm grid.

Cost and caching: the answer is a pure function of its parameters (an upload id names fixed
content). The rigid contact search holds the interpreter for about 0.05 s without roll and
0.3 s with roll on the default grid (±12 mm in 0.05 mm steps, 481 rows; the conicity needs
the same grid, so one search serves both) and up to 0.8 s on the largest grid allowed
(:data:`MAX_ROWS` rows). Searches are kept in an LRU of :data:`GEOMETRY_CACHE` entries and
rendered answers (JSON, gzip) in a :class:`~flexride.store.lru.ByteLRU` of
:data:`ANSWER_CACHE_BYTES`; concurrent requests for the same answer compute it once.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
from fastapi import Request, Response

from flexride.api.services.result_cache import Rendered, accepts_gzip, gzip_settings, render
from flexride.contact.placement import Placement, place_rail
from flexride.contact.profiles import Profile
from flexride.contact.search import ContactGeometry, SearchSettings, search_contact
from flexride.contact.table_rows import (
    CONICITY_STEP_MM,
    CONICITY_Y_MAX_MM,
    TABLE_COLUMNS,
    conicity_rows,
    rounded,
    table_rows,
)
from flexride.errors import ErrorItem, ScenarioError
from flexride.scenario.contact import ProfileSource
from flexride.store.lru import ByteLRU
from flexride.track.measured import MeasuredSources

__all__ = ["MAX_DRAWN_POINTS", "MAX_ROWS", "GeometryQuery", "geometry_answer",
           "geometry_content"]

MAX_ROWS = 4001
"""Most rows (Δy grid points) of one answer: ±20 mm in 0.01 mm steps."""
MAX_DRAWN_POINTS = 1500
"""Most points of each profile drawn."""
GEOMETRY_CACHE = 8
"""Contact searches kept (one of 4001 points holds about 2 MB)."""
ANSWER_CACHE_BYTES = 48 * 1024 * 1024
"""Bytes of rendered answers kept (the default grid's answer is about 0.4 MB)."""
BUILTIN = {"wheel": "s1002", "rail": "60e1"}
"""The built-in profile of each kind."""

_ANSWERS = ByteLRU(ANSWER_CACHE_BYTES, max_entries=256)


@dataclass(frozen=True)
class GeometryQuery:
    """The parameters of a contact-geometry request (lengths in mm), hashable.

    Attributes
    ----------
    wheel, rail : str
        ``s1002`` / ``60e1`` or the id of an uploaded profile (64 hexadecimal digits).
    inclination : str
        ``1:40``, ``1:20`` or ``none``.
    gauge_mm, gauge_height_mm, flange_back_mm, r0_mm : float
        Track gauge, gauge point below the top of rail, flange-back distance, nominal rolling
        radius (mm).
    roll : bool
        Solve the wheelset roll (True) or keep it 0.
    y_max_mm, step_mm : float
        Half range and step of the Δy grid (mm).
    """

    wheel: str
    rail: str
    inclination: str
    gauge_mm: float
    gauge_height_mm: float
    flange_back_mm: float
    r0_mm: float
    roll: bool
    y_max_mm: float
    step_mm: float

    def __post_init__(self) -> None:
        """Normalise the profile names (built-in names are case-insensitive)."""
        for kind in ("wheel", "rail"):
            value = getattr(self, kind)
            if value.lower() == BUILTIN[kind]:
                object.__setattr__(self, kind, BUILTIN[kind])

    def check(self) -> None:
        """Refuse what the ranges of the single parameters let through (422 at the query
        parameter).

        Raises
        ------
        ScenarioError
            Located at ``("query", name)``: a grid of more than :data:`MAX_ROWS` rows or a step
            beyond the half range; a flange-back distance not below the gauge.
        """
        n_half = round(self.y_max_mm / self.step_mm)
        if n_half < 1:
            raise _at("step_mm", f"the step ({self.step_mm:g} mm) must not exceed the Δy half "
                      f"range y_max_mm ({self.y_max_mm:g} mm)")
        if 2 * n_half + 1 > MAX_ROWS:
            least = 2.0 * self.y_max_mm / (MAX_ROWS - 1)
            raise _at("step_mm", f"±{self.y_max_mm:g} mm in {self.step_mm:g} mm steps gives "
                      f"{2 * n_half + 1} rows, at most {MAX_ROWS} are allowed (allowed: "
                      f"≥ {least:.4g} mm for this y_max_mm)")
        if self.flange_back_mm >= self.gauge_mm:
            raise _at("flange_back_mm", f"the flange-back distance ({self.flange_back_mm:g} mm) "
                      f"must be smaller than the gauge ({self.gauge_mm:g} mm)")

    @property
    def placement(self) -> Placement:
        """The placement of the profiles (SI units)."""
        return Placement(inclination=self.inclination,  # type: ignore[arg-type]
                         gauge=self.gauge_mm * 1e-3, gauge_height=self.gauge_height_mm * 1e-3,
                         flange_back=self.flange_back_mm * 1e-3, r0=self.r0_mm * 1e-3)

    @property
    def settings(self) -> SearchSettings:
        """The search settings of the Δy grid (SI units)."""
        return SearchSettings(y_max=self.y_max_mm * 1e-3, step=self.step_mm * 1e-3,
                              roll=self.roll)

    def on_conicity_grid(self) -> GeometryQuery:
        """The same query on the grid of the equivalent conicity (the CLI's)."""
        return replace(self, y_max_mm=CONICITY_Y_MAX_MM, step_mm=CONICITY_STEP_MM)


def _at(name: str, msg: str) -> ScenarioError:
    """A 422 problem at query parameter ``name``."""
    return ScenarioError.at(("query", name), msg, source="request")


def _at_many(names: tuple[str, ...], msg: str) -> ScenarioError:
    """The same problem at several query parameters."""
    items = [ErrorItem(("query", n), msg) for n in names]
    return ScenarioError(f"request: {msg}", items)


Dirs = tuple[str | None, str | None]
"""Upload directories the wheel and the rail profile are read from (None: built in)."""


def _dirs(query: GeometryQuery, sources: MeasuredSources) -> Dirs:
    """Where the profiles of ``query`` are read from: None for a built-in profile, else the
    upload directory of ``sources`` (part of the cache keys: another store may lack the id).
    """
    def one(spec: str, kind: str) -> str | None:
        return None if spec == BUILTIN[kind] else str(sources.upload_dir)

    return one(query.wheel, "wheel"), one(query.rail, "rail")


@lru_cache(maxsize=8)
def _profile(spec: str, kind: str, upload_dir: str | None) -> Profile:
    """The built-in profile or the upload ``spec`` of ``kind`` (cached; an upload id names
    fixed content).

    Raises
    ------
    ScenarioError
        Located at ``("query", kind)``: no such upload, or a file that is not a ``kind``
        profile.
    """
    from flexride.contact.scenario_table import load_profile

    if upload_dir is None:
        src = ProfileSource(builtin=spec)
    else:
        src = ProfileSource(upload=spec)
    sources = MeasuredSources(upload_dir=None if upload_dir is None else Path(upload_dir),
                              allow_paths=False)
    try:
        return load_profile(src, kind, sources)
    except ScenarioError as err:
        msgs = [it.msg for it in err.items] or [str(err)]
        raise _at(kind, "; ".join(msgs)) from None


def _profiles(query: GeometryQuery, dirs: Dirs) -> tuple[Profile, Profile]:
    """The wheel and rail profiles of ``query``, read from ``dirs``."""
    return _profile(query.wheel, "wheel", dirs[0]), _profile(query.rail, "rail", dirs[1])


@lru_cache(maxsize=GEOMETRY_CACHE)
def _search(query: GeometryQuery, dirs: Dirs) -> ContactGeometry:
    """The rigid contact search of ``query`` (cached).

    Raises
    ------
    ScenarioError
        Located at the gauge and the flange-back distance (and the uploaded profiles) when
        the wheels do not rest on their rails within the profiles at Δy = 0, at ``y_max_mm``
        when they do but not over the whole grid.
    """
    wheel, rail = _profiles(query, dirs)
    placement = query.placement
    try:
        return search_contact(wheel, rail, placement, query.settings)
    except ScenarioError as err:
        centre = SearchSettings(y_max=1e-4, step=1e-4, roll=query.roll)
        try:
            search_contact(wheel, rail, placement, centre)
        except ScenarioError:
            uploaded = tuple(k for k, d in zip(("wheel", "rail"), dirs, strict=True) if d)
            raise _at_many((*uploaded, "gauge_mm", "flange_back_mm"), (
                f"the wheels do not rest on their rails at Δy = 0 ({wheel.name} on "
                f"{rail.name}; taping lines at ±{placement.taping_line * 1e3:g} mm, gauge "
                f"points at ±{placement.gauge * 500.0:g} mm): check "
                f"{'the profiles, ' if uploaded else ''}the gauge and the flange-back "
                "distance")) from None
        raise _at("y_max_mm", str(err)) from None


def _conicity(query: GeometryQuery, dirs: Dirs) -> tuple[list[dict[str, Any]], str | None]:
    """The equivalent conicity rows of ``query``'s profiles and placement (the CLI's grid
    and amplitudes), or no rows and the reason.
    """
    from flexride.contact.conicity import DEFAULT_AMPLITUDES, equivalent_conicity

    try:
        geo = _search(query.on_conicity_grid(), dirs)
        tan_ge = equivalent_conicity(geo.y, geo.delta_r, DEFAULT_AMPLITUDES)
    except ScenarioError as err:
        return [], f"no equivalent conicity on ±{CONICITY_Y_MAX_MM:g} mm: {err}"
    return conicity_rows(DEFAULT_AMPLITUDES, tan_ge), None


def _drawn(y: np.ndarray, z: np.ndarray, n_all: int) -> dict[str, Any]:
    """At most :data:`MAX_DRAWN_POINTS` of the points (y, z) in m as a profile line in mm."""
    step = max(1, -(-y.size // MAX_DRAWN_POINTS))
    idx = list(range(0, y.size, step))
    if idx[-1] != y.size - 1:
        idx[-1] = y.size - 1
    return {"y_mm": [round(float(y[i]) * 1e3, 4) for i in idx],
            "z_mm": [round(float(z[i]) * 1e3, 4) for i in idx], "points": n_all}


def _placed_rail(rail: Profile, query: GeometryQuery) -> dict[str, Any]:
    """The left rail in track coordinates (canted, gauge point at gauge/2, top at z = 0)."""
    placement = query.placement
    pr = place_rail(rail.curve(query.settings.smoothing_length), placement)
    c, s = math.cos(pr.alpha), math.sin(pr.alpha)
    eta = c * rail.y - s * rail.z + pr.eta_shift
    z = s * rail.y + c * rail.z + pr.z_shift
    return _drawn(eta, z, rail.y.size)


def _placed_wheel(wheel: Profile, geo: ContactGeometry) -> dict[str, Any]:
    """The left wheel at Δy = 0 in track coordinates: the profile (s, z) about the axle
    centre (taping line b0 out, r0 below), rotated by the roll and lifted.
    """
    i0 = geo.i0
    b0, r0 = geo.placement.taping_line, geo.placement.r0
    phi, lift = float(geo.roll[i0]), float(geo.lift[0, i0])
    c, s = math.cos(phi), math.sin(phi)
    py, pz = b0 + wheel.y, wheel.z - r0
    return _drawn(float(geo.y[i0]) + c * py - s * pz, r0 + lift + s * py + c * pz,
                  wheel.y.size)


def _profiles_out(wheel: Profile, rail: Profile, geo: ContactGeometry,
                  query: GeometryQuery) -> dict[str, Any]:
    """The ``profiles`` part of the answer."""
    i0, p = geo.i0, geo.placement
    return {
        "rail": _placed_rail(rail, query),
        "wheel": _placed_wheel(wheel, geo),
        "axle_y_mm": round(float(geo.y[i0]) * 1e3, 6),
        "axle_z_mm": round((p.r0 + float(geo.lift[0, i0])) * 1e3, 6),
        "roll_rad": round(float(geo.roll[i0]), 9),
        "taping_line_y_mm": round(p.taping_line * 1e3, 6),
        "gauge_point_y_mm": round(p.gauge * 500.0, 6),
        "gauge_point_z_mm": round(-p.gauge_height * 1e3, 6),
    }


def _other_branch(geo: ContactGeometry, name: str) -> np.ndarray:
    """Field ``name`` of the branch not carrying the rigid contact [2, n], NaN where absent."""
    other = (1 - geo.rigid)[:, None, :]
    values = np.take_along_axis(getattr(geo, name), other, axis=1)[:, 0, :]
    active = np.take_along_axis(geo.active, other, axis=1)[:, 0, :]
    return np.where(active, values, np.nan)


def _contacts(geo: ContactGeometry) -> list[dict[str, Any]]:
    """Axle heights and contact points per grid point, in track coordinates (mm)."""
    sg = np.array([[1.0], [-1.0]])
    y1, z1 = sg * geo.at_rigid("eta") * 1e3, geo.at_rigid("z_contact") * 1e3
    y2, z2 = sg * _other_branch(geo, "eta") * 1e3, _other_branch(geo, "z_contact") * 1e3
    axle = (geo.placement.r0 + geo.lift) * 1e3
    out = []
    for i in range(geo.n):
        out.append({
            "dy_mm": rounded(geo.y[i] * 1e3, 4),
            "axle_z_left_mm": rounded(axle[0, i], 5), "axle_z_right_mm": rounded(axle[1, i], 5),
            "left_y_mm": rounded(y1[0, i], 4), "left_z_mm": rounded(z1[0, i], 4),
            "right_y_mm": rounded(y1[1, i], 4), "right_z_mm": rounded(z1[1, i], 4),
            "left_second_y_mm": rounded(y2[0, i], 4), "left_second_z_mm": rounded(z2[0, i], 4),
            "right_second_y_mm": rounded(y2[1, i], 4),
            "right_second_z_mm": rounded(z2[1, i], 4),
        })
    return out


def _parameters(query: GeometryQuery, geo: ContactGeometry) -> dict[str, Any]:
    """The parameters of the answer (the half range as the grid has it)."""
    out = asdict(query)
    out["y_max_mm"] = round(geo.settings.y_max * 1e3, 6)
    return out


def geometry_content(query: GeometryQuery, sources: MeasuredSources) -> dict[str, Any]:
    """The answer of ``GET /contact/geometry`` for ``query`` (a JSON-able dict, fields of
    :class:`~flexride.api.schemas.ContactGeometryOut`).

    Parameters
    ----------
    query : GeometryQuery
        The request's parameters.
    sources : MeasuredSources
        Where uploaded profiles are read from (the service's upload store; never paths).

    Returns
    -------
    dict
        Parameters, profile names, the table's columns and rows, the contact points per row,
        the equivalent conicity and the placed profiles (mm, rad).

    Raises
    ------
    ScenarioError
        Located at the query parameter that makes the request impossible (422).
    """
    query.check()
    dirs = _dirs(query, sources)
    wheel, rail = _profiles(query, dirs)
    geo = _search(query, dirs)
    conicity, note = _conicity(query, dirs)
    return {
        "parameters": _parameters(query, geo),
        "wheel_name": wheel.name, "rail_name": rail.name,
        "columns": dict(TABLE_COLUMNS),
        "rows": table_rows(geo),
        "contacts": _contacts(geo),
        "conicity_method": "integration",
        "conicity": conicity,
        "conicity_note": note,
        "profiles": _profiles_out(wheel, rail, geo, query),
    }


def geometry_answer(request: Request, query: GeometryQuery,
                    sources: MeasuredSources) -> Response:
    """The HTTP answer of ``GET /contact/geometry``: rendered once per parameter set (and
    upload store) and kept, gzip-encoded when the request accepts it as the app's gzip
    middleware would.

    Parameters
    ----------
    request : fastapi.Request
        The request (its ``Accept-Encoding`` and the app's gzip settings decide the body).
    query : GeometryQuery
        The request's parameters.
    sources : MeasuredSources
        The service's upload store.

    Returns
    -------
    fastapi.Response
        JSON of :func:`geometry_content`.
    """
    gz = gzip_settings(request.app)
    gzip_min = None if gz is None else gz[0]
    key = (query, _dirs(query, sources), gzip_min)

    def make() -> tuple[Rendered, int]:
        r = render(geometry_content(query, sources), gzip_min)
        return r, r.nbytes

    rendered: Rendered = _ANSWERS.get_or_make(key, make)
    return rendered.response(accepts_gzip(request))

"""Contact tables of a real wheel/rail profile pair for the solver kernel, cached by content.

:func:`profile_contact_table` runs the rigid contact-point search
(:func:`flexride.contact.search.search_contact`), evaluates Hertz (ellipse factors and normal
constant) and Kalker's coefficients at every contact candidate and returns a
:class:`ProfileContactTable`. Tables are cached on disk under
``cache_root()/contact-<version>/`` keyed by a SHA-256 of the profiles' points and every
parameter.

Data layout for the kernel
--------------------------
:meth:`ProfileContactTable.as_arrays` returns ``params`` [:data:`POINT_PARAMS`] and ``data`` of
shape [2 sides, 2 slots, :data:`POINT_FIELDS`, n], C-contiguous, so ``data[side, slot, f]`` is a
contiguous row for :func:`flexride.contact.geometry.interp_uniform` on the grid
Δy_i = y0 + i·dy (the wheelset's lateral displacement relative to its rails, positive to the
left). Side 0 is the left wheel (sg = +1), side 1 the right (sg = −1); slot 0 is the tread
branch, slot 1 the flange branch (flange root and flange). The first ten fields are those of
:data:`flexride.contact.geometry.TABLE_FIELDS` with the same meaning and order, so the
kernel's ``CT_*`` indices apply to each slot unchanged:

``r``      rolling radius of the contact point, m
``gamma``  contact angle in the wheelset frame, rad, positive when the normal force on the wheel
           points toward the track centre; the track-frame angle is gamma + sg·φ (φ the
           wheelset roll dof)
``dz``     vertical approach offset, m: the contact's vertical compression is
           δ_z = (z_rail + z_irr) − (z_wheelset + sg·b0·φ) + dz, zero at the rigid configuration
           of the table (both wheels touching, kinematic roll) for the slot carrying the rigid
           contact, and −gap for the other slot (dz = rise − gap)
``yc``     lateral offset of the contact on the wheel from its taping line in the wheelset
           frame, m, positive to the left (sg·s with s the EN 13715 coordinate): the contact
           point is at (0, sg·b0 + yc, −r) from the axle centre
``ca, cb`` Hertz semi-axis factors, m/N^(1/3) (a = ca·N^(1/3) rolling, b = cb·N^(1/3) lateral)
``c11, c22, c23, c33`` Kalker's coefficients

and four more:

``gap``    vertical gap of the slot at the rigid configuration, m (0 for the rigid contact,
           :data:`GAP_NONE` where the branch has no contact candidate)
``gh``     normal contact constant G, m/N^(2/3): N = (δ_n/G)^(3/2) with the normal approach
           δ_n = δ_z·cos(gamma + sg·φ) (Hertz theory with the same curvatures by default)
``yr``     lateral position of the contact on the rail relative to the placed rail profile's
           origin (the crown top on the rail axis for the built-in 60E1), m, positive to the
           left
``zr``     height of the contact point above the top of rail, m (≤ 0)

Evaluating both slots, each with its own normal (gamma), radius, lever (yc, r), Hertz
constant and creep coefficients, and summing their forces gives the two-point contact; a slot
whose δ_z ≤ 0 carries nothing. Where a branch is absent its fields hold the nearest present
values along Δy (finite, for interpolation) and ``gap`` = :data:`GAP_NONE`, so δ_z stays
negative. The kinematic roll φ(Δy) of the table is :attr:`ProfileContactTable.roll`.

:meth:`ProfileContactTable.single_table` gives the classical one-point table (the rigid contact,
jumping to the flange when the flange carries it) as a :class:`ContactTable`, usable by the
current kernel as is; :meth:`ProfileContactTable.slot_table` gives one branch.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from flexride.contact.geometry import TABLE_FIELDS, ContactTable
from flexride.contact.hertz import hertz_constant, hertz_contact
from flexride.contact.kalker import kalker_from_axes
from flexride.contact.placement import Placement
from flexride.contact.profiles.profile import Profile
from flexride.contact.search import ContactGeometry, SearchSettings, search_contact
from flexride.errors import ScenarioError
from flexride.fileio import atomic_path, cache_root

__all__ = [
    "GAP_NONE",
    "POINT_FIELDS",
    "POINT_PARAMS",
    "NormalLaw",
    "ProfileContactTable",
    "contact_tables_from_geometry",
    "profile_contact_table",
    "shear_modulus_of",
]

#: Field order of :meth:`ProfileContactTable.as_arrays` (first ten = TABLE_FIELDS).
POINT_FIELDS = (*TABLE_FIELDS, "gap", "gh", "yr", "zr")
#: Scalar order of the parameter vector of :meth:`ProfileContactTable.as_arrays`.
POINT_PARAMS = ("y0", "dy", "r0", "b0", "gap_none", "shear_modulus")
#: Gap (m) stored where a branch has no contact candidate.
GAP_NONE = 0.05
#: Bump when the cached content or layout changes.
CACHE_SCHEMA = 1

NormalLaw = Literal["hertz", "zhai-worn", "zhai-conical"]
_F = {name: k for k, name in enumerate(POINT_FIELDS)}


def shear_modulus_of(E: float, nu: float) -> float:
    """Shear modulus G = E/(2(1 + ν)) in Pa of an isotropic material (E in Pa)."""
    return float(E) / (2.0 * (1.0 + float(nu)))


def _ro(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a, dtype=np.float64)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class ProfileContactTable:
    """Two-point contact table of a wheel/rail profile pair (layout in the module docstring).

    Attributes
    ----------
    y0, dy : float
        Grid start and step of Δy in m.
    data : numpy.ndarray
        [2 sides, 2 slots, len(POINT_FIELDS), n] float64, read-only.
    roll : numpy.ndarray
        Kinematic wheelset roll φ(Δy) in rad [n] (0 when searched without roll).
    rigid_slot : numpy.ndarray
        Slot carrying the rigid contact [2, n] (int).
    two_point : numpy.ndarray
        Both slots within the two-point tolerance [2, n] (bool).
    r0 : float
        Nominal rolling radius in m.
    b0 : float
        Lateral distance of the taping lines from the track centre in m (half distance between
        the nominal rolling circles).
    shear_modulus : float
        Shear modulus of wheel and rail for Kalker's creep coefficients in Pa.
    flange_onset : float
        Smallest |Δy| in m at which the flange branch carries the rigid contact on a wheel
        (the grid half-range when it never does).
    meta : dict
        Profiles, placement, settings, materials and normal law used (JSON-able).
    """

    y0: float
    dy: float
    data: np.ndarray
    roll: np.ndarray
    rigid_slot: np.ndarray
    two_point: np.ndarray
    r0: float
    b0: float
    shear_modulus: float
    flange_onset: float
    meta: dict[str, Any] = field(default_factory=dict)

    @property
    def n(self) -> int:
        """Number of grid points."""
        return int(self.data.shape[-1])

    @property
    def y_grid(self) -> np.ndarray:
        """Δy grid in m [n]."""
        return self.y0 + self.dy * np.arange(self.n)

    def field(self, name: str) -> np.ndarray:
        """Field ``name`` of :data:`POINT_FIELDS` as [2 sides, 2 slots, n]."""
        if name not in _F:
            raise KeyError(f"unknown contact table field {name!r}; fields: {POINT_FIELDS}")
        return self.data[:, :, _F[name], :]

    def rigid_delta_r(self) -> np.ndarray:
        """Rolling-radius difference r_left − r_right of the rigid contacts [n] in m (the
        input of :func:`flexride.contact.conicity.equivalent_conicity` on :attr:`y_grid`).
        """
        r = self.field("r")
        idx = self.rigid_slot[:, None, :].astype(np.intp)
        rigid = np.take_along_axis(r, idx, axis=1)[:, 0, :]
        return rigid[0] - rigid[1]

    def flange_angle(self, touching: float = 1e-4) -> float:
        """Largest contact angle (rad) of the flange branch where it carries the rigid contact
        (gap below ``touching``, m), over both sides: the flange angle that Nadal's
        derailment limit uses (70° for S1002).
        """
        gamma, gap = self.field("gamma")[:, 1, :], self.field("gap")[:, 1, :]
        in_contact = gap < touching
        if not in_contact.any():
            return float(np.max(np.abs(gamma)))
        return float(np.max(np.abs(gamma[in_contact])))

    def as_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """Flat float64 arrays for the numba kernel.

        Returns
        -------
        params : numpy.ndarray
            [6]: y0 m, dy m, r0 m, b0 m, gap_none m, shear_modulus Pa (:data:`POINT_PARAMS`).
        data : numpy.ndarray
            [2, 2, len(POINT_FIELDS), n], C-contiguous (a read-only view of :attr:`data`).
        """
        params = np.array([self.y0, self.dy, self.r0, self.b0, GAP_NONE, self.shear_modulus])
        return params, self.data

    def _table(self, values: np.ndarray) -> ContactTable:
        kw = {name: values[:, _F[name], :] for name in TABLE_FIELDS}
        return ContactTable(y0=self.y0, dy=self.dy, r0=self.r0, b0=self.b0,
                            flange_clearance=self.flange_onset, flange_stiffness=0.0, **kw)

    def slot_table(self, slot: int) -> ContactTable:
        """One branch (0 tread, 1 flange) as a :class:`ContactTable` (dz includes −gap)."""
        if slot not in (0, 1):
            raise ValueError(f"slot must be 0 (tread) or 1 (flange), got {slot!r}")
        return self._table(self.data[:, slot])

    def single_table(self) -> ContactTable:
        """The rigid contact point per wheel as a one-point :class:`ContactTable`.

        It jumps from the tread to the flange where the flange branch takes over; its
        ``flange_stiffness`` is 0 and ``flange_clearance`` the flange onset: the flange is part
        of the geometry, not a separate spring.
        """
        idx = self.rigid_slot[:, None, None, :]
        values = np.take_along_axis(self.data, np.broadcast_to(
            idx, (2, 1, self.data.shape[2], self.n)), axis=1)[:, 0]
        return self._table(values)


def _kernel_fields(geo: ContactGeometry, E: float, nu: float, normal: NormalLaw,
                   max_curvature_ratio: float) -> tuple[np.ndarray, int]:
    """Fill [2, 2, F, n] from a search result; returns the data and the number of clamped
    curvature ratios.
    """
    n = geo.n
    data = np.empty((2, 2, len(POINT_FIELDS), n))
    rise = geo.rise()
    clamped = 0
    for side in range(2):
        sg = 1.0 if side == 0 else -1.0
        for slot in range(2):
            act = geo.active[side, slot]
            src = slot if geo.active[side, slot].any() else 1 - slot
            r = geo.r[side, src]
            gam = geo.gamma[side, src]
            a_curv = 0.5 * geo.k_wheel_rolling[side, src]
            b_curv = 0.5 * (geo.k_wheel[side, src] + geo.k_rail[side, src])
            lo = a_curv / max_curvature_ratio
            hi = a_curv * max_curvature_ratio
            clamped += int(np.count_nonzero(((b_curv < lo) | (b_curv > hi)) & act))
            b_curv = np.clip(b_curv, lo, hi)
            ca = np.empty(n)
            cb = np.empty(n)
            gh = np.empty(n)
            cij = np.empty((4, n))
            cache: dict[tuple[float, float], tuple[float, float, float]] = {}
            for i in range(n):
                key = (float(a_curv[i]), float(b_curv[i]))
                hit = cache.get(key)
                if hit is None:
                    hit = hertz_contact(key[0], key[1], E, nu)
                    cache[key] = hit
                ca[i], cb[i], gh[i] = hit
                cij[:, i] = kalker_from_axes(ca[i], cb[i], nu)
            if normal != "hertz":
                tread: Literal["worn", "conical"] = "worn" if normal == "zhai-worn" else "conical"
                gh = np.array([hertz_constant(float(ri), tread) for ri in r])
            gap = np.where(act, geo.gap[side, slot], GAP_NONE)
            out = data[side, slot]
            out[_F["r"]] = r
            out[_F["gamma"]] = gam
            out[_F["dz"]] = rise[side] - gap
            out[_F["yc"]] = sg * geo.s[side, src]
            out[_F["ca"]] = ca
            out[_F["cb"]] = cb
            out[_F["c11"]], out[_F["c22"]], out[_F["c23"]], out[_F["c33"]] = cij
            out[_F["gap"]] = gap
            out[_F["gh"]] = gh
            out[_F["yr"]] = sg * (geo.eta[side, src] - geo.rail_origin[side, 0])
            out[_F["zr"]] = geo.z_contact[side, src]
    if not np.all(np.isfinite(data)):
        raise ScenarioError("contact table: non-finite values (no contact found on a wheel)")
    return data, clamped


def contact_tables_from_geometry(
    geo: ContactGeometry,
    E: float = 2.1e11,
    nu: float = 0.28,
    shear_modulus: float | None = None,
    normal: NormalLaw = "hertz",
    max_curvature_ratio: float = 1000.0,
) -> ProfileContactTable:
    """Build the kernel table from a contact-point search result.

    Parameters
    ----------
    geo : ContactGeometry
        Result of :func:`~flexride.contact.search.search_contact`.
    E : float
        Young's modulus of wheel and rail steel in Pa.
    nu : float
        Poisson's ratio.
    shear_modulus : float, optional
        Shear modulus for the creep forces in Pa; default E/(2(1 + ν)).
    normal : {"hertz", "zhai-worn", "zhai-conical"}
        Normal contact constant: Hertz theory with the contact's curvatures (default) or Zhai's
        empirical constants (3.86·R^−0.115·1e−8, 4.57·R^−0.149·1e−8 with R the rolling radius).
    max_curvature_ratio : float
        The lateral relative curvature B is clipped to [A/ratio, A·ratio] (A the rolling one)
        where the profiles are nearly conformal (Hertz does not apply there; the count of
        clipped contacts is in ``meta["clamped_curvatures"]``).

    Returns
    -------
    ProfileContactTable
    """
    for name, value in (("Young's modulus E (Pa)", E),
                        ("max_curvature_ratio", max_curvature_ratio)):
        if not (math.isfinite(float(value)) and float(value) > 1.0):
            raise ScenarioError(f"{name} must be a finite number > 1, got {value!r}")
    if not (math.isfinite(float(nu)) and 0.0 <= float(nu) <= 0.5):
        raise ScenarioError(f"Poisson's ratio nu must lie in [0, 0.5], got {nu!r}")
    if normal not in ("hertz", "zhai-worn", "zhai-conical"):
        raise ScenarioError(f"normal law must be hertz, zhai-worn or zhai-conical, got {normal!r}")
    g_shear = shear_modulus_of(E, nu) if shear_modulus is None else float(shear_modulus)
    if not (math.isfinite(g_shear) and g_shear > 0.0):
        raise ScenarioError(f"shear modulus (Pa) must be positive, got {shear_modulus!r}")
    data, clamped = _kernel_fields(geo, float(E), float(nu), normal, float(max_curvature_ratio))
    flange = geo.rigid == 1
    onset = float(geo.settings.y_max)
    if flange.any():
        onset = float(np.min(np.abs(np.broadcast_to(geo.y, flange.shape)[flange])))
    st = geo.settings
    meta = {
        "wheel": list(geo.wheel_names),
        "rail": list(geo.rail_names),
        "placement": geo.placement.as_dict(),
        "settings": {"y_max": st.y_max, "step": st.step, "sampling": st.sampling,
                     "roll": st.roll, "flange_angle": st.flange_angle,
                     "two_point_tolerance": st.two_point_tolerance,
                     "smoothing_length": st.smoothing_length},
        "E": float(E),
        "nu": float(nu),
        "normal": normal,
        "max_curvature_ratio": float(max_curvature_ratio),
        "clamped_curvatures": clamped,
    }
    return ProfileContactTable(
        y0=float(geo.y[0]),
        dy=float(st.step),
        data=_ro(data),
        roll=_ro(geo.roll),
        rigid_slot=_ro_int(geo.rigid),
        two_point=_ro_bool(geo.two_point),
        r0=geo.placement.r0,
        b0=geo.placement.taping_line,
        shear_modulus=g_shear,
        flange_onset=onset,
        meta=meta,
    )


def _ro_int(a: np.ndarray) -> np.ndarray:
    out = np.ascontiguousarray(a, dtype=np.int64)
    out.flags.writeable = False
    return out


def _ro_bool(a: np.ndarray) -> np.ndarray:
    out = np.ascontiguousarray(a, dtype=bool)
    out.flags.writeable = False
    return out


# --- cache -----------------------------------------------------------------------------------

def _version() -> str:
    from flexride import __version__

    return __version__


def cache_dir() -> Any:
    """Directory of cached contact tables (created on first write)."""
    return cache_root() / f"contact-{_version()}"


def _key(wheels: tuple[Profile, Profile], rails: tuple[Profile, Profile], payload: dict) -> str:
    body = {
        "wheels": [w.digest() for w in wheels],
        "rails": [r.digest() for r in rails],
        "params": payload,
        "schema": CACHE_SCHEMA,
        "flexride": _version(),
        "numpy_major": np.__version__.split(".")[0],
    }
    text = json.dumps(body, sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:32]


def _load(key: str) -> ProfileContactTable | None:
    d = cache_dir()
    npz, meta_path = d / f"{key}.npz", d / f"{key}.json"
    if not (npz.is_file() and meta_path.is_file()):
        return None
    try:
        info = json.loads(meta_path.read_text(encoding="utf-8"))
        with np.load(npz, allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
        return ProfileContactTable(
            y0=float(info["y0"]), dy=float(info["dy"]), data=_ro(arrays["data"]),
            roll=_ro(arrays["roll"]), rigid_slot=_ro_int(arrays["rigid_slot"]),
            two_point=_ro_bool(arrays["two_point"]), r0=float(info["r0"]),
            b0=float(info["b0"]), shear_modulus=float(info["shear_modulus"]),
            flange_onset=float(info["flange_onset"]), meta=dict(info["meta"]),
        )
    except (OSError, ValueError, KeyError, TypeError, json.JSONDecodeError):
        return None


def _store(key: str, table: ProfileContactTable) -> None:
    d = cache_dir()
    info = {"y0": table.y0, "dy": table.dy, "r0": table.r0, "b0": table.b0,
            "shear_modulus": table.shear_modulus, "flange_onset": table.flange_onset,
            "meta": table.meta}
    try:
        with atomic_path(d / f"{key}.npz") as tmp, open(tmp, "wb") as fh:
            np.savez(fh, allow_pickle=False, data=np.asarray(table.data),
                     roll=np.asarray(table.roll), rigid_slot=np.asarray(table.rigid_slot),
                     two_point=np.asarray(table.two_point))
        with atomic_path(d / f"{key}.json") as tmp:
            tmp.write_text(json.dumps(info), encoding="utf-8")
    except OSError:
        return  # a read-only cache only costs the rebuild next time


def profile_contact_table(
    wheel: Profile | tuple[Profile, Profile],
    rail: Profile | tuple[Profile, Profile],
    placement: Placement | None = None,
    settings: SearchSettings | None = None,
    *,
    E: float = 2.1e11,
    nu: float = 0.28,
    shear_modulus: float | None = None,
    normal: NormalLaw = "hertz",
    max_curvature_ratio: float = 1000.0,
    use_cache: bool = True,
) -> ProfileContactTable:
    """Search the contact points of a profile pair and build its kernel table (cached).

    Parameters
    ----------
    wheel, rail : Profile or (Profile, Profile)
        Profiles of both sides, or (left, right) pairs.
    placement : Placement, optional
        Inclination, gauge, gauge height, flange-back distance, r0.
    settings : SearchSettings, optional
        Grid (default ±12 mm, 0.05 mm step), sampling, roll, branch split, tolerance.
    E, nu, shear_modulus, normal, max_curvature_ratio
        As for :func:`contact_tables_from_geometry`.
    use_cache : bool
        Read and write the on-disk cache (content hash of the profiles' points and all
        parameters).

    Returns
    -------
    ProfileContactTable
    """
    placement = placement or Placement()
    settings = settings or SearchSettings()
    wheels = wheel if isinstance(wheel, tuple) else (wheel, wheel)
    rails = rail if isinstance(rail, tuple) else (rail, rail)
    payload = {
        "placement": placement.as_dict(),
        "settings": [settings.y_max, settings.step, settings.sampling, settings.roll,
                     settings.flange_angle, settings.two_point_tolerance,
                     settings.smoothing_length],
        "E": float(E), "nu": float(nu),
        "shear_modulus": None if shear_modulus is None else float(shear_modulus),
        "normal": normal, "max_curvature_ratio": float(max_curvature_ratio),
        "names": [p.name for p in (*wheels, *rails)],
    }
    key = _key(wheels, rails, payload) if use_cache else ""
    if use_cache:
        hit = _load(key)
        if hit is not None:
            return hit
    geo = search_contact(wheels, rails, placement, settings)
    table = contact_tables_from_geometry(geo, E, nu, shear_modulus, normal, max_curvature_ratio)
    if use_cache:
        _store(key, table)
    return table

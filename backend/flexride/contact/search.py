"""Rigid contact-point search of a wheelset on its two rails against the lateral displacement.

For each lateral displacement Δy of the wheelset relative to the track centre line (m, project
axes: positive to the left) the wheelset is lowered onto the rigid rails until both wheels touch:
its vertical position z and, with ``roll=True``, its roll angle φ follow from the two contact
conditions (min gap = 0 on each side). The wheel profiles are rotated exactly with the wheelset
(about the axle centre, which lies r0 above the taping-line circle's lowest point), so the roll
moves the contact laterally by about r0·φ as well as vertically.

Per side the vertical gap g(η) between wheel and rail is evaluated on the wheel's sampling
points; its discrete local minima, refined by a parabola, are the contact candidates. They fall
into two *branches* by the wheel's slope angle at the candidate: the tread branch (slot 0, angle
below ``flange_angle``) and the flange branch (slot 1: flange root and flange). Each branch keeps
its lowest candidate; the branch with the smaller gap carries the rigid contact (gap 0), the
other one has the gap that remains at the rigid configuration (≥ 0), or is absent when the gap
has no local minimum in that branch. A *two-point contact* is a position where both branches
are within ``two_point_tolerance``. Contact-point jumps (e.g. S1002 on 60E1 at 1:40 near
Δy = 0 within the tread branch, and from tread to flange root near 5.5 mm) appear as jumps
between neighbouring grid points; nothing is smoothed.

Geometry per side is computed in the side frame of :mod:`flexride.contact.placement` (η outward
from the track centre, z up from the top of rail); the left side is sign sg = +1, the right side
sg = −1: a wheelset displacement Δy shifts the wheel by sg·Δy in η and the roll φ rotates it by
sg·φ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np

from flexride._numba_env import FASTMATH
from flexride.contact.placement import PlacedRail, Placement, place_rail
from flexride.contact.profiles.profile import Profile, SampledProfile
from flexride.errors import ScenarioError

__all__ = ["SIDES", "SLOTS", "ContactGeometry", "SearchSettings", "search_contact"]

#: Side order of every [2, …] array: 0 left (sg = +1), 1 right (sg = −1).
SIDES = ("left", "right")
#: Slot order of every [.., 2, ..] slot axis: 0 tread branch, 1 flange branch.
SLOTS = ("tread", "flange")

_FM = set(FASTMATH)
_ROLL_BRACKET = 0.05  # rad
_NO_OVERLAP = 1.0e30


@dataclass(frozen=True)
class SearchSettings:
    """Resolution and classification settings of :func:`search_contact` (SI units).

    Attributes
    ----------
    y_max : float
        Half range of the Δy grid in m (default 12 mm); rounded to a multiple of ``step``.
    step : float
        Δy grid step in m (default 0.05 mm).
    sampling : float
        Lateral sampling step of the profiles in m (default 0.02 mm).
    roll : bool
        Solve the wheelset roll from the condition that both wheels touch (default); False
        keeps φ = 0 and lowers each wheel onto its rail separately.
    flange_angle : float
        Wheel slope angle in rad separating the tread branch from the flange branch
        (default 0.2 rad ≈ 11.5°; S1002 reaches it at s ≈ −23 mm, between the largest tread
        contact angle, ≈ 7.5°, and the flange-root contacts, ≥ 16°).
    two_point_tolerance : float
        Gap in m below which the second branch counts as a second contact point (default
        0.1 mm, the order of the Hertz approach at 50 kN).
    smoothing_length : float
        Smoothing length of the profile splines in m (0 interpolates the points).
    """

    y_max: float = 0.012
    step: float = 5.0e-5
    sampling: float = 2.0e-5
    roll: bool = True
    flange_angle: float = 0.2
    two_point_tolerance: float = 1.0e-4
    smoothing_length: float = 0.0

    def __post_init__(self) -> None:
        """Check the search range and step."""
        checks = (
            ("y_max (m)", self.y_max, 1e-4, 0.05),
            ("step (m)", self.step, 1e-6, 1e-3),
            ("sampling (m)", self.sampling, 1e-6, 2e-4),
            ("flange_angle (rad)", self.flange_angle, 0.02, 1.2),
            ("two_point_tolerance (m)", self.two_point_tolerance, 0.0, 5e-3),
            ("smoothing_length (m)", self.smoothing_length, 0.0, 0.05),
        )
        for name, value, lo, hi in checks:
            v = float(value)
            if not (math.isfinite(v) and lo <= v <= hi):
                raise ScenarioError(f"contact search {name} must lie in [{lo:g}, {hi:g}], got "
                                    f"{value!r}")
        n_half = round(float(self.y_max) / float(self.step))
        if n_half < 1 or n_half > 20000:
            raise ScenarioError("contact search: y_max/step must be between 1 and 20000")
        object.__setattr__(self, "y_max", n_half * float(self.step))

    @property
    def grid(self) -> np.ndarray:
        """Δy grid in m (odd length, symmetric, contains 0)."""
        n_half = round(self.y_max / self.step)
        return self.step * np.arange(-n_half, n_half + 1)


# --- compiled core ---------------------------------------------------------------------------

@numba.njit(cache=True, fastmath=_FM)
def _gaps(zw, s0, hw, zr, e0, he, bw, r0, shift, theta, lift, g, eta):
    """Vertical gap at every wheel sampling point (NaN off the rail); returns (gmin, kmin)."""
    c = math.cos(theta)
    sn = math.sin(theta)
    nw = zw.shape[0]
    nr = zr.shape[0]
    # wheel points that can reach the rail: η = shift + c·py − sn·pz with pz ∈ [zmin, zmax] − r0
    zlo = zw[0]
    zhi = zw[0]
    for k in range(nw):
        if zw[k] < zlo:
            zlo = zw[k]
        elif zw[k] > zhi:
            zhi = zw[k]
    a = sn * (zlo - r0)
    b = sn * (zhi - r0)
    lo = (e0 - shift + min(a, b)) / c
    hi = (e0 + (nr - 1) * he - shift + max(a, b)) / c
    k_lo = max(0, int(math.floor((lo - bw - s0) / hw)) - 2)  # noqa: RUF046 (numba)
    k_hi = min(nw, int(math.ceil((hi - bw - s0) / hw)) + 3)  # noqa: RUF046
    for k in range(0, min(k_lo, nw)):
        g[k] = math.nan
        eta[k] = math.nan
    for k in range(max(k_hi, 0), nw):
        g[k] = math.nan
        eta[k] = math.nan
    gmin = _NO_OVERLAP
    kmin = -1
    inv_he = 1.0 / he
    for k in range(k_lo, k_hi):
        py = bw + s0 + k * hw
        pz = zw[k] - r0
        e = shift + c * py - sn * pz
        eta[k] = e
        t = (e - e0) * inv_he
        if not (t >= 0.0 and t <= nr - 1):
            g[k] = math.nan
            continue
        i = int(t)
        if i >= nr - 1:
            i = nr - 2
        f = t - i
        gv = r0 + lift + sn * py + c * pz - (zr[i] + f * (zr[i + 1] - zr[i]))
        g[k] = gv
        if gv < gmin:
            gmin = gv
            kmin = k
    return gmin, kmin


@numba.njit(cache=True, fastmath=_FM)
def _dgap(zw, s0, hw, zr, e0, he, bw, r0, shift, theta, k, eta):
    """d(gap)/dθ at wheel point k for a rotation θ about the axle centre."""
    c = math.cos(theta)
    sn = math.sin(theta)
    py = bw + s0 + k * hw
    pz = zw[k] - r0
    zrel = sn * py + c * pz
    t = (eta - e0) / he
    i = min(max(int(t), 0), zr.shape[0] - 2)
    slope = (zr[i + 1] - zr[i]) / he
    return (eta - shift) + slope * zrel


@numba.njit(cache=True, fastmath=_FM)
def _solve_roll(zwL, s0L, hwL, zrL, e0L, heL, zwR, s0R, hwR, zrR, e0R, heR, bw, r0, dy,
                phi0, gL, etaL, gR, etaR):
    """Roll φ with equal minimum gaps on both sides (monotone in φ: bracketed Newton)."""
    lo = -_ROLL_BRACKET
    hi = _ROLL_BRACKET
    phi = phi0
    gmL = 0.0
    for _ in range(200):
        gmL, kL = _gaps(zwL, s0L, hwL, zrL, e0L, heL, bw, r0, dy, phi, 0.0, gL, etaL)
        gmR, kR = _gaps(zwR, s0R, hwR, zrR, e0R, heR, bw, r0, -dy, -phi, 0.0, gR, etaR)
        if kL < 0 or kR < 0:
            return math.nan, math.nan
        f = gmL - gmR
        if abs(f) < 1e-13 or hi - lo < 1e-14:
            break
        if f > 0.0:
            hi = phi
        else:
            lo = phi
        # d(gap)/dφ per side: lateral lever of the contact about the axle centre, plus the
        # rail slope times the lateral motion of the contact point (≈ r0·dθ)
        fp = (_dgap(zwL, s0L, hwL, zrL, e0L, heL, bw, r0, dy, phi, kL, etaL[kL])
              + _dgap(zwR, s0R, hwR, zrR, e0R, heR, bw, r0, -dy, -phi, kR, etaR[kR]))
        new = phi - f / fp if fp > 0.0 else 0.5 * (lo + hi)
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
        phi = new
    return phi, -gmL


@numba.njit(cache=True, fastmath=_FM)
def _candidates(g, eta, angw, flange_angle, out):
    """Best candidate per branch from the local minima of g.

    out[slot] = (found, gap, k + t, eta) ; out[2, 0] = 1 when the overall minimum lies at the
    edge of the overlap (the profiles do not cover the contact).
    """
    n = g.shape[0]
    for slot in range(2):
        out[slot, 0] = 0.0
        out[slot, 1] = math.inf
    out[2, 0] = 0.0
    # overall minimum and the valid range
    first = -1
    last = -1
    gbest = math.inf
    kbest = -1
    for k in range(n):
        if g[k] == g[k]:
            if first < 0:
                first = k
            last = k
            if g[k] < gbest:
                gbest = g[k]
                kbest = k
    if kbest < 0:
        out[2, 0] = 1.0
        return
    if kbest == first or kbest == last:
        out[2, 0] = 1.0
    for k in range(first + 1, last):
        a = g[k - 1]
        b = g[k]
        c = g[k + 1]
        if not (b <= a and b < c):
            continue
        den = a - 2.0 * b + c
        t = 0.5 * (a - c) / den if den > 0.0 else 0.0
        if t > 0.5:
            t = 0.5
        elif t < -0.5:
            t = -0.5
        gap = b - 0.25 * (a - c) * t
        kk = k + t
        i = int(math.floor(kk))  # noqa: RUF046 (numba)
        f = kk - i
        ang = angw[i] + f * (angw[i + 1] - angw[i])
        slot = 1 if ang >= flange_angle else 0
        if gap < out[slot, 1]:
            out[slot, 0] = 1.0
            out[slot, 1] = gap
            out[slot, 2] = kk
            out[slot, 3] = eta[i] + f * (eta[i + 1] - eta[i])


@numba.njit(cache=True, fastmath=_FM, nogil=True)  # other API threads run while it searches
def _search(dys, roll, zwL, s0L, hwL, awL, zrL, e0L, heL, zwR, s0R, hwR, awR, zrR, e0R, heR,
            bw, r0, flange_angle, res_phi, res_lift, res_slot, res_edge):
    """Solve every Δy; res_slot[side, slot, i, 0:4] = (found, gap, k, eta)."""
    n = dys.shape[0]
    gL = np.empty(zwL.shape[0])
    etaL = np.empty(zwL.shape[0])
    gR = np.empty(zwR.shape[0])
    etaR = np.empty(zwR.shape[0])
    cand = np.empty((3, 4))
    i0 = n // 2
    order = np.empty(n, dtype=np.int64)
    m = 0
    for i in range(i0, n):
        order[m] = i
        m += 1
    for i in range(i0 - 1, -1, -1):
        order[m] = i
        m += 1
    phi_prev = 0.0
    for j in range(n):
        i = order[j]
        if i == i0 - 1:
            phi_prev = res_phi[i0]
        dy = dys[i]
        if roll:
            phi, lift = _solve_roll(zwL, s0L, hwL, zrL, e0L, heL, zwR, s0R, hwR, zrR, e0R, heR,
                                    bw, r0, dy, phi_prev, gL, etaL, gR, etaR)
            if phi != phi:
                res_edge[i] = 1
                continue
            liftL = lift
            liftR = lift
        else:
            phi = 0.0
            gmL, kL = _gaps(zwL, s0L, hwL, zrL, e0L, heL, bw, r0, dy, 0.0, 0.0, gL, etaL)
            gmR, kR = _gaps(zwR, s0R, hwR, zrR, e0R, heR, bw, r0, -dy, 0.0, 0.0, gR, etaR)
            if kL < 0 or kR < 0:
                res_edge[i] = 1
                continue
            liftL = -gmL
            liftR = -gmR
        phi_prev = phi
        res_phi[i] = phi
        res_lift[0, i] = liftL
        res_lift[1, i] = liftR
        for side in range(2):
            if side == 0:
                _gaps(zwL, s0L, hwL, zrL, e0L, heL, bw, r0, dy, phi, liftL, gL, etaL)
                _candidates(gL, etaL, awL, flange_angle, cand)
            else:
                _gaps(zwR, s0R, hwR, zrR, e0R, heR, bw, r0, -dy, -phi, liftR, gR, etaR)
                _candidates(gR, etaR, awR, flange_angle, cand)
            if cand[2, 0] > 0.0:
                res_edge[i] = 1
            for slot in range(2):
                for q in range(4):
                    res_slot[side, slot, i, q] = cand[slot, q]


# --- result ----------------------------------------------------------------------------------

def _ro(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.flags.writeable = False
    return a


@dataclass(frozen=True, eq=False)
class ContactGeometry:
    """Result of :func:`search_contact` (all lengths in m, angles in rad).

    Arrays indexed ``[side, slot, i]`` have side 0 left / 1 right (:data:`SIDES`), slot 0 tread
    branch / 1 flange branch (:data:`SLOTS`) and i the Δy grid index. Where a branch has no
    candidate (``active`` False) its entries hold the nearest active value along Δy (or NaN if
    the branch never occurs) and ``gap`` is +inf.

    Attributes
    ----------
    y : numpy.ndarray
        Δy grid [n], wheelset displacement to the left relative to the track centre line.
    roll : numpy.ndarray
        Wheelset roll φ [n] at the rigid configuration (right-handed about x, positive raises
        the left wheel); 0 with ``roll=False``.
    lift : numpy.ndarray
        Vertical position [2, n] of the axle centre above its nominal height (r0 above the top
        of rail) at which each wheel touches; both rows equal with ``roll=True``.
    active, gap : numpy.ndarray
        Branch present [2, 2, n] (bool) and its vertical gap at the rigid configuration
        (0 for the branch carrying the rigid contact, +inf when absent).
    s : numpy.ndarray
        Contact position on the wheel profile [2, 2, n] (profile y = EN 13715 s, m).
    eta : numpy.ndarray
        Lateral position of the contact from the track centre line, outward, [2, 2, n].
    rail_y, rail_z : numpy.ndarray
        Contact position on the rail profile (un-rotated profile coordinates) [2, 2, n].
    z_contact : numpy.ndarray
        Height of the contact point on the rail above the top of rail [2, 2, n].
    r : numpy.ndarray
        Rolling radius r0 − z_wheel(s) [2, 2, n].
    gamma : numpy.ndarray
        Contact angle in the wheelset frame [2, 2, n]: the wheel profile's slope angle at the
        contact, positive when the normal force on the wheel points toward the track centre.
        In the track frame it is gamma + sg·roll.
    gamma_rail : numpy.ndarray
        Slope angle of the placed rail at the contact, in the track frame [2, 2, n] (equals
        gamma + sg·roll up to the sampling resolution for the rigid contact).
    k_wheel, k_rail : numpy.ndarray
        Lateral principal curvatures [2, 2, n] in 1/m, positive for a convex surface (the
        material bulges toward the other body): the wheel tread of S1002 is slightly concave,
        the rail crown convex (1/0.3 m on 60E1).
    rigid : numpy.ndarray
        Slot carrying the rigid contact [2, n] (int).
    two_point : numpy.ndarray
        Both branches within the two-point tolerance [2, n] (bool).
    placement : Placement
        Placement parameters used.
    settings : SearchSettings
        Resolution and classification settings used.
    wheel_names, rail_names : tuple of str
        Source names of the left and right profiles.
    """

    y: np.ndarray
    roll: np.ndarray
    lift: np.ndarray
    active: np.ndarray
    gap: np.ndarray
    s: np.ndarray
    eta: np.ndarray
    rail_y: np.ndarray
    rail_z: np.ndarray
    z_contact: np.ndarray
    r: np.ndarray
    gamma: np.ndarray
    gamma_rail: np.ndarray
    k_wheel: np.ndarray
    k_rail: np.ndarray
    rigid: np.ndarray
    two_point: np.ndarray
    placement: Placement
    settings: SearchSettings
    wheel_names: tuple[str, str]
    rail_names: tuple[str, str]
    rail_origin: np.ndarray = field(repr=False, default_factory=lambda: np.zeros((2, 2)))

    @property
    def n(self) -> int:
        """Number of grid points."""
        return int(self.y.size)

    @property
    def i0(self) -> int:
        """Grid index of Δy = 0."""
        return self.n // 2

    def at_rigid(self, name: str) -> np.ndarray:
        """Field ``name`` of the rigid contact per side, shape [2, n]."""
        arr = getattr(self, name)
        idx = self.rigid[:, None, :]
        return np.take_along_axis(arr, idx, axis=1)[:, 0, :]

    @property
    def k_wheel_rolling(self) -> np.ndarray:
        """Principal curvature of the wheel in the rolling direction [2, 2, n] in 1/m:
        cos(gamma)/r (Meusnier: the circumferential normal curvature of a surface of revolution
        whose normal is tilted by the contact angle from the radius); the straight rail has 0.
        """
        return np.cos(self.gamma) / self.r

    @property
    def delta_r(self) -> np.ndarray:
        """Rolling-radius difference r_left − r_right of the rigid contacts [n] in m."""
        r = self.at_rigid("r")
        return r[0] - r[1]

    @property
    def gamma_track(self) -> np.ndarray:
        """Contact angles of the rigid contacts in the track frame [2, n] in rad."""
        g = self.at_rigid("gamma")
        return g + np.array([[1.0], [-1.0]]) * self.roll[None, :]

    def rise(self) -> np.ndarray:
        """Vertical rise of each wheel at its nominal rolling circle [2, n] in m, relative to
        Δy = 0: lift + sg·b0·roll − (the same at Δy = 0), with b0 the taping-line η.
        """
        b0 = self.placement.taping_line
        sg = np.array([[1.0], [-1.0]])
        z = self.lift + sg * b0 * self.roll[None, :]
        return z - z[:, self.i0 : self.i0 + 1]


def _fill_inactive(values: np.ndarray, active: np.ndarray) -> np.ndarray:
    """Hold the nearest active value along the last axis where inactive (NaN if none)."""
    out = np.array(values, dtype=np.float64)
    n = out.shape[-1]
    idx = np.arange(n)
    for side in range(out.shape[0]):
        for slot in range(out.shape[1]):
            a = active[side, slot]
            if a.all():
                continue
            if not a.any():
                out[side, slot] = np.nan
                continue
            good = idx[a]
            pos = np.searchsorted(good, idx).clip(0, good.size - 1)
            left = good[np.maximum(pos - 1, 0)]
            right = good[pos]
            nearest = np.where(np.abs(idx - left) <= np.abs(right - idx), left, right)
            out[side, slot] = np.where(a, out[side, slot], out[side, slot][nearest])
    return out


def _as_pair(p: Profile | tuple[Profile, Profile], kind: str) -> tuple[Profile, Profile]:
    pair = p if isinstance(p, tuple) else (p, p)
    if len(pair) != 2:
        raise ScenarioError(f"give one {kind} profile or a (left, right) pair")
    for q in pair:
        if not isinstance(q, Profile) or q.kind != kind:
            raise ScenarioError(f"expected a {kind} profile, got {getattr(q, 'kind', q)!r}")
    return pair[0], pair[1]


def _sampled_profiles(
    wheels: tuple[Profile, Profile],
    rails: tuple[Profile, Profile],
    placement: Placement,
    settings: SearchSettings,
) -> tuple[list[SampledProfile], list[PlacedRail], list[SampledProfile]]:
    """Wheel profiles, placed rails and placed rail profiles of both sides (left, right),
    smoothed over ``settings.smoothing_length`` and sampled every ``settings.sampling`` (m); a
    profile given for both sides is sampled once.
    """
    h = settings.sampling
    ell = settings.smoothing_length
    wsamp: list[SampledProfile] = []
    placed: list[PlacedRail] = []
    rsamp: list[SampledProfile] = []
    w_cache: dict[int, SampledProfile] = {}
    r_cache: dict[int, tuple[PlacedRail, SampledProfile]] = {}
    for side in range(2):
        wp, rp = wheels[side], rails[side]
        if id(wp) not in w_cache:
            w_cache[id(wp)] = wp.curve(ell).sample(h)
        if id(rp) not in r_cache:
            pr = place_rail(rp.curve(ell), placement)
            r_cache[id(rp)] = (pr, pr.sample(h))
        wsamp.append(w_cache[id(wp)])
        placed.append(r_cache[id(rp)][0])
        rsamp.append(r_cache[id(rp)][1])
    return wsamp, placed, rsamp


def _solve_grid(
    dys: np.ndarray,
    wsamp: list[SampledProfile],
    rsamp: list[SampledProfile],
    placement: Placement,
    settings: SearchSettings,
    names: tuple[str, str],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rigid configuration and contact candidates at every Δy of ``dys`` (m) by the compiled
    search: roll φ [n] (rad), lift [2, n] (m) and per side and branch (found, gap (m),
    wheel sample index, η (m)) [2, 2, n, 4].

    Raises
    ------
    ScenarioError
        When the contact reaches the end of a profile at some Δy (``names``: wheel and rail
        names for the message).
    """
    n = dys.size
    res_phi = np.zeros(n)
    res_lift = np.zeros((2, n))
    res_slot = np.zeros((2, 2, n, 4))
    res_edge = np.zeros(n, dtype=np.int64)
    wl, wr = wsamp
    rl, rr = rsamp
    _search(dys, bool(settings.roll),
            wl.z, wl.y0, wl.h, wl.angle, rl.z, rl.y0, rl.h,
            wr.z, wr.y0, wr.h, wr.angle, rr.z, rr.y0, rr.h,
            placement.taping_line, placement.r0, settings.flange_angle,
            res_phi, res_lift, res_slot, res_edge)
    bad = np.flatnonzero(res_edge)
    if bad.size:
        worst = dys[bad[np.argmin(np.abs(dys[bad]))]]
        raise ScenarioError(
            f"contact search: at Δy = {worst * 1e3:.3f} mm the contact reaches the end of a "
            f"profile ({names[0]} / {names[1]}): the profiles do not cover the "
            "contact; reduce the Δy range or use longer profiles"
        )
    return res_phi, res_lift, res_slot


def _rigid_gaps(
    res_slot: np.ndarray, res_lift: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Branches found [2, 2, n], their gaps (m, 0 for the rigid contact, +inf when absent),
    the slot carrying the rigid contact [2, n] and the lift (m) [2, n] at which it touches, the
    parabola refinement's offset of the rigid gap (~1e-9 m) removed from gaps and lift.
    """
    found = res_slot[..., 0] > 0.5
    gap = np.where(found, res_slot[..., 1], np.inf)
    # the rigid contact has gap 0 exactly (removes the parabola refinement's ~1e-9 m offset)
    gmin = gap.min(axis=1, keepdims=True)
    gap = np.where(found, gap - gmin, np.inf)
    rigid = np.argmin(gap, axis=1)
    lift = res_lift - gmin[:, 0, :]
    return found, gap, rigid, lift


def _contact_point_fields(
    found: np.ndarray,
    kk: np.ndarray,
    eta: np.ndarray,
    wsamp: list[SampledProfile],
    rsamp: list[SampledProfile],
    placed: list[PlacedRail],
    r0: float,
) -> dict[str, np.ndarray]:
    """Wheel and rail values at every contact found [2, 2, n] (NaN elsewhere), from the wheel
    sample index ``kk`` and the lateral position ``eta`` (m) of the contact: wheel position s,
    rolling radius r (m), contact angle gamma (rad), lateral curvatures k_wheel and k_rail
    (1/m, positive convex), contact height z_contact (m), rail slope gamma_rail (rad) and the
    position on the rail profile rail_y, rail_z (m). ``r0`` is the nominal rolling radius (m).
    """
    sh = found.shape
    out = {name: np.full(sh, np.nan) for name in (
        "s", "r", "gamma", "k_wheel", "z_contact", "gamma_rail", "k_rail", "rail_y", "rail_z")}
    for side in range(2):
        ws, rs, pr = wsamp[side], rsamp[side], placed[side]
        wy = ws.y
        rgrid = rs.y
        for slot in range(2):
            m = found[side, slot]
            if not m.any():
                continue
            sc = ws.y0 + kk[side, slot, m] * ws.h
            out["s"][side, slot, m] = sc
            zw = np.interp(sc, wy, ws.z)
            out["r"][side, slot, m] = r0 - zw
            out["gamma"][side, slot, m] = np.interp(sc, wy, ws.angle)
            out["k_wheel"][side, slot, m] = np.interp(sc, wy, ws.curvature)
            e = eta[side, slot, m]
            out["z_contact"][side, slot, m] = np.interp(e, rgrid, rs.z)
            out["gamma_rail"][side, slot, m] = np.interp(e, rgrid, rs.angle)
            out["k_rail"][side, slot, m] = -np.interp(e, rgrid, rs.curvature)
            py, pz = pr.to_profile(e, out["z_contact"][side, slot, m])
            out["rail_y"][side, slot, m] = py
            out["rail_z"][side, slot, m] = pz
    return out


def search_contact(
    wheel: Profile | tuple[Profile, Profile],
    rail: Profile | tuple[Profile, Profile],
    placement: Placement | None = None,
    settings: SearchSettings | None = None,
) -> ContactGeometry:
    """Rigid contact points of a wheelset on its rails over a grid of lateral displacements.

    Parameters
    ----------
    wheel : Profile or (Profile, Profile)
        Wheel profile of both wheels, or (left, right) profiles; each drawn in the
        :class:`~flexride.contact.profiles.profile.Profile` convention (the right one is
        mirrored into place).
    rail : Profile or (Profile, Profile)
        Rail profile(s), likewise.
    placement : Placement, optional
        Inclination, gauge, gauge height, flange-back distance, r0 (defaults: 1:40, 1435 mm,
        14 mm, 1360 mm, 460 mm).
    settings : SearchSettings, optional
        Grid, sampling, roll and branch settings.

    Returns
    -------
    ContactGeometry

    Raises
    ------
    ScenarioError
        When the profiles do not cover the contact over the grid (the contact reaches the end
        of a profile) or the wheel never meets the rail.
    """
    placement = placement or Placement()
    settings = settings or SearchSettings()
    wheels = _as_pair(wheel, "wheel")
    rails = _as_pair(rail, "rail")
    wsamp, placed, rsamp = _sampled_profiles(wheels, rails, placement, settings)
    dys = settings.grid
    res_phi, res_lift, res_slot = _solve_grid(dys, wsamp, rsamp, placement, settings,
                                              (wheels[0].name, rails[0].name))
    found, gap, rigid, lift = _rigid_gaps(res_slot, res_lift)
    kk = res_slot[..., 2]
    eta = res_slot[..., 3]
    pts = _contact_point_fields(found, kk, eta, wsamp, rsamp, placed, placement.r0)
    two_point = found.all(axis=1) & (gap.max(axis=1, where=found, initial=0.0)
                                      <= settings.two_point_tolerance)

    def fill(a: np.ndarray) -> np.ndarray:
        return _ro(_fill_inactive(a, found))

    f = {name: fill(a) for name, a in pts.items()}
    return ContactGeometry(
        y=_ro(dys), roll=_ro(res_phi), lift=_ro(lift), active=_ro(found), gap=_ro(gap),
        s=f["s"], eta=fill(np.where(found, eta, np.nan)), rail_y=f["rail_y"],
        rail_z=f["rail_z"], z_contact=f["z_contact"], r=f["r"], gamma=f["gamma"],
        gamma_rail=f["gamma_rail"], k_wheel=f["k_wheel"], k_rail=f["k_rail"],
        rigid=_ro(rigid), two_point=_ro(two_point), placement=placement, settings=settings,
        wheel_names=(wheels[0].name, wheels[1].name),
        rail_names=(rails[0].name, rails[1].name),
        rail_origin=_ro(np.array([list(placed[0].origin), list(placed[1].origin)])),
    )

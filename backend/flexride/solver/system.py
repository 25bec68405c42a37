"""SystemArrays: what the numba kernel works on — flat arrays and one tuple of named scalars.

Coordinates are one vector: the vehicle bodies' coordinates one after another (6 rigid +
elastic per body), then the rail modes ordered [rail (left, right)][direction (vertical,
lateral, torsion)][mode]. Scalars are the named fields of :class:`Scalars` (``sys.par.speed``);
rows and columns of the tables and state arrays are indexed by the constants below.
"""

from __future__ import annotations

from typing import NamedTuple, get_type_hints

import numpy as np


class Scalars(NamedTuple):
    """Scalar parameters of the kernel, by name (a numba-typed named tuple: each access is a
    field of the argument, no array load).

    Floats are Python ``float`` and counts Python ``int`` (typed float64 / int64), so every
    scenario gives the same numba signature.
    """

    dt: float  # time step (s)
    psi: float  # Zhai's ψ (-)
    phi: float  # Zhai's φ (-)
    speed: float  # running speed V (m/s)
    gravity: float  # g (m/s²)
    b0: float  # half distance between the rolling circles (m)
    r0: float  # nominal rolling radius (m)
    win_len: float  # rail window length L (m)
    spacing: float  # fastener spacing d (m)
    h_foot: float  # shear centre above the rail foot h_f (m)
    h_head: float  # running surface above the shear centre (m)
    cz_d: float  # vertical fastener damping per length c_z/d (N·s/m²)
    ky_d: float  # lateral fastener stiffness per length k_y/d (N/m²)
    cy_d: float  # lateral fastener damping per length c_y/d (N·s/m²)
    kr_d: float  # fastener roll stiffness per length k_r/d (N·m/rad/m)
    cr_d: float  # fastener roll damping per length c_r/d (N·m·s/rad/m)
    mu: float  # wheel–rail friction coefficient (-)
    g_shear: float  # shear modulus of wheel and rail (Pa)
    hertz_g: float  # Hertz contact constant G (m/N^(2/3))
    flange_clearance: float  # lateral displacement where the flange touches (m)
    flange_k: float  # flange contact stiffness (N/m)
    runaway: float  # body displacement that stops a run (m)
    chatter_force: float  # step-to-step change of a wheel force that counts as chatter (N)
    v_min: float  # creepages referred to max(V, v_min) (m/s)
    ct_y0: float  # first Δy of the contact table (m)
    ct_dy: float  # step of the contact table (m)
    ct2_y0: float  # first Δy of the two-slot table (m)
    ct2_dy: float  # step of the two-slot table (m)
    irr_s0: float  # first grid point of the irregularity table (m)
    irr_ds: float  # step of the irregularity table (m)
    ln_s0: float  # first grid point of the line table (m)
    ln_ds: float  # step of the line table (m)
    s_start: float  # position of the vehicle centre at t = 0 (m)
    margin: float  # rail kept beyond the outermost wheelsets (m)
    k_traction: float  # traction link stiffness (N/m)
    c_traction: float  # traction link damping (N·s/m)
    contact_model: int  # 0 conical tread (one point + flange spring), 1 profiles (two slots)
    n_veh: int  # vehicle coordinates
    n_rail_modes: int  # modes per rail and direction
    n_bodies: int  # bodies
    n_elem: int  # suspension elements
    n_ws: int  # wheelsets
    n_dec: int  # steps per output sample
    shift_bays: int  # fastener bays the rail window moves at once
    n_points: int  # recorded points
    n_ch: int  # recorded channels


def make_scalars(**values: float) -> Scalars:
    """:class:`Scalars` from keyword values, each cast to its field's type.

    Parameters
    ----------
    **values : float or int
        Every field of :class:`Scalars` by name, in the units of its comment (s, m, N/m, …).
        Floats become ``float`` and counts ``int``, so numba sees one signature whatever the
        caller passed (e.g. an integer speed or a NumPy scalar).

    Returns
    -------
    Scalars

    Raises
    ------
    TypeError
        A field is missing or unknown.
    """
    kinds = get_type_hints(Scalars)
    unknown = set(values) - set(kinds)
    if unknown:
        raise TypeError(f"unknown scalar field(s): {', '.join(sorted(unknown))}")
    return Scalars(**{k: kinds[k](v) for k, v in values.items()})


# --- contact table fields (ct[side, field, i]) -------------------------------------------
CT_R, CT_GAMMA, CT_DZ, CT_YC, CT_CA, CT_CB, CT_C11, CT_C22, CT_C23, CT_C33 = range(10)

# --- two-slot profile contact table fields (ct2[side, slot, field, i]) -----------------------
# the first ten are the CT_* fields above, then: vertical gap at the rigid configuration, Hertz
# normal constant G (m/N^(2/3)), contact position on the rail (lateral, height)
PT_GAP, PT_GH, PT_YR, PT_ZR = range(10, 14)
N_PT = 14
CONTACT_CONICAL, CONTACT_PROFILES = 0, 1

# --- line table rows -------------------------------------------------------------------------
LN_KAPPA, LN_ROLL, LN_HEADING, LN_HINT, LN_DKAPPA = range(5)

# --- per-body line values (body_line[body, field]), scratch filled by vehicle_forces --------
BL_HEADING, BL_HINT, BL_ROLL, BL_KAPPA, BL_DROLL = range(5)
N_BL = 5

# --- per-wheel auxiliary outputs (aux[wheelset, side, field]) ------------------------------
# AUX_N is the sum of the normal forces of the wheel's contact points; AUX_N_FLANGE the normal
# force of the flange slot (profiles; 0 for the conical tread); AUX_ANGLE the track-frame contact
# angle (rad) of the more loaded point (0 without contact)
AUX_FZ, AUX_FY, AUX_N, AUX_RAIL_Z, AUX_RAIL_Y, AUX_DELTA, AUX_FX, AUX_N_FLANGE, AUX_ANGLE = range(9)
N_AUX = 9
#: per-wheel accumulated outputs (facc[wheelset, side, k]): Fz, Fy, N, N_flange, angle
N_FACC = 5
#: creep-force state per wheel (cst[wheelset, side, 3·slot + k]): (Fx, Fy, Mz) of each slot
N_CST = 6

# --- channel kinds ---------------------------------------------------------------------------
CH_POINT_ACC_Y, CH_POINT_ACC_Z, CH_WHEEL_FZ, CH_WHEEL_FY, CH_RAIL_Z, CH_RAIL_Y, CH_COORD = range(7)
CH_WHEEL_N = 7
CH_WHEEL_N_FLANGE, CH_WHEEL_ANGLE = 8, 9
#: force of a suspension element's translational spring–damper on its body A (channel ``a`` the
#: element, ``b`` the direction 0 x, 1 y, 2 z; N, in A's track frame), the mean over the output
#: interval of ``el_force`` (accumulated in ``eacc[element, direction]``)
CH_ELEMENT_FORCE = 10

# --- state scalars (tstate) ------------------------------------------------------------------
T_TIME, T_WIN_S0, T_STEP, T_NREC, T_FIRST = range(5)
N_TSTATE = 5

# --- the run-time watch (watch[wheelset, side, quantity, field]) ------------------------------
# quantities: the wheel's lateral creep force (both slots), its normal force; fields: the last
# value, the last step-to-step change, the steps in a row the change alternated in sign beyond
# ``chatter_force``
W_CREEP_Y, W_NORMAL = range(2)
N_WATCH_Q = 2
W_LAST, W_CHANGE, W_COUNT = range(3)
N_WATCH_F = 3
#: Steps in a row of alternating changes beyond ``chatter_force`` that stop a run.
CHATTER_STEPS = 64


class SystemArrays(NamedTuple):
    """Everything the kernel needs: named scalars and flat NumPy arrays.

    Keep the number of arrays down: the kernel's calls that take ``sys`` slow down with it in
    a step, not smoothly. A 35th array (unused) beside the 34 of 2026-12-03 made every step
    of the reference case 15 % slower (6.3 → 7.2 µs, alternating runs); hence the channel
    recipes are one array ``ch`` (they were three) since ``el_force`` came: 33 arrays.
    """

    par: Scalars  # named scalars
    minv: np.ndarray  # float64[n] inverse generalised mass
    kdiag: np.ndarray  # float64[n_veh] modal stiffness of elastic coordinates
    cdiag: np.ndarray  # float64[n_veh] modal damping of elastic coordinates
    body_off: np.ndarray  # int64[nb] first coordinate of each body
    body_ndof: np.ndarray  # int64[nb]
    body_x: np.ndarray  # float64[nb] reference position from the vehicle centre (m)
    body_h: np.ndarray  # float64[nb] CG height above TOR (m)
    body_mass: np.ndarray  # float64[nb]
    body_inertia: np.ndarray  # float64[nb, 3]
    body_ws: np.ndarray  # int64[nb] 1 for wheelsets
    phi: np.ndarray  # float64[:] all marker matrices, row-major 6 × ndof each
    el_a: np.ndarray  # int64[ne] body A
    el_b: np.ndarray  # int64[ne] body B
    el_phia: np.ndarray  # int64[ne] offset of marker A's matrix in ``phi``
    el_phib: np.ndarray  # int64[ne]
    el_k: np.ndarray  # float64[ne, 6]
    el_c: np.ndarray  # float64[ne, 6]
    el_pb: np.ndarray  # float64[ne, 3] marker B position from B's track-frame origin (m)
    ws_body: np.ndarray  # int64[nw] body index of each wheelset
    rail_kz: np.ndarray  # float64[nm] E·I_y·κ⁴ + k_z/d
    rail_kyb: np.ndarray  # float64[nm] E·I_z·κ⁴
    rail_ktb: np.ndarray  # float64[nm] G·J·κ²
    rail_kap: np.ndarray  # float64[nm] κ_k
    rail_dst: np.ndarray  # float64[nm, nm] sin(kπj/N)
    ct: np.ndarray  # float64[2, 10, n_ct] contact geometry table (one point per wheel)
    ct2: np.ndarray  # float64[2, 2, N_PT, n_ct2] two-slot profile table (contact_model 1)
    irr: np.ndarray  # float64[4, n_irr] rail irregularities z_L, z_R, y_L, y_R
    line: np.ndarray  # float64[5, n_line] line geometry
    pt_body: np.ndarray  # int64[np] body of each recorded point
    pt_phi: np.ndarray  # int64[np] offset of the point's marker matrix
    ch: np.ndarray  # int64[nch, 3] recipe of each recorded channel: kind (CH_*), a, b
    # scratch: the kernel writes here, so one SystemArrays serves one thread at a time
    body_line: np.ndarray  # float64[nb, N_BL] line values at each body, see BL_*
    # float64[ne, 3] translational spring–damper force (x, y, z) of each element on marker A,
    # in A's track frame (N), written by every force evaluation (zero without translational rates)
    el_force: np.ndarray

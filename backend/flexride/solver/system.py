"""SystemArrays: the flat arrays the numba kernel works on (no Python objects inside).

Coordinates are one vector: the vehicle bodies' coordinates one after another (6 rigid +
elastic per body), then the rail modes ordered [rail (left, right)][direction (vertical,
lateral, torsion)][mode]. Scalars sit in ``fpar``/``ipar`` at the indices named below.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

# --- float parameters (fpar) -------------------------------------------------------------
F_DT, F_PSI, F_PHI, F_SPEED, F_GRAVITY, F_B0, F_R0, F_RAIL_B = range(8)
F_WIN_LEN, F_SPACING, F_RAIL_M, F_RAIL_J, F_H_FOOT, F_H_HEAD = range(8, 14)
F_KZ_D, F_CZ_D, F_KY_D, F_CY_D, F_KR_D, F_CR_D = range(14, 20)
F_MU, F_GSHEAR, F_HERTZ_G, F_FL_CLEAR, F_FL_K, F_RUNAWAY, F_VMIN = range(20, 27)
F_CT_Y0, F_CT_DY, F_IRR_S0, F_IRR_DS, F_LN_S0, F_LN_DS, F_S_START, F_MARGIN = range(27, 35)
F_K_TRACTION, F_C_TRACTION = range(35, 37)
N_FPAR = 37

# --- integer parameters (ipar) -----------------------------------------------------------
I_NVEH, I_NRAIL_MODES, I_NBODIES, I_NELEM, I_NWS, I_NDEC, I_SHIFT_BAYS, I_NPOINTS = range(8)
I_NCH = 8
N_IPAR = 9

# --- contact table fields (ct[side, field, i]) -------------------------------------------
CT_R, CT_GAMMA, CT_DZ, CT_YC, CT_CA, CT_CB, CT_C11, CT_C22, CT_C23, CT_C33 = range(10)
N_CT = 10

# --- line table rows -------------------------------------------------------------------------
LN_KAPPA, LN_ROLL, LN_HEADING, LN_HINT, LN_DKAPPA = range(5)

# --- per-body line values (body_line[body, field]), scratch filled by vehicle_forces --------
BL_HEADING, BL_HINT, BL_ROLL, BL_KAPPA, BL_DROLL = range(5)
N_BL = 5

# --- irregularity rows -----------------------------------------------------------------------
IRR_ZL, IRR_ZR, IRR_YL, IRR_YR = range(4)

# --- per-wheel auxiliary outputs (aux[wheelset, side, field]) ------------------------------
AUX_FZ, AUX_FY, AUX_N, AUX_RAIL_Z, AUX_RAIL_Y, AUX_DELTA, AUX_FX = range(7)
N_AUX = 7

# --- channel kinds ---------------------------------------------------------------------------
CH_POINT_ACC_Y, CH_POINT_ACC_Z, CH_WHEEL_FZ, CH_WHEEL_FY, CH_RAIL_Z, CH_RAIL_Y, CH_COORD = range(7)
CH_WHEEL_N = 7

# --- state scalars (tstate) ------------------------------------------------------------------
T_TIME, T_WIN_S0, T_STEP, T_NREC, T_FIRST = range(5)
N_TSTATE = 5


class SystemArrays(NamedTuple):
    """Everything the kernel needs, as flat NumPy arrays."""

    fpar: np.ndarray  # float64[N_FPAR]
    ipar: np.ndarray  # int64[N_IPAR]
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
    ct: np.ndarray  # float64[2, N_CT, n_ct] contact geometry table
    irr: np.ndarray  # float64[4, n_irr] rail irregularities z_L, z_R, y_L, y_R
    line: np.ndarray  # float64[5, n_line] line geometry
    pt_body: np.ndarray  # int64[np] body of each recorded point
    pt_phi: np.ndarray  # int64[np] offset of the point's marker matrix
    ch_kind: np.ndarray  # int64[nch]
    ch_a: np.ndarray  # int64[nch]
    ch_b: np.ndarray  # int64[nch]
    # scratch: the kernel writes here, so one SystemArrays serves one thread at a time
    body_line: np.ndarray  # float64[nb, N_BL] line values at each body, see BL_*

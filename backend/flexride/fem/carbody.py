"""Parametric shell model of a B-type metro car body (aluminium double-skin extrusions).

Geometry (model axes: x forward from the body centre, y to the left, z up from top of rail):
floor at ``floor_height``, vertical side walls from the floor to the eaves, a circular-arc roof
from the eaves up to ``roof_height`` on the centre line, end walls with a gangway opening, four
doors and windows per side. Panels are four-node shells (double-skin extrusions as sandwich
laminates); side sills, cant rails, underframe longitudinal members, end sills, door and window
frames are beams; each bogie bolster is a transverse beam at the air-spring height hung from the
floor by stiff webs, carrying the air-spring seats and the bogie centre pivot. Non-structural mass
(under-floor equipment, interior, passengers, roof equipment) is distributed by
:mod:`flexride.fem.massmatch` so that mass, CG and inertias match the vehicle parameters.
"""

from __future__ import annotations

import itertools
from dataclasses import asdict, dataclass, replace

import numpy as np

from flexride.fem.massmatch import (
    InertiaTarget,
    MassGroup,
    groups_to_point_masses,
    solve_group_masses,
)
from flexride.fem.meshing import NodeRegistry, mesh_lines
from flexride.fem.model import FEModel
from flexride.fem.pyfe3d_adapter import ALUMINIUM, BeamSection, Mesh, ShellSection, assemble
from flexride.fem.rigid import mass_properties

#: Region names of car-body nodes (index = region code).
REGIONS = ("floor", "wall_left", "wall_right", "roof", "end_front", "end_rear", "underframe")
_FLOOR, _WALL_L, _WALL_R, _ROOF, _END_F, _END_R, _UNDER = range(7)

@dataclass(frozen=True)
class CarBodyParams:
    """Parameters of the car-body model (lengths m, thicknesses m, fractions -).

    The section thicknesses and the non-structural mass split are the calibration variables;
    the defaults in :data:`flexride.fem.defaults.CARBODY_CALIBRATED` are used by the default
    model.
    """

    length: float = 19.0
    width: float = 2.8
    floor_height: float = 1.10
    eave_height: float = 3.40
    roof_height: float = 3.80
    underframe_height: float = 0.90
    bogie_spacing: float = 12.6
    air_spring_y: float = 0.95
    door_centres: tuple[float, ...] = (2.3, 6.9)
    door_width: float = 1.30
    door_height: float = 1.86
    window_centres: tuple[float, ...] = (0.0, 4.6, 8.45)
    window_widths: tuple[float, ...] = (2.4, 2.2, 1.2)
    window_sill: float = 0.86
    window_height: float = 0.90
    gangway_width: float = 1.20
    gangway_height: float = 1.95
    # double-skin extrusions: face-sheet thickness and overall depth
    floor_face: float = 3.0e-3
    floor_depth: float = 0.040
    wall_face: float = 2.5e-3
    wall_depth: float = 0.030
    roof_face: float = 2.0e-3
    roof_depth: float = 0.024
    end_face: float = 2.5e-3
    end_depth: float = 0.030
    web_fraction: float = 0.04
    beam_scale: float = 1.0
    # prior split of the non-structural mass
    nsm_floor: float = 0.30
    nsm_aisle: float = 0.15
    aisle_half_width: float = 0.6
    nsm_underfloor: float = 0.35
    nsm_roof: float = 0.08
    nsm_walls: float = 0.08
    nsm_ends: float = 0.04
    underfloor_cg_height: float = 0.60

    def to_dict(self) -> dict:
        """JSON-able dict."""
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self).items()}

    def with_values(self, **kw) -> CarBodyParams:
        """Copy with some fields replaced."""
        return replace(self, **kw)


def _roof_z(p: CarBodyParams, y: np.ndarray | float) -> np.ndarray:
    a, c = p.width / 2.0, p.roof_height - p.eave_height
    if c <= 0:
        return np.full_like(np.asarray(y, float), p.eave_height)
    r = (a**2 + c**2) / (2.0 * c)
    y = np.asarray(y, dtype=float)
    return p.roof_height - (r - np.sqrt(np.maximum(r**2 - y**2, 0.0)))


def _box(w, h, t, scale):
    return BeamSection.box(w, h, t, ALUMINIUM).scaled(scale)


def build_carbody(
    params: CarBodyParams,
    target: InertiaTarget | None,
    element_size: float = 0.2,
) -> FEModel:
    """Generate the car-body FE model.

    Parameters
    ----------
    params : CarBodyParams
        Geometry, sections and mass split.
    target : InertiaTarget or None
        Mass, CG (model coordinates) and inertias to match with non-structural mass; None
        gives the bare structure.
    element_size : float
        Largest element edge (m).

    Returns
    -------
    FEModel
        Mesh, sections, named nodes and regions; ``info["mass_groups"]`` lists the
        non-structural masses.
    """
    p = params
    h = float(element_size)
    L2, W2 = p.length / 2.0, p.width / 2.0
    lc, ys = p.bogie_spacing / 2.0, p.air_spring_y
    zf, ze = p.floor_height, p.eave_height
    xs = mesh_lines(-L2, L2, h, (0.0, lc, -lc))
    yl = mesh_lines(-W2, W2, h, (0.0, ys, -ys))
    zl = mesh_lines(zf, ze, h)
    zroof = _roof_z(p, yl)
    zroof[0] = zroof[-1] = ze
    nx, ny, nz = xs.size, yl.size, zl.size
    reg = NodeRegistry()

    floor = np.array([[reg.node(x, y, zf, _FLOOR) for y in yl] for x in xs])
    wall_l = np.array([[reg.node(x, W2, z, _WALL_L) for z in zl] for x in xs])
    wall_r = np.array([[reg.node(x, -W2, z, _WALL_R) for z in zl] for x in xs])
    roof = np.array(
        [[reg.node(x, y, zr, _ROOF) for y, zr in zip(yl, zroof, strict=False)] for x in xs]
    )
    s = (zl - zf) / (ze - zf)
    ends = {}
    for xe, r in ((L2, _END_F), (-L2, _END_R)):
        ends[xe] = np.array(
            [
                [reg.node(xe, y, zf + (zr - zf) * sk, r) for sk in s]
                for y, zr in zip(yl, zroof, strict=False)
            ]
        )

    quads: list[tuple[int, int, int, int]] = []
    qgroup: list[int] = []
    shell_names = ["floor", "side_wall", "roof", "end_wall"]
    G_FLOOR, G_WALL, G_ROOF, G_END = range(4)

    def add_grid(grid, group, skip=None):
        for i in range(grid.shape[0] - 1):
            for j in range(grid.shape[1] - 1):
                if skip is not None and skip(i, j):
                    continue
                quads.append((grid[i, j], grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1]))
                qgroup.append(group)

    add_grid(floor, G_FLOOR)
    add_grid(roof, G_ROOF)

    xc = 0.5 * (xs[:-1] + xs[1:])
    zc = 0.5 * (zl[:-1] + zl[1:])
    yc = 0.5 * (yl[:-1] + yl[1:])
    doors = [(c, p.door_width) for d in p.door_centres for c in ((d, -d) if d else (d,))]
    windows = [
        (c, w)
        for d, w in zip(p.window_centres, p.window_widths, strict=False)
        for c in ((d, -d) if d else (d,))
    ]
    z_door = zf + p.door_height
    z_sill, z_top = zf + p.window_sill, zf + p.window_sill + p.window_height

    def opening(i: int, k: int) -> str | None:
        x, z = xc[i], zc[k]
        for c, w in doors:
            if abs(x - c) < w / 2.0 and z < z_door:
                return "door"
        for c, w in windows:
            if abs(x - c) < w / 2.0 and z_sill < z < z_top:
                return "window"
        return None

    add_grid(wall_l, G_WALL, lambda i, k: opening(i, k) is not None)
    add_grid(wall_r, G_WALL, lambda i, k: opening(i, k) is not None)
    z_gw = zf + p.gangway_height
    for xe in (L2, -L2):
        grid = ends[xe]
        zc_end = np.array(
            [
                [
                    0.5 * (grid_z(reg, grid[j, k]) + grid_z(reg, grid[j, k + 1]))
                    for k in range(nz - 1)
                ]
                for j in range(ny - 1)
            ]
        )
        add_grid(
            grid,
            G_END,
            lambda j, k, zc_end=zc_end: abs(yc[j]) < p.gangway_width / 2.0 and zc_end[j, k] < z_gw,
        )

    # ---- beams
    bs = p.beam_scale
    beam_sections = [
        _box(0.15, 0.25, 6e-3, bs),  # side sill
        _box(0.12, 0.12, 4e-3, bs),  # cant rail
        _box(0.12, 0.16, 5e-3, bs),  # underframe longitudinal member
        _box(0.15, 0.20, 6e-3, bs),  # end sill
        _box(0.10, 0.08, 5e-3, bs),  # door / window frame
        _box(0.30, 0.20, 12e-3, bs),  # bolster
        _box(0.30, 0.20, 12e-3, max(bs, 1.0) * 4.0),  # bolster web (stiff, short)
    ]
    beam_names = [
        "side_sill",
        "cant_rail",
        "underframe_longitudinal",
        "end_sill",
        "opening_frame",
        "bolster",
        "bolster_web",
    ]
    B_SILL, B_CANT, B_LONG, B_END, B_FRAME, B_BOLSTER, B_WEB = range(7)
    beams: list[tuple[int, int]] = []
    bgroup: list[int] = []
    bvxy: list[tuple[float, float, float]] = []

    def add_line(nodes, group, vxy):
        for a, b in itertools.pairwise(nodes):
            beams.append((int(a), int(b)))
            bgroup.append(group)
            bvxy.append(vxy)

    jl, jr = ny - 1, 0
    j_as = [int(np.argmin(np.abs(yl - ys))), int(np.argmin(np.abs(yl + ys)))]
    add_line(floor[:, jl], B_SILL, (0.0, 1.0, 0.0))
    add_line(floor[:, jr], B_SILL, (0.0, 1.0, 0.0))
    add_line(wall_l[:, -1], B_CANT, (0.0, 1.0, 0.0))
    add_line(wall_r[:, -1], B_CANT, (0.0, 1.0, 0.0))
    for j in j_as:
        add_line(floor[:, j], B_LONG, (0.0, 1.0, 0.0))
    add_line(floor[0, :], B_END, (1.0, 0.0, 0.0))
    add_line(floor[-1, :], B_END, (1.0, 0.0, 0.0))
    # frames around openings (posts and headers / sills) on both walls
    for wall in (wall_l, wall_r):
        mask = np.array([[opening(i, k) is not None for k in range(nz - 1)] for i in range(nx - 1)])
        for i in range(nx - 1):
            for k in range(nz - 1):
                if not mask[i, k]:
                    continue
                # each edge of an opening cell that borders a solid cell (or the floor) gets a beam
                if i == 0 or not mask[i - 1, k]:
                    add_line([wall[i, k], wall[i, k + 1]], B_FRAME, (1.0, 0.0, 0.0))
                if i == nx - 2 or not mask[i + 1, k]:
                    add_line([wall[i + 1, k], wall[i + 1, k + 1]], B_FRAME, (1.0, 0.0, 0.0))
                if k == nz - 2 or not mask[i, k + 1]:
                    add_line([wall[i, k + 1], wall[i + 1, k + 1]], B_FRAME, (0.0, 0.0, 1.0))
                if k > 0 and not mask[i, k - 1]:
                    add_line([wall[i, k], wall[i + 1, k]], B_FRAME, (0.0, 0.0, 1.0))
    # bolsters at the bogie centres: transverse beam at the air-spring height, hung by webs
    zu = p.underframe_height
    named: dict[str, int] = {}
    for xb, tag in ((lc, "1"), (-lc, "2")):
        ib = int(np.argmin(np.abs(xs - xb)))
        bol = [reg.node(xs[ib], y, zu, _UNDER) for y in yl]
        add_line(bol, B_BOLSTER, (1.0, 0.0, 0.0))
        for j, nb in enumerate(bol):
            add_line([nb, floor[ib, j]], B_WEB, (1.0, 0.0, 0.0))
        named[f"as{tag}L"] = bol[j_as[0]]
        named[f"as{tag}R"] = bol[j_as[1]]
        named[f"bogie{tag}"] = bol[int(np.argmin(np.abs(yl)))]

    coords = reg.array()
    region = np.asarray(reg.region, dtype=np.int64)
    mesh = Mesh(
        nodes=coords,
        quads=np.asarray(quads, dtype=np.int64),
        quad_group=np.asarray(qgroup, dtype=np.int64),
        beams=np.asarray(beams, dtype=np.int64),
        beam_group=np.asarray(bgroup, dtype=np.int64),
        beam_vxy=np.asarray(bvxy, dtype=float),
    )
    shells = [
        ShellSection(p.floor_face, p.floor_depth, p.web_fraction),
        ShellSection(p.wall_face, p.wall_depth, p.web_fraction),
        ShellSection(p.roof_face, p.roof_depth, p.web_fraction),
        ShellSection(p.end_face, p.end_depth, p.web_fraction),
    ]

    # named points: paper points and floor grid
    j0 = int(np.argmin(np.abs(yl)))
    i_front, i_rear, i_mid = (int(np.argmin(np.abs(xs - v))) for v in (lc, -lc, 0.0))
    named["PR"] = int(roof[i_front, j0])
    named["PFB"] = int(floor[i_front, j0])
    named["PC"] = int(floor[i_mid, j0])
    named["PRB"] = int(floor[i_rear, j0])
    named["PLA"] = int(floor[i_rear, j_as[0]])
    named["PRA"] = int(floor[i_rear, j_as[1]])
    grid_names = []
    for ix, x in enumerate(np.arange(-9.0, 9.0 + 1e-9, 1.0)):
        if abs(x) > L2:
            continue
        for iy, y in enumerate((-1.0, -0.5, 0.0, 0.5, 1.0)):
            i = int(np.argmin(np.abs(xs - x)))
            j = int(np.argmin(np.abs(yl - y)))
            name = f"F{ix:02d}_{iy}"
            named[name] = int(floor[i, j])
            grid_names.append(name)

    model = FEModel(
        name="carbody",
        mesh=mesh,
        shell_sections=shells,
        beam_sections=beam_sections,
        shell_group_names=shell_names,
        beam_group_names=beam_names,
        named_nodes=named,
        node_region=region,
        region_names=list(REGIONS),
        info={"params": p.to_dict(), "element_size": h, "floor_grid": grid_names},
    )
    if target is not None:
        _add_nonstructural_mass(model, p, target)
    return compact(model)


def grid_z(reg: NodeRegistry, i: int) -> float:
    """z coordinate of node ``i`` of a registry."""
    return reg.coords[i][2]


def _node_areas(mesh: Mesh, group: int) -> np.ndarray:
    """Tributary area of every node from the shells of ``group`` (a quarter of each quad)."""
    sel = mesh.quad_group == group
    q = mesh.quads[sel]
    x = mesh.nodes
    a, b, c, d = (x[q[:, k]] for k in range(4))
    area = 0.5 * np.linalg.norm(np.cross(c - a, d - b), axis=1)
    out = np.zeros(mesh.n_nodes)
    for k in range(4):
        np.add.at(out, q[:, k], area / 4.0)
    return out


def compact(model: FEModel) -> FEModel:
    """Drop nodes that no element or mass uses and renumber (in place; returns the model)."""
    mesh = model.mesh
    used = np.zeros(mesh.n_nodes, dtype=bool)
    for arr in (mesh.quads, mesh.beams, mesh.springs):
        used[arr.ravel()] = True
    used[mesh.mass_nodes] = True
    new = -np.ones(mesh.n_nodes, dtype=np.int64)
    new[used] = np.arange(int(used.sum()))
    mesh.nodes = mesh.nodes[used]
    mesh.quads = new[mesh.quads]
    mesh.beams = new[mesh.beams]
    mesh.springs = new[mesh.springs]
    mesh.mass_nodes = new[mesh.mass_nodes]
    if model.node_region is not None:
        model.node_region = model.node_region[used]
    model.named_nodes = {k: int(new[v]) for k, v in model.named_nodes.items()}
    return model


#: Longitudinal bands (|x| in m, as fractions of the half length) of the mass groups.
_BANDS = (0.0, 0.2, 0.4, 0.6, 0.8, 1.0001)


def _add_nonstructural_mass(model: FEModel, p: CarBodyParams, target: InertiaTarget) -> None:
    mesh = model.mesh
    coords = mesh.nodes
    _, M = assemble(mesh, model.shell_sections, model.beam_sections)
    structure = mass_properties(M, coords)
    nsm_total = max(target.mass - structure.mass, 0.0)
    L2 = p.length / 2.0
    x, y = coords[:, 0], coords[:, 1]
    a_floor, a_wall, a_roof, a_end = (_node_areas(mesh, g) for g in range(4))
    drop = p.underfloor_cg_height - p.floor_height
    kinds = {
        # kind: (node weights, extra node mask, offset z)
        "floor": (a_floor, np.ones_like(x, dtype=bool), 0.0),
        "aisle": (a_floor, np.abs(y) <= p.aisle_half_width + 1e-9, 0.0),
        "underfloor": (a_floor, np.abs(y) <= p.aisle_half_width + 1e-9, drop),
        "roof": (a_roof, np.abs(y) <= 0.9 + 1e-9, 0.0),
        "walls": (a_wall, np.ones_like(x, dtype=bool), 0.0),
    }
    fractions = {
        "floor": p.nsm_floor,
        "aisle": p.nsm_aisle,
        "underfloor": p.nsm_underfloor,
        "roof": p.nsm_roof,
        "walls": p.nsm_walls,
        "ends": p.nsm_ends,
    }
    ax = np.abs(x) / L2
    groups: list[MassGroup] = []
    areas: list[float] = []
    for kind, (w, mask, dz) in kinds.items():
        for b0, b1 in itertools.pairwise(_BANDS):
            sel = mask & (ax >= b0 - 1e-9) & (ax < b1 - 1e-9) & (w > 0)
            if not sel.any():
                continue
            nodes = np.flatnonzero(sel)
            wts = w[nodes]
            offs = np.tile([0.0, 0.0, dz], (nodes.size, 1))
            groups.append(
                MassGroup(f"{kind}.{b0:.1f}-{min(b1, 1.0):.1f}", kind, nodes, wts / wts.sum(), offs)
            )
            areas.append(float(wts.sum()))
    nodes = np.flatnonzero(a_end > 0)
    groups.append(
        MassGroup(
            "ends", "ends", nodes, a_end[nodes] / a_end[nodes].sum(), np.zeros((nodes.size, 3))
        )
    )
    areas.append(float(a_end.sum()))
    for kind, frac in fractions.items():
        idx = [i for i, g in enumerate(groups) if g.kind == kind]
        total = sum(areas[i] for i in idx)
        for i in idx:
            groups[i].prior = frac * nsm_total * areas[i] / total
    masses = solve_group_masses(coords, groups, structure, target)
    n_, m_, o_ = groups_to_point_masses(groups, masses)
    mesh.mass_nodes, mesh.mass_values, mesh.mass_offsets = n_, m_, o_
    model.info["structural_mass_kg"] = float(structure.mass)
    model.info["mass_groups_kg"] = {
        g.name: round(float(mg), 3) for g, mg in zip(groups, masses, strict=False)
    }

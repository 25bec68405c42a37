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
from flexride.fem.meshing import ElementLists, NodeRegistry, mesh_lines
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
    """Aluminium box section ``w`` × ``h`` with wall ``t`` (m), stiffness scaled by ``scale``."""
    return BeamSection.box(w, h, t, ALUMINIUM).scaled(scale)


#: Shell groups (index = section of :func:`_shell_sections`).
SHELL_GROUPS = ("floor", "side_wall", "roof", "end_wall")
_G_FLOOR, _G_WALL, _G_ROOF, _G_END = range(4)
#: Beam groups (index = section of :func:`_beam_sections`).
BEAM_GROUPS = (
    "side_sill",
    "cant_rail",
    "underframe_longitudinal",
    "end_sill",
    "opening_frame",
    "bolster",
    "bolster_web",
)
_B_SILL, _B_CANT, _B_LONG, _B_END, _B_FRAME, _B_BOLSTER, _B_WEB = range(7)


@dataclass(frozen=True)
class _Grid:
    """Mesh lines of the car body (m) and the lines the beams and points sit on.

    Attributes
    ----------
    xs : numpy.ndarray
        x of the cross-sections, through the body centre and the bogie centres.
    yl : numpy.ndarray
        y of the floor and roof lines, through the centre line and the air springs.
    zl : numpy.ndarray
        z of the side-wall lines, floor to eaves.
    zroof : numpy.ndarray
        Roof height at each ``yl`` (the eaves at the ends).
    j_air : tuple of int
        Indices in ``yl`` of the left and right air springs.
    """

    xs: np.ndarray
    yl: np.ndarray
    zl: np.ndarray
    zroof: np.ndarray
    j_air: tuple[int, int]


@dataclass(frozen=True)
class _Panels:
    """Node indices of the panel grids: ``floor`` and ``roof`` (x, y), ``wall_left`` and
    ``wall_right`` (x, z), ``end_front`` and ``end_rear`` (y, z).
    """

    floor: np.ndarray
    wall_left: np.ndarray
    wall_right: np.ndarray
    roof: np.ndarray
    end_front: np.ndarray
    end_rear: np.ndarray


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
    grid = _grid(p, h)
    reg = NodeRegistry()
    panels = _panel_nodes(reg, p, grid)
    openings = _openings(p, grid)
    el = ElementLists()
    _add_shells(el, reg, p, grid, panels, openings)
    _add_frame_beams(el, grid, panels, openings)
    named = _add_bolsters(el, reg, p, grid, panels)
    grid_names = _add_output_nodes(named, p, grid, panels)
    mesh = Mesh(
        nodes=reg.array(),
        quads=np.asarray(el.quads, dtype=np.int64),
        quad_group=np.asarray(el.quad_group, dtype=np.int64),
        beams=np.asarray(el.beams, dtype=np.int64),
        beam_group=np.asarray(el.beam_group, dtype=np.int64),
        beam_vxy=np.asarray(el.beam_vxy, dtype=float),
    )
    model = FEModel(
        name="carbody",
        mesh=mesh,
        shell_sections=_shell_sections(p),
        beam_sections=_beam_sections(p.beam_scale),
        shell_group_names=list(SHELL_GROUPS),
        beam_group_names=list(BEAM_GROUPS),
        named_nodes=named,
        node_region=np.asarray(reg.region, dtype=np.int64),
        region_names=list(REGIONS),
        info={"params": p.to_dict(), "element_size": h, "floor_grid": grid_names},
    )
    if target is not None:
        _add_nonstructural_mass(model, p, target)
    return compact(model)


def _grid(p: CarBodyParams, h: float) -> _Grid:
    """Mesh lines at most ``h`` m apart: x through the centre and the bogie centres, y through
    the centre line and the air springs, z from the floor to the eaves; the roof arc over y.
    """
    L2, W2 = p.length / 2.0, p.width / 2.0
    lc, ys = p.bogie_spacing / 2.0, p.air_spring_y
    xs = mesh_lines(-L2, L2, h, (0.0, lc, -lc))
    yl = mesh_lines(-W2, W2, h, (0.0, ys, -ys))
    zl = mesh_lines(p.floor_height, p.eave_height, h)
    zroof = _roof_z(p, yl)
    zroof[0] = zroof[-1] = p.eave_height
    j_air = (int(np.argmin(np.abs(yl - ys))), int(np.argmin(np.abs(yl + ys))))
    return _Grid(xs=xs, yl=yl, zl=zl, zroof=zroof, j_air=j_air)


def _panel_nodes(reg: NodeRegistry, p: CarBodyParams, g: _Grid) -> _Panels:
    """Nodes of the floor, the side walls, the roof and the end walls (in that order), each
    tagged with its region; edges shared by two panels get one node.
    """
    L2, W2 = p.length / 2.0, p.width / 2.0
    zf, ze = p.floor_height, p.eave_height
    floor = np.array([[reg.node(x, y, zf, _FLOOR) for y in g.yl] for x in g.xs])
    wall_l = np.array([[reg.node(x, W2, z, _WALL_L) for z in g.zl] for x in g.xs])
    wall_r = np.array([[reg.node(x, -W2, z, _WALL_R) for z in g.zl] for x in g.xs])
    roof = np.array(
        [[reg.node(x, y, zr, _ROOF) for y, zr in zip(g.yl, g.zroof, strict=False)] for x in g.xs]
    )
    s = (g.zl - zf) / (ze - zf)
    ends = {}
    for xe, r in ((L2, _END_F), (-L2, _END_R)):
        ends[xe] = np.array(
            [
                [reg.node(xe, y, zf + (zr - zf) * sk, r) for sk in s]
                for y, zr in zip(g.yl, g.zroof, strict=False)
            ]
        )
    return _Panels(floor=floor, wall_left=wall_l, wall_right=wall_r, roof=roof,
                   end_front=ends[L2], end_rear=ends[-L2])


def _openings(p: CarBodyParams, g: _Grid) -> np.ndarray:
    """(nx − 1, nz − 1) mask of the side-wall cells (x, z) that are door or window openings
    (both walls alike): doors from the floor up, windows between sill and top.
    """
    xc = 0.5 * (g.xs[:-1] + g.xs[1:])
    zc = 0.5 * (g.zl[:-1] + g.zl[1:])
    zf = p.floor_height
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

    return np.array([[opening(i, k) is not None for k in range(g.zl.size - 1)]
                     for i in range(g.xs.size - 1)])


def _add_shells(el: ElementLists, reg: NodeRegistry, p: CarBodyParams, g: _Grid,
                panels: _Panels, openings: np.ndarray) -> None:
    """Shells of the floor, the roof, the side walls (without the openings) and the end walls
    (without the gangway opening), in that order.
    """
    el.add_grid(panels.floor, _G_FLOOR)
    el.add_grid(panels.roof, _G_ROOF)
    el.add_grid(panels.wall_left, _G_WALL, lambda i, k: bool(openings[i, k]))
    el.add_grid(panels.wall_right, _G_WALL, lambda i, k: bool(openings[i, k]))
    yc = 0.5 * (g.yl[:-1] + g.yl[1:])
    z_gw = p.floor_height + p.gangway_height
    for grid in (panels.end_front, panels.end_rear):
        zc_end = np.array(
            [
                [
                    0.5 * (grid_z(reg, grid[j, k]) + grid_z(reg, grid[j, k + 1]))
                    for k in range(g.zl.size - 1)
                ]
                for j in range(g.yl.size - 1)
            ]
        )

        def in_gangway(j: int, k: int, zc_end: np.ndarray = zc_end) -> bool:
            return abs(yc[j]) < p.gangway_width / 2.0 and zc_end[j, k] < z_gw

        el.add_grid(grid, _G_END, in_gangway)


def _add_frame_beams(el: ElementLists, g: _Grid, panels: _Panels, openings: np.ndarray) -> None:
    """Beams along the panel edges: side sills, cant rails, the underframe longitudinal members
    under the air springs, end sills, then frames around the openings of both walls.
    """
    floor, wall_l, wall_r = panels.floor, panels.wall_left, panels.wall_right
    jl, jr = g.yl.size - 1, 0
    el.add_line(floor[:, jl], _B_SILL, (0.0, 1.0, 0.0))
    el.add_line(floor[:, jr], _B_SILL, (0.0, 1.0, 0.0))
    el.add_line(wall_l[:, -1], _B_CANT, (0.0, 1.0, 0.0))
    el.add_line(wall_r[:, -1], _B_CANT, (0.0, 1.0, 0.0))
    for j in g.j_air:
        el.add_line(floor[:, j], _B_LONG, (0.0, 1.0, 0.0))
    el.add_line(floor[0, :], _B_END, (1.0, 0.0, 0.0))
    el.add_line(floor[-1, :], _B_END, (1.0, 0.0, 0.0))
    for wall in (wall_l, wall_r):
        _add_opening_frames(el, wall, openings)


def _add_opening_frames(el: ElementLists, wall: np.ndarray, mask: np.ndarray) -> None:
    """Posts and headers / sills around the openings of one wall: each edge of an opening cell
    that borders a solid cell (or the floor) gets a beam.
    """
    nx1, nz1 = mask.shape
    for i in range(nx1):
        for k in range(nz1):
            if not mask[i, k]:
                continue
            if i == 0 or not mask[i - 1, k]:
                el.add_line([wall[i, k], wall[i, k + 1]], _B_FRAME, (1.0, 0.0, 0.0))
            if i == nx1 - 1 or not mask[i + 1, k]:
                el.add_line([wall[i + 1, k], wall[i + 1, k + 1]], _B_FRAME, (1.0, 0.0, 0.0))
            if k == nz1 - 1 or not mask[i, k + 1]:
                el.add_line([wall[i, k + 1], wall[i + 1, k + 1]], _B_FRAME, (0.0, 0.0, 1.0))
            if k > 0 and not mask[i, k - 1]:
                el.add_line([wall[i, k], wall[i + 1, k]], _B_FRAME, (0.0, 0.0, 1.0))


def _add_bolsters(el: ElementLists, reg: NodeRegistry, p: CarBodyParams, g: _Grid,
                  panels: _Panels) -> dict[str, int]:
    """A bolster at each bogie centre: a transverse beam at the air-spring height
    (``underframe_height``, m) hung from the floor by stiff webs.

    Returns
    -------
    dict of str to int
        The air-spring seats ``as1L``, ``as1R`` and the centre pivot ``bogie1`` of the front
        bolster, then those of the rear one (``…2``).
    """
    lc = p.bogie_spacing / 2.0
    named: dict[str, int] = {}
    for xb, tag in ((lc, "1"), (-lc, "2")):
        ib = int(np.argmin(np.abs(g.xs - xb)))
        bol = [reg.node(g.xs[ib], y, p.underframe_height, _UNDER) for y in g.yl]
        el.add_line(bol, _B_BOLSTER, (1.0, 0.0, 0.0))
        for j, nb in enumerate(bol):
            el.add_line([nb, panels.floor[ib, j]], _B_WEB, (1.0, 0.0, 0.0))
        named[f"as{tag}L"] = bol[g.j_air[0]]
        named[f"as{tag}R"] = bol[g.j_air[1]]
        named[f"bogie{tag}"] = bol[int(np.argmin(np.abs(g.yl)))]
    return named


def _add_output_nodes(named: dict[str, int], p: CarBodyParams, g: _Grid,
                      panels: _Panels) -> list[str]:
    """Name the paper's points (roof and floor nodes above the bogie centres, the floor at the
    centre, above the rear air springs) and a floor grid (x every 1 m from −9 to +9 m, y at
    −1.0, −0.5, 0, 0.5, 1.0 m: ``F<ix>_<iy>``) in ``named``; returns the grid's names.
    """
    L2, lc = p.length / 2.0, p.bogie_spacing / 2.0
    floor, roof, xs, yl = panels.floor, panels.roof, g.xs, g.yl
    j0 = int(np.argmin(np.abs(yl)))
    i_front, i_rear, i_mid = (int(np.argmin(np.abs(xs - v))) for v in (lc, -lc, 0.0))
    named["PR"] = int(roof[i_front, j0])
    named["PFB"] = int(floor[i_front, j0])
    named["PC"] = int(floor[i_mid, j0])
    named["PRB"] = int(floor[i_rear, j0])
    named["PLA"] = int(floor[i_rear, g.j_air[0]])
    named["PRA"] = int(floor[i_rear, g.j_air[1]])
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
    return grid_names


def _shell_sections(p: CarBodyParams) -> list[ShellSection]:
    """Double-skin sections of the :data:`SHELL_GROUPS` (face and depth in m)."""
    return [
        ShellSection(p.floor_face, p.floor_depth, p.web_fraction),
        ShellSection(p.wall_face, p.wall_depth, p.web_fraction),
        ShellSection(p.roof_face, p.roof_depth, p.web_fraction),
        ShellSection(p.end_face, p.end_depth, p.web_fraction),
    ]


def _beam_sections(bs: float) -> list[BeamSection]:
    """Box sections of the :data:`BEAM_GROUPS` (m), stiffness scaled by ``bs``; the bolster
    webs at least four times the bolster.
    """
    return [
        _box(0.15, 0.25, 6e-3, bs),  # side sill
        _box(0.12, 0.12, 4e-3, bs),  # cant rail
        _box(0.12, 0.16, 5e-3, bs),  # underframe longitudinal member
        _box(0.15, 0.20, 6e-3, bs),  # end sill
        _box(0.10, 0.08, 5e-3, bs),  # door / window frame
        _box(0.30, 0.20, 12e-3, bs),  # bolster
        _box(0.30, 0.20, 12e-3, max(bs, 1.0) * 4.0),  # bolster web (stiff, short)
    ]


def grid_z(reg: NodeRegistry, i: int) -> float:
    """Z coordinate of node ``i`` of a registry."""
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

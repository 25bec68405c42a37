"""Beam model of an H-type bogie frame (welded steel box side beams, tubular cross beams).

Model axes: x forward from the bogie centre, y to the left, z up from top of rail. The beam
axes lie in the horizontal plane at the frame's CG height; the axle-box spring seats (below) and
the air-spring seats (above) hang on short stiff, massless links. Motors, gearboxes, brake units
and brackets are non-structural point masses on the side and cross beams, distributed by
:mod:`flexride.fem.massmatch` to match mass and inertias.

Note on the paper's frame inertias (Table 4: 1.194 / 0.876 / 2.099 t·m²): they give
``Izz > Ixx + Iyy`` (by 0.7 %), which no real body can have, since ``Ixx + Iyy - Izz = 2 Σ m z²``.
A flat frame (all mass in the beam plane) is the closest real body: the least-squares fit
then misses each inertia by about 0.7 %.
"""

from __future__ import annotations

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
from flexride.fem.pyfe3d_adapter import STEEL, BeamSection, Material, Mesh, assemble
from flexride.fem.rigid import mass_properties

REGIONS = ("side_beam", "cross_beam", "centre", "seat")
_SIDE, _CROSS, _CENTRE, _SEAT = range(4)

#: Stiff, practically massless material of the spring-seat links.
RIGID_LINK = Material(E=2.0e12, nu=0.3, rho=1.0)


@dataclass(frozen=True)
class FrameParams:
    """Parameters of the bogie-frame model (m; section sizes m)."""

    wheelbase: float = 2.2
    primary_y: float = 1.0
    primary_height: float = 0.50
    air_spring_y: float = 0.95
    air_spring_height: float = 0.90
    beam_height: float = 0.65
    side_beam_overhang: float = 0.35
    cross_beam_x: float = 0.30
    side_beam_width: float = 0.22
    side_beam_depth: float = 0.25
    side_beam_wall: float = 0.010
    cross_beam_diameter: float = 0.18
    cross_beam_wall: float = 0.012
    stiffness_scale: float = 1.0

    def to_dict(self) -> dict:
        """JSON-able dict."""
        return asdict(self)

    def with_values(self, **kw) -> FrameParams:
        """Copy with some fields replaced."""
        return replace(self, **kw)


def build_frame(
    params: FrameParams, target: InertiaTarget | None, element_size: float = 0.1
) -> FEModel:
    """Generate the bogie-frame FE model.

    Parameters
    ----------
    params : FrameParams
        Geometry and sections.
    target : InertiaTarget or None
        Mass, CG and inertias to match with non-structural mass (None: bare structure).
    element_size : float
        Largest beam element length (m).

    Returns
    -------
    FEModel
    """
    p = params
    h = float(element_size)
    reg = NodeRegistry()
    el = ElementLists()
    named = _add_side_beams(el, reg, p, h)
    _add_cross_beams(el, reg, p, h)
    named["centre"] = reg.node(0.0, 0.0, p.beam_height, _CENTRE)
    mesh = Mesh(
        nodes=reg.array(),
        beams=np.asarray(el.beams, dtype=np.int64),
        beam_group=np.asarray(el.beam_group, dtype=np.int64),
        beam_vxy=np.asarray(el.beam_vxy, dtype=float),
    )
    model = FEModel(
        name="frame",
        mesh=mesh,
        beam_sections=_sections(p),
        beam_group_names=["side_beam", "cross_beam", "centre_bracket", "seat_link"],
        named_nodes=named,
        node_region=np.asarray(reg.region, dtype=np.int64),
        region_names=list(REGIONS),
        info={"params": p.to_dict(), "element_size": h},
    )
    if target is not None:
        _add_nonstructural_mass(model, target)
    return model


_B_SIDE, _B_CROSS, _B_CENTRE, _B_LINK = range(4)


def _add_side_beams(el: ElementLists, reg: NodeRegistry, p: FrameParams,
                    h: float) -> dict[str, int]:
    """The left and right side beams (elements at most ``h`` m long, with nodes at the axles,
    the centre and the cross beams), each with links down to its two axle-box spring seats and
    up to its air-spring seat.

    Returns
    -------
    dict of str to int
        The seats by name: ``ab1L``, ``ab2L``, ``asL``, then ``ab1R``, ``ab2R``, ``asR``.
    """
    a = p.wheelbase / 2.0
    xe = a + p.side_beam_overhang
    zb = p.beam_height
    xs = mesh_lines(-xe, xe, h, (-a, a, 0.0, -p.cross_beam_x, p.cross_beam_x))
    named: dict[str, int] = {}
    for side, yv in (("L", p.primary_y), ("R", -p.primary_y)):
        line = [reg.node(x, yv, zb, _SIDE) for x in xs]
        el.add_line(line, _B_SIDE, (0.0, 1.0, 0.0))
        for ax, tag in ((a, "1"), (-a, "2")):
            top = reg.node(ax, yv, zb, _SIDE)
            seat = reg.node(ax, yv, p.primary_height, _SEAT)
            el.add_line([top, seat], _B_LINK, (1.0, 0.0, 0.0))
            named[f"ab{tag}{side}"] = seat
        top = reg.node(0.0, yv, zb, _SIDE)
        ya = p.air_spring_y if side == "L" else -p.air_spring_y
        seat = reg.node(0.0, ya, p.air_spring_height, _SEAT)
        el.add_line([top, seat], _B_LINK, (1.0, 0.0, 0.0))
        named[f"as{side}"] = seat
    return named


def _add_cross_beams(el: ElementLists, reg: NodeRegistry, p: FrameParams, h: float) -> None:
    """The two cross beams between the side beams and the centre bracket between the cross
    beams (elements at most ``h`` m long).
    """
    zb = p.beam_height
    ys = mesh_lines(-p.primary_y, p.primary_y, h, (0.0,))
    for xc in (p.cross_beam_x, -p.cross_beam_x):
        line = [reg.node(xc, y, zb, _CROSS) for y in ys]
        el.add_line(line, _B_CROSS, (1.0, 0.0, 0.0))
    xcen = mesh_lines(-p.cross_beam_x, p.cross_beam_x, h, (0.0,))
    el.add_line([reg.node(x, 0.0, zb, _CENTRE) for x in xcen], _B_CENTRE, (0.0, 1.0, 0.0))


def _sections(p: FrameParams) -> list[BeamSection]:
    """Sections of the side beams (steel box), cross beams (steel tube), centre bracket and
    seat links (stiff, practically massless), stiffness scaled by ``stiffness_scale``.
    """
    s = p.stiffness_scale
    return [
        BeamSection.box(p.side_beam_width, p.side_beam_depth, p.side_beam_wall, STEEL).scaled(s),
        BeamSection.tube(p.cross_beam_diameter, p.cross_beam_wall, STEEL).scaled(s),
        BeamSection.box(0.20, 0.20, 0.010, STEEL).scaled(s),
        BeamSection(A=0.02, Iyy=2e-4, Izz=2e-4, J=4e-4, material=RIGID_LINK),
    ]


def _add_nonstructural_mass(model: FEModel, target: InertiaTarget) -> None:
    mesh = model.mesh
    x = mesh.nodes
    _, M = assemble(mesh, [], model.beam_sections)
    structure = mass_properties(M, x)
    nsm = max(target.mass - structure.mass, 0.0)
    groups: list[MassGroup] = []
    reg = model.node_region
    ax, ay = np.abs(x[:, 0]), np.abs(x[:, 1])
    xmax = ax[reg == _SIDE].max()
    for b0, b1 in zip(np.linspace(0, 1, 5)[:-1], np.linspace(0, 1, 5)[1:], strict=False):
        sel = np.flatnonzero((reg == _SIDE) & (ax >= b0 * xmax - 1e-9) & (ax < b1 * xmax + 1e-9))
        groups.append(_group(f"side.{b0:.2f}-{b1:.2f}", "side", sel, 0.4 * nsm / 4))
    ymax = ay[reg == _CROSS].max()
    for b0, b1 in zip(np.linspace(0, 1, 4)[:-1], np.linspace(0, 1, 4)[1:], strict=False):
        sel = np.flatnonzero((reg == _CROSS) & (ay >= b0 * ymax - 1e-9) & (ay < b1 * ymax + 1e-9))
        groups.append(_group(f"cross.{b0:.2f}-{b1:.2f}", "cross", sel, 0.5 * nsm / 3))
    sel = np.flatnonzero(reg == _CENTRE)
    groups.append(_group("centre", "centre", sel, 0.1 * nsm))
    groups = [g for g in groups if g.nodes.size]
    masses = solve_group_masses(x, groups, structure, target, weight=1.0e3)
    n_, m_, o_ = groups_to_point_masses(groups, masses)
    mesh.mass_nodes, mesh.mass_values, mesh.mass_offsets = n_, m_, o_
    model.info["structural_mass_kg"] = float(structure.mass)
    model.info["mass_groups_kg"] = {
        g.name: round(float(mg), 3) for g, mg in zip(groups, masses, strict=False)
    }


def _group(name: str, kind: str, nodes: np.ndarray, prior: float) -> MassGroup:
    n = max(nodes.size, 1)
    return MassGroup(
        name, kind, nodes, np.full(nodes.size, 1.0 / n), np.zeros((nodes.size, 3)), prior
    )

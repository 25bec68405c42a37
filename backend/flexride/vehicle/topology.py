"""Vehicle topology: bodies, suspension elements at their real positions, output points.

Bodies (front to rear): ``carbody``; ``frame1`` (front bogie), ``frame2`` (rear bogie);
``wheelset1`` … ``wheelset4``. Each body's reference frame follows the track at the body's own
position along the line (DESIGN §3.2). Suspension elements are three-directional spring–dampers
(plus optional rotational springs) between two markers that coincide in the nominal geometry,
so roll, pitch and yaw coupling follows from where the elements sit.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flexride.bodies import ModalBody, rigid_body
from flexride.scenario.solver import Output, OutputPoint
from flexride.scenario.vehicle import Vehicle


@dataclass(frozen=True)
class PaperPoint:
    """One of the paper's car-body measurement points (DESIGN §5) and where it sits.

    Attributes
    ----------
    name : str
        The point's name (channels ``carbody.<name>.acc.<y|z>``).
    description : str
        One line for people.
    along : {"front", "centre", "rear"}
        Above the front bogie centre, at the body centre or above the rear bogie centre.
    across : {"centre", "left", "right"}
        On the centre line or above the left/right air spring.
    level : {"floor", "roof"}
        On the floor (``output.floor_height_m``) or the roof (``output.roof_height_m``).
    """

    name: str
    description: str
    along: str
    across: str
    level: str


PAPER_POINTS: tuple[PaperPoint, ...] = (
    PaperPoint("PR", "roof above the front bogie centre", "front", "centre", "roof"),
    PaperPoint("PFB", "floor above the front bogie centre (the paper's PB)", "front", "centre",
               "floor"),
    PaperPoint("PC", "floor at the car-body centre", "centre", "centre", "floor"),
    PaperPoint("PRB", "floor above the rear bogie centre", "rear", "centre", "floor"),
    PaperPoint("PLA", "floor above the rear bogie's left air spring", "rear", "left", "floor"),
    PaperPoint("PRA", "floor above the rear bogie's right air spring", "rear", "right", "floor"),
)
"""The paper's points in channel order: the one list every layer reads (via the recorded
points of a run, or ``GET /api/v1/schemas/points``)."""
PAPER_POINT_NAMES = tuple(p.name for p in PAPER_POINTS)
"""Names of :data:`PAPER_POINTS`, in order."""
FLOOR_TOLERANCE_M = 0.05
"""A user point this close to the floor height counts as a floor point (ISO 2631 floor
weighting rather than seat)."""


@dataclass
class SuspensionElement:
    """Linear spring–damper between marker ``marker_a`` of body ``body_a`` and ``marker_b`` of
    ``body_b``. Stiffness and damping are given for the six relative motions (x, y, z in N/m and
    N·s/m; roll, pitch, yaw in N·m/rad and N·m·s/rad), in the track frame of body A.
    """

    name: str
    body_a: int
    marker_a: str
    body_b: int
    marker_b: str
    stiffness: np.ndarray
    damping: np.ndarray


@dataclass
class VehicleModel:
    """Bodies, suspension elements and recorded points of one vehicle."""

    bodies: list[ModalBody]
    elements: list[SuspensionElement]
    wheelsets: list[int]
    points: list[tuple[str, int, str]] = field(default_factory=list)
    recorded: list[RecordedPoint] = field(default_factory=list)
    rolling_circle_half_distance: float = 0.7465
    wheel_radius: float = 0.42

    @property
    def total_mass(self) -> float:
        """Mass of the whole vehicle (kg)."""
        return float(sum(b.mass for b in self.bodies))


def _six(k3: tuple[float, float, float], kr: tuple[float, float, float] = (0.0, 0.0, 0.0)):
    return np.array([*k3, *kr], dtype=float)


#: Extent of the floor used for comfort-map grids (half length, half width) (m).
FLOOR_HALF_LENGTH = 9.0
FLOOR_HALF_WIDTH = 1.2


def floor_grid(spacing: float) -> list[tuple[str, tuple[float, float]]]:
    """Names ``F<i>_<j>`` and (x, y) positions (m) of a floor grid with the given spacing."""
    nx = int(np.floor(2 * FLOOR_HALF_LENGTH / spacing + 1e-9)) + 1
    ny = int(np.floor(2 * FLOOR_HALF_WIDTH / spacing + 1e-9)) + 1
    xs = np.linspace(-FLOOR_HALF_LENGTH, FLOOR_HALF_LENGTH, nx)
    ys = np.linspace(-FLOOR_HALF_WIDTH, FLOOR_HALF_WIDTH, ny) if ny > 1 else np.zeros(1)
    return [(f"F{i}_{j}", (float(x), float(y))) for i, x in enumerate(xs)
            for j, y in enumerate(ys)]


def paper_point_positions(params: Vehicle, output: Output) -> list[OutputPoint]:
    """The paper's points :data:`PAPER_POINTS` in car-body coordinates (m)."""
    lc = params.geometry.bogie_centre_spacing / 2.0
    ys = params.geometry.secondary_lateral_half_spacing
    x = {"front": lc, "centre": 0.0, "rear": -lc}
    y = {"centre": 0.0, "left": ys, "right": -ys}
    z = {"floor": output.floor_height_m, "roof": output.roof_height_m}
    return [OutputPoint(name=p.name, x=x[p.along], y=y[p.across], z=z[p.level])
            for p in PAPER_POINTS]


def carbody_output_points(params: Vehicle, output: Output) -> list[OutputPoint]:
    """Every recorded car-body point, in the order of its channels: the paper's points, the user
    points of ``output.points`` and the floor grid (``output.floor_grid_spacing_m``).

    Coordinates are car-body coordinates (m): x from the body centre, forward positive; y left
    positive; z above top of rail.

    Raises
    ------
    ValueError
        If a name is used twice.
    """
    pts = paper_point_positions(params, output) + list(output.points)
    if output.floor_grid_spacing_m:
        fl = output.floor_height_m
        pts += [OutputPoint(name=name, x=x, y=y, z=fl)
                for name, (x, y) in floor_grid(output.floor_grid_spacing_m)]
    names: set[str] = set()
    for pt in pts:
        if pt.name in names:
            raise ValueError(f"output point {pt.name!r} is defined twice")
        names.add(pt.name)
    return pts


@dataclass(frozen=True)
class RecordedPoint:
    """A point whose accelerations are recorded (channels ``<body>.<name>.acc.<y|z>``).

    Attributes
    ----------
    body, name : str
        Body and point name.
    description : str
        One line for people (the paper's points say which of the paper's points they are).
    x, y, z : float
        Position in the nominal vehicle geometry (m): x from the car-body centre, forward
        positive; y left positive; z above top of rail. For car-body points these are car-body
        coordinates; a frame's or wheelset's ``centre`` is its centre of gravity.
    on_floor : bool or None
        Whether the point is on the car-body floor (ISO 2631 / EN 12299 floor measurement);
        None for points off the car body.
    kind : {"paper", "user", "grid", "body"}
        One of the paper's points, a user point, a floor-grid point (comfort maps), or the
        centre of a frame or wheelset.
    """

    body: str
    name: str
    description: str
    x: float
    y: float
    z: float
    on_floor: bool | None
    kind: str

    @property
    def position(self) -> tuple[float, float, float]:
        """``(x, y, z)`` in m."""
        return (self.x, self.y, self.z)

    def to_dict(self) -> dict[str, Any]:
        """The JSON form (as in result files and the API)."""
        return {"body": self.body, "name": self.name, "description": self.description,
                "x": self.x, "y": self.y, "z": self.z, "on_floor": self.on_floor,
                "kind": self.kind}


def _carbody_point(pt: OutputPoint, output: Output, kind: str) -> RecordedPoint:
    paper = next((p for p in PAPER_POINTS if p.name == pt.name), None) if kind == "paper" else None
    if paper is not None:
        text, floor = f"{paper.name}: {paper.description}", paper.level == "floor"
    elif kind == "grid":
        text, floor = "floor grid point (comfort map)", True
    else:
        floor = abs(pt.z - output.floor_height_m) <= FLOOR_TOLERANCE_M
        text = f"user point, {'on the floor' if floor else f'{pt.z:g} m above top of rail'}"
    return RecordedPoint("carbody", pt.name, text, pt.x, pt.y, pt.z, floor, kind)


def recorded_points(params: Vehicle, output: Output | None = None) -> list[RecordedPoint]:
    """The recorded points of the vehicle in channel order: those :func:`build_vehicle` makes
    (the car-body points of :func:`carbody_output_points`, then the centres of ``frame1``,
    ``frame2`` and ``wheelset1`` … ``wheelset4``).

    Parameters
    ----------
    params : Vehicle
        Vehicle parameters (geometry, CG heights).
    output : Output, optional
        Output settings (floor and roof heights, user points, floor grid).

    Returns
    -------
    list of RecordedPoint
    """
    return build_vehicle(params, output).recorded


def build_vehicle(
    params: Vehicle,
    output: Output | None = None,
    carbody: ModalBody | None = None,
    frames: tuple[ModalBody, ModalBody] | None = None,
) -> VehicleModel:
    """Build the 7-body metro vehicle from its parameters.

    Parameters
    ----------
    params : Vehicle
        Validated vehicle parameters.
    output : Output, optional
        Output settings (floor/roof heights, user points).
    carbody, frames : ModalBody, optional
        Flexible replacements for the rigid car body / bogie frames (same names and reference
        positions); markers are added to them here.

    Returns
    -------
    VehicleModel
    """
    output = output or Output()
    g = params.geometry
    bodies = _bodies(params, carbody, frames)
    rates = _SuspensionRates.of(params)
    elements: list[SuspensionElement] = []
    for jf, i_f in enumerate(_I_FRAMES):
        elements += _secondary_suspension(params, bodies, jf, i_f, rates)
        elements += _optional_elements(params, bodies, jf, i_f)
        elements += _primary_suspension(params, bodies, jf, i_f, rates)
    points, recorded = _recorded_points(params, output, bodies)
    return VehicleModel(
        bodies=bodies,
        elements=elements,
        wheelsets=list(_I_WHEELSETS),
        points=points,
        recorded=recorded,
        rolling_circle_half_distance=g.rolling_circle_half_distance,
        wheel_radius=g.wheel_radius,
    )


#: Indices of the bodies in :attr:`VehicleModel.bodies`.
_I_CARBODY = 0
_I_FRAMES = (1, 2)
_I_WHEELSETS = (3, 4, 5, 6)


def _bodies(params: Vehicle, carbody: ModalBody | None,
            frames: tuple[ModalBody, ModalBody] | None) -> list[ModalBody]:
    """The seven bodies front to rear: the car body at x = 0, the frames at ± half the bogie
    spacing, the wheelsets at ± half the wheelbase from their frame (m); rigid unless flexible
    replacements are given.
    """
    g = params.geometry
    lc = g.bogie_centre_spacing / 2.0
    lw = g.wheelbase / 2.0
    cb, fr, ws = params.carbody, params.frame, params.wheelset
    bodies: list[ModalBody] = []
    bodies.append(
        carbody or rigid_body("carbody", cb.mass, (cb.ixx, cb.iyy, cb.izz), 0.0, cb.cg_height)
    )
    frame_x = (lc, -lc)
    for i, x in enumerate(frame_x):
        if frames is not None:
            bodies.append(frames[i])
        else:
            bodies.append(
                rigid_body(f"frame{i + 1}", fr.mass, (fr.ixx, fr.iyy, fr.izz), x, fr.cg_height)
            )
    ws_x = (lc + lw, lc - lw, -lc + lw, -lc - lw)
    for i, x in enumerate(ws_x):
        bodies.append(
            rigid_body(
                f"wheelset{i + 1}",
                ws.mass,
                (ws.ixx, ws.iyy, ws.izz),
                x,
                ws.cg_height,
                is_wheelset=True,
            )
        )
    return bodies


@dataclass(frozen=True)
class _SuspensionRates:
    """Six-component stiffness (N/m, N·m/rad) and damping (N·s/m, N·m·s/rad) of the primary
    and secondary suspension elements (translations only; rotations zero).
    """

    k_prim: np.ndarray
    c_prim: np.ndarray
    k_sec: np.ndarray
    c_sec: np.ndarray

    @classmethod
    def of(cls, params: Vehicle) -> _SuspensionRates:
        """The rates of the vehicle's primary and secondary suspension."""
        p, s = params.primary, params.secondary
        return cls(k_prim=_six((p.kx, p.ky, p.kz)), c_prim=_six((p.cx, p.cy, p.cz)),
                   k_sec=_six((s.kx, s.ky, s.kz)), c_sec=_six((s.cx, s.cy, s.cz)))


def _secondary_suspension(params: Vehicle, bodies: list[ModalBody], jf: int, i_f: int,
                          rates: _SuspensionRates) -> list[SuspensionElement]:
    """The air springs of bogie ``jf`` (0 front, 1 rear; frame body ``i_f``), left and right,
    at the secondary height and lateral half spacing (m), with their markers ``as<n><L|R>`` on
    the car body and the frame; then the bogie-centre markers ``bogie<n>`` (pivot).
    """
    g = params.geometry
    carbody_body, frame = bodies[_I_CARBODY], bodies[i_f]
    xf = frame.x_ref
    elements = []
    for side, ys in (
        ("L", g.secondary_lateral_half_spacing),
        ("R", -g.secondary_lateral_half_spacing),
    ):
        m_c = f"as{jf + 1}{side}"
        carbody_body.add_marker(
            m_c, (xf - carbody_body.x_ref, ys, g.secondary_height - carbody_body.cg_height)
        )
        frame.add_marker(m_c, (0.0, ys, g.secondary_height - frame.cg_height))
        elements.append(
            SuspensionElement(f"secondary.{jf + 1}{side}", _I_CARBODY, m_c, i_f, m_c,
                              rates.k_sec.copy(), rates.c_sec.copy())
        )
    centre = f"bogie{jf + 1}"
    carbody_body.add_marker(
        centre, (xf - carbody_body.x_ref, 0.0, g.secondary_height - carbody_body.cg_height)
    )
    frame.add_marker(centre, (0.0, 0.0, g.secondary_height - frame.cg_height))
    return elements


def _optional_elements(params: Vehicle, bodies: list[ModalBody], jf: int,
                       i_f: int) -> list[SuspensionElement]:
    """The optional elements of bogie ``jf`` (frame body ``i_f``) whose rate is not zero: the
    anti-roll bar (roll stiffness N·m/rad at the bogie centre), the secondary lateral damper
    (N·s/m at its height) and the yaw dampers left and right (N·s/m), with their markers.
    """
    g, o = params.geometry, params.optional
    carbody_body, frame = bodies[_I_CARBODY], bodies[i_f]
    xf = frame.x_ref
    elements = []
    centre = f"bogie{jf + 1}"
    if o.anti_roll_bar_stiffness > 0.0:
        elements.append(
            SuspensionElement(
                f"anti_roll_bar.{jf + 1}",
                _I_CARBODY,
                centre,
                i_f,
                centre,
                _six((0.0, 0.0, 0.0), (o.anti_roll_bar_stiffness, 0.0, 0.0)),
                np.zeros(6),
            )
        )
    if o.secondary_lateral_damper > 0.0:
        m = f"latdamper{jf + 1}"
        carbody_body.add_marker(
            m,
            (
                xf - carbody_body.x_ref,
                0.0,
                o.secondary_lateral_damper_height - carbody_body.cg_height,
            ),
        )
        frame.add_marker(m, (0.0, 0.0, o.secondary_lateral_damper_height - frame.cg_height))
        elements.append(
            SuspensionElement(
                f"lateral_damper.{jf + 1}",
                _I_CARBODY,
                m,
                i_f,
                m,
                np.zeros(6),
                _six((0.0, o.secondary_lateral_damper, 0.0)),
            )
        )
    if o.yaw_damper > 0.0:
        for side, ys in (
            ("L", o.yaw_damper_lateral_half_spacing),
            ("R", -o.yaw_damper_lateral_half_spacing),
        ):
            m = f"yawdamper{jf + 1}{side}"
            carbody_body.add_marker(
                m, (xf - carbody_body.x_ref, ys, g.secondary_height - carbody_body.cg_height)
            )
            frame.add_marker(m, (0.0, ys, g.secondary_height - frame.cg_height))
            elements.append(
                SuspensionElement(
                    f"yaw_damper.{jf + 1}{side}",
                    _I_CARBODY,
                    m,
                    i_f,
                    m,
                    np.zeros(6),
                    _six((o.yaw_damper, 0.0, 0.0)),
                )
            )
    return elements


def _primary_suspension(params: Vehicle, bodies: list[ModalBody], jf: int, i_f: int,
                        rates: _SuspensionRates) -> list[SuspensionElement]:
    """The axle-box springs of bogie ``jf`` (frame body ``i_f``): two per wheelset, left and
    right at the primary height and lateral half spacing (m), with markers
    ``<wheelset>.axlebox<L|R>`` on the frame and ``axlebox<L|R>`` on the wheelset (pitch
    locked: the wheelset's pitch coordinate is its spin).
    """
    g = params.geometry
    frame = bodies[i_f]
    elements = []
    for i_w in _I_WHEELSETS[2 * jf : 2 * jf + 2]:
        wheelset = bodies[i_w]
        dx = wheelset.x_ref - frame.x_ref
        for side, ys in (
            ("L", g.primary_lateral_half_spacing),
            ("R", -g.primary_lateral_half_spacing),
        ):
            m = f"axlebox{side}"
            m_f = f"{wheelset.name}.{m}"
            frame.add_marker(m_f, (dx, ys, g.primary_height - frame.cg_height))
            wheelset.add_marker(
                m, (0.0, ys, g.primary_height - wheelset.cg_height), lock_pitch=True
            )
            elements.append(
                SuspensionElement(
                    f"primary.{wheelset.name}.{side}",
                    i_f,
                    m_f,
                    i_w,
                    m,
                    rates.k_prim.copy(),
                    rates.c_prim.copy(),
                )
            )
    return elements


def _recorded_points(params: Vehicle, output: Output, bodies: list[ModalBody]) -> tuple[
        list[tuple[str, int, str]], list[RecordedPoint]]:
    """Markers ``point.<name>`` for the car-body output points, then a ``centre`` marker on
    each frame and wheelset.

    Returns
    -------
    points : list of (str, int, str)
        Point name, body index and marker, for the kernel.
    recorded : list of RecordedPoint
        The same points for everyone else (positions in m).
    """
    carbody_body = bodies[_I_CARBODY]
    points: list[tuple[str, int, str]] = []
    recorded: list[RecordedPoint] = []
    n_paper, n_user = len(PAPER_POINTS), len(output.points)
    for k, pt in enumerate(carbody_output_points(params, output)):
        marker = f"point.{pt.name}"
        carbody_body.add_marker(
            marker, (pt.x - carbody_body.x_ref, pt.y, pt.z - carbody_body.cg_height)
        )
        points.append((pt.name, _I_CARBODY, marker))
        kind = "paper" if k < n_paper else "user" if k < n_paper + n_user else "grid"
        recorded.append(_carbody_point(pt, output, kind))
    for i in (*_I_FRAMES, *_I_WHEELSETS):
        b = bodies[i]
        b.add_marker("centre", (0.0, 0.0, 0.0), lock_pitch=b.is_wheelset)
        points.append(("centre", i, "centre"))
        recorded.append(RecordedPoint(b.name, "centre", f"centre of gravity of {b.name}",
                                      b.x_ref, 0.0, b.cg_height, None, "body"))
    return points, recorded

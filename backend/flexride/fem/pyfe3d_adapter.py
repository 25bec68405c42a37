"""The one module that talks to pyfe3d: element matrices and sparse assembly.

Everything else in :mod:`flexride.fem` sees a mesh as plain NumPy arrays (:class:`Mesh`) and
gets SciPy sparse matrices back. Elements used: pyfe3d ``Quad4`` (four-node shell, first-order
shear deformation, physics-based drilling stiffness), ``BeamC`` (two-node Timoshenko beam with
consistent mass) and ``Spring`` (six-component spring between two nodes). Lumped masses with an
offset from their node (like Nastran's CONM2) are added here too.

DOF order: six per node (ux, uy, uz, rx, ry, rz), node after node, so the DOF of component ``c``
of node ``i`` is ``6*i + c``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pyfe3d
import scipy.sparse as sp
from pyfe3d import (
    DOF,
    INT,
    BeamC,
    BeamCData,
    BeamCProbe,
    Quad4,
    Quad4Data,
    Quad4Probe,
    Spring,
    SpringData,
    SpringProbe,
)
from pyfe3d.beamprop import BeamProp
from pyfe3d.shellprop_utils import isotropic_plate, laminated_plate

PYFE3D_VERSION: str = pyfe3d.__version__


@dataclass(frozen=True)
class Material:
    """Linear elastic isotropic material.

    Attributes
    ----------
    E : float
        Young's modulus (Pa).
    nu : float
        Poisson's ratio (-).
    rho : float
        Density (kg/m³).
    """

    E: float
    nu: float
    rho: float

    @property
    def G(self) -> float:
        """Shear modulus (Pa)."""
        return self.E / (2.0 * (1.0 + self.nu))


#: Aluminium alloy of car-body extrusions (EN AW-6005A-T6).
ALUMINIUM = Material(E=70.0e9, nu=0.33, rho=2700.0)
#: Structural steel of bogie frames (S355).
STEEL = Material(E=206.0e9, nu=0.30, rho=7850.0)


@dataclass(frozen=True)
class ShellSection:
    """Shell section: a solid plate or a double-skin (hollow) extrusion.

    A double-skin extrusion (``depth > 0``) is modelled as a three-ply laminate: two face sheets
    of thickness ``face`` and a core of depth ``depth - 2*face`` whose webs are smeared into an
    isotropic layer with modulus and density scaled by ``web_fraction`` (web thickness over web
    pitch). With ``depth == 0`` the section is a solid plate of thickness ``face``.

    Attributes
    ----------
    face : float
        Face-sheet thickness (m) or plate thickness when ``depth == 0``.
    depth : float
        Overall depth of the extrusion (m); 0 for a solid plate.
    web_fraction : float
        Smeared web fraction of the core (-).
    material : Material
        Material of faces and webs.
    """

    face: float
    depth: float = 0.0
    web_fraction: float = 0.04
    material: Material = ALUMINIUM

    def to_pyfe3d(self):
        """The pyfe3d ``ShellProp`` of this section."""
        m = self.material
        if self.depth <= 0.0:
            return isotropic_plate(thickness=self.face, E=m.E, nu=m.nu, rho=m.rho)
        core = max(self.depth - 2.0 * self.face, 1e-6)
        ec = m.E * self.web_fraction
        return laminated_plate(
            stack=[0.0, 0.0, 0.0],
            plyts=[self.face, core, self.face],
            laminaprops=[(m.E, m.nu), (ec, m.nu), (m.E, m.nu)],
            rhos=[m.rho, m.rho * self.web_fraction, m.rho],
        )

    @property
    def mass_per_area(self) -> float:
        """Mass per unit area (kg/m²)."""
        m = self.material
        if self.depth <= 0.0:
            return m.rho * self.face
        core = max(self.depth - 2.0 * self.face, 1e-6)
        return m.rho * (2.0 * self.face + self.web_fraction * core)


@dataclass(frozen=True)
class BeamSection:
    """Beam cross-section (thin-walled rectangular box or given properties).

    Attributes
    ----------
    A : float
        Area (m²).
    Iyy, Izz : float
        Second moments of area about the element y and z axes (m⁴).
    J : float
        Torsion constant (m⁴).
    material : Material
        Material.
    nsm : float
        Non-structural mass per unit length (kg/m).
    """

    A: float
    Iyy: float
    Izz: float
    J: float
    material: Material = ALUMINIUM
    nsm: float = 0.0

    @classmethod
    def box(
        cls, width: float, height: float, wall: float, material: Material = ALUMINIUM
    ) -> BeamSection:
        """Thin-walled rectangular tube ``width`` (element y) × ``height`` (element z) with
        wall thickness ``wall`` (all m); Bredt's formula for the torsion constant.
        """
        b, h, t = width, height, wall
        bi, hi = b - 2 * t, h - 2 * t
        area = b * h - bi * hi
        izz = (h * b**3 - hi * bi**3) / 12.0  # about z: y² integral (width direction)
        iyy = (b * h**3 - bi * hi**3) / 12.0
        am = (b - t) * (h - t)
        jt = 4.0 * am**2 * t / (2.0 * (b - t) + 2.0 * (h - t))
        return cls(A=area, Iyy=iyy, Izz=izz, J=jt, material=material)

    @classmethod
    def tube(cls, diameter: float, wall: float, material: Material = STEEL) -> BeamSection:
        """Circular tube of outer ``diameter`` and ``wall`` thickness (m)."""
        ro, ri = diameter / 2.0, diameter / 2.0 - wall
        area = np.pi * (ro**2 - ri**2)
        i = np.pi * (ro**4 - ri**4) / 4.0
        return cls(A=float(area), Iyy=float(i), Izz=float(i), J=float(2 * i), material=material)

    def scaled(self, stiffness: float = 1.0) -> BeamSection:
        """Copy with the stiffness properties (A, I, J) and structural mass scaled."""
        return BeamSection(
            A=self.A * stiffness,
            Iyy=self.Iyy * stiffness,
            Izz=self.Izz * stiffness,
            J=self.J * stiffness,
            material=self.material,
            nsm=self.nsm,
        )

    @property
    def mass_per_length(self) -> float:
        """Mass per unit length (kg/m)."""
        return self.material.rho * self.A + self.nsm

    def to_pyfe3d(self) -> BeamProp:
        """The pyfe3d ``BeamProp`` of this section (shear factor 5/6 for the shear areas)."""
        m = self.material
        p = BeamProp()
        p.A = self.A
        p.E = m.E
        p.G = m.G * 5.0 / 6.0
        p.GJ = m.G * self.J
        p.Iyy = self.Iyy
        p.Izz = self.Izz
        p.J = self.J
        rho = m.rho
        mpl = self.mass_per_length
        scale = mpl / (rho * self.A) if self.A > 0 else 1.0
        p.intrho = mpl
        p.intrhoy2 = rho * self.Izz * scale
        p.intrhoz2 = rho * self.Iyy * scale
        return p


@dataclass
class Mesh:
    """A finite-element mesh as plain arrays.

    Attributes
    ----------
    nodes : numpy.ndarray
        (n, 3) node coordinates (m).
    quads : numpy.ndarray
        (nq, 4) node indices of four-node shell elements (counter-clockwise about the normal).
    quad_group : numpy.ndarray
        (nq,) index into the list of shell sections.
    beams : numpy.ndarray
        (nb, 2) node indices of beam elements.
    beam_group : numpy.ndarray
        (nb,) index into the list of beam sections.
    beam_vxy : numpy.ndarray
        (nb, 3) vector in each beam's local x–y plane (orientation of the section).
    springs : numpy.ndarray
        (ns, 2) node indices of spring elements (global axes).
    spring_k : numpy.ndarray
        (ns, 6) stiffness of each spring: kx, ky, kz (N/m), krx, kry, krz (N·m/rad).
    mass_nodes : numpy.ndarray
        (nm,) node of each lumped mass.
    mass_values : numpy.ndarray
        (nm,) lumped mass values (kg).
    mass_offsets : numpy.ndarray
        (nm, 3) position of each lumped mass relative to its node (m).
    """

    nodes: np.ndarray
    quads: np.ndarray = field(default_factory=lambda: np.zeros((0, 4), dtype=np.int64))
    quad_group: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    beams: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))
    beam_group: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    beam_vxy: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    springs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))
    spring_k: np.ndarray = field(default_factory=lambda: np.zeros((0, 6)))
    mass_nodes: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    mass_values: np.ndarray = field(default_factory=lambda: np.zeros(0))
    mass_offsets: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))

    @property
    def n_nodes(self) -> int:
        """Number of nodes."""
        return int(self.nodes.shape[0])

    @property
    def n_dof(self) -> int:
        """Number of DOFs (6 per node)."""
        return DOF * self.n_nodes


#: Sparse triplets (rows, columns, values) of a part of a matrix.
_Triplets = tuple[np.ndarray, np.ndarray, np.ndarray]


def _coo(rows, cols, vals, n) -> sp.csc_matrix:
    mat = sp.coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsc()
    mat.sum_duplicates()
    return mat


def assemble(
    mesh: Mesh,
    shell_sections: list[ShellSection],
    beam_sections: list[BeamSection],
    lumped: bool = False,
) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    """Assemble the global stiffness and mass matrices.

    Parameters
    ----------
    mesh : Mesh
        The mesh.
    shell_sections, beam_sections : list
        Section of each shell / beam group (indexed by ``mesh.quad_group`` / ``beam_group``).
    lumped : bool
        Lumped element mass matrices instead of consistent ones.

    Returns
    -------
    K, M : scipy.sparse.csc_matrix
        Symmetric stiffness (N/m, N·m/rad) and mass (kg, kg·m²) matrices of size 6 × n_nodes.
    """
    n = mesh.n_dof
    x = np.ascontiguousarray(mesh.nodes, dtype=float).ravel()
    k_parts: list[_Triplets] = []
    m_parts: list[_Triplets] = []
    if len(mesh.quads):
        k, m = _quad_triplets(mesh, x, shell_sections, lumped)
        k_parts.append(k)
        m_parts.append(m)
    if len(mesh.beams):
        k, m = _beam_triplets(mesh, x, beam_sections, lumped)
        k_parts.append(k)
        m_parts.append(m)
    if len(mesh.springs):
        k_parts.append(_spring_triplets(mesh))
    if len(mesh.mass_nodes):
        m_parts.append(lumped_mass_triplets(mesh.mass_nodes, mesh.mass_values, mesh.mass_offsets))
    K = _matrix(k_parts, n)
    M = _matrix(m_parts, n)
    # remove round-off asymmetry
    K = ((K + K.T) * 0.5).tocsc()
    M = ((M + M.T) * 0.5).tocsc()
    return K, M


def _matrix(parts: list[_Triplets], n: int) -> sp.csc_matrix:
    """The n × n matrix of the sum of the triplets of ``parts`` (duplicates summed)."""
    def cat(k: int, dtype) -> np.ndarray:
        return np.concatenate([p[k] for p in parts]) if parts else np.zeros(0, dtype=dtype)

    return _coo(cat(0, INT), cat(1, INT), cat(2, float), n)


def _quad_triplets(mesh: Mesh, x: np.ndarray, shell_sections: list[ShellSection],
                   lumped: bool) -> tuple[_Triplets, _Triplets]:
    """Stiffness and mass triplets of the shells (pyfe3d ``Quad4``); ``x`` are the node
    coordinates (m), flattened. Lumped masses keep the 120 entries pyfe3d writes per element.
    """
    nq = len(mesh.quads)
    data = Quad4Data()
    probe = Quad4Probe()
    kr = np.zeros(data.KC0_SPARSE_SIZE * nq, dtype=INT)
    kc = np.zeros_like(kr)
    kv = np.zeros(data.KC0_SPARSE_SIZE * nq)
    mr = np.zeros(data.M_SPARSE_SIZE * nq, dtype=INT)
    mc = np.zeros_like(mr)
    mv = np.zeros(data.M_SPARSE_SIZE * nq)
    props = [s.to_pyfe3d() for s in shell_sections]
    mtype = 1 if lumped else 0
    for e, (conn, g) in enumerate(
        zip(mesh.quads.tolist(), mesh.quad_group.tolist(), strict=False)
    ):
        q = Quad4(probe)
        q.c1, q.c2, q.c3, q.c4 = (DOF * c for c in conn)
        q.init_k_KC0 = e * data.KC0_SPARSE_SIZE
        q.init_k_M = e * data.M_SPARSE_SIZE
        q.update_rotation_matrix(x)
        q.update_probe_xe(x)
        q.update_KC0(kr, kc, kv, props[g])
        q.update_M(mr, mc, mv, props[g], mtype=mtype)
    if lumped:  # mtype=1 writes only the first 120 entries per element
        keep = (np.arange(mr.size) % data.M_SPARSE_SIZE) < 120
        mr, mc, mv = mr[keep], mc[keep], mv[keep]
    return (kr, kc, kv), (mr, mc, mv)


def _beam_triplets(mesh: Mesh, x: np.ndarray, beam_sections: list[BeamSection],
                   lumped: bool) -> tuple[_Triplets, _Triplets]:
    """Stiffness and mass triplets of the beams (pyfe3d ``BeamC``, oriented by
    ``mesh.beam_vxy``); ``x`` are the node coordinates (m), flattened. Lumped masses keep 36
    entries per element.
    """
    nb = len(mesh.beams)
    data = BeamCData()
    probe = BeamCProbe()
    kr = np.zeros(data.KC0_SPARSE_SIZE * nb, dtype=INT)
    kc = np.zeros_like(kr)
    kv = np.zeros(data.KC0_SPARSE_SIZE * nb)
    msize = 36 if lumped else data.M_SPARSE_SIZE
    mr = np.zeros(data.M_SPARSE_SIZE * nb, dtype=INT)
    mc = np.zeros_like(mr)
    mv = np.zeros(data.M_SPARSE_SIZE * nb)
    props = [s.to_pyfe3d() for s in beam_sections]
    mtype = 1 if lumped else 0
    for e, (conn, g, v) in enumerate(
        zip(mesh.beams.tolist(), mesh.beam_group.tolist(), mesh.beam_vxy.tolist(), strict=False)
    ):
        b = BeamC(probe)
        b.c1, b.c2 = DOF * conn[0], DOF * conn[1]
        b.init_k_KC0 = e * data.KC0_SPARSE_SIZE
        b.init_k_M = e * data.M_SPARSE_SIZE
        b.update_rotation_matrix(v[0], v[1], v[2], x)
        b.update_probe_xe(x)
        b.update_KC0(kr, kc, kv, props[g])
        b.update_M(mr, mc, mv, props[g], mtype=mtype)
    if lumped:
        keep = (np.arange(mr.size) % data.M_SPARSE_SIZE) < msize
        mr, mc, mv = mr[keep], mc[keep], mv[keep]
    return (kr, kc, kv), (mr, mc, mv)


def _spring_triplets(mesh: Mesh) -> _Triplets:
    """Stiffness triplets of the springs (pyfe3d ``Spring``, global axes; ``mesh.spring_k`` in
    N/m and N·m/rad).
    """
    ns = len(mesh.springs)
    data = SpringData()
    probe = SpringProbe()
    kr = np.zeros(data.KC0_SPARSE_SIZE * ns, dtype=INT)
    kc = np.zeros_like(kr)
    kv = np.zeros(data.KC0_SPARSE_SIZE * ns)
    for e, (conn, k) in enumerate(
        zip(mesh.springs.tolist(), mesh.spring_k.tolist(), strict=False)
    ):
        s = Spring(probe)
        s.c1, s.c2 = DOF * conn[0], DOF * conn[1]
        s.init_k_KC0 = e * data.KC0_SPARSE_SIZE
        s.kxe, s.kye, s.kze, s.krxe, s.krye, s.krze = k
        s.update_rotation_matrix(1.0, 0.0, 0.0, 0.0, 1.0, 0.0)
        s.update_KC0(kr, kc, kv)
    return kr, kc, kv


def lumped_mass_triplets(
    nodes: np.ndarray, masses: np.ndarray, offsets: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sparse triplets of point masses rigidly attached to nodes with an offset.

    The mass at ``p = x_node + e`` moves as ``u_p = u + θ × e``, so its 6 × 6 node matrix is
    ``m Tᵀ T`` with ``T = [I, -[e]×]``: exact rigid-body mass properties (CONM2 with offset).

    Returns
    -------
    rows, cols, values : numpy.ndarray
        36 triplets per mass.
    """
    nodes = np.asarray(nodes, dtype=np.int64)
    masses = np.asarray(masses, dtype=float)
    offsets = np.asarray(offsets, dtype=float).reshape(-1, 3)
    nm = nodes.size
    T = np.zeros((nm, 3, 6))
    T[:, 0, 0] = T[:, 1, 1] = T[:, 2, 2] = 1.0
    ex, ey, ez = offsets[:, 0], offsets[:, 1], offsets[:, 2]
    # θ × e = (θy ez − θz ey, θz ex − θx ez, θx ey − θy ex)
    T[:, 0, 4], T[:, 0, 5] = ez, -ey
    T[:, 1, 3], T[:, 1, 5] = -ez, ex
    T[:, 2, 3], T[:, 2, 4] = ey, -ex
    me = masses[:, None, None] * np.einsum("nki,nkj->nij", T, T)
    base = DOF * nodes
    ii, jj = np.meshgrid(np.arange(6), np.arange(6), indexing="ij")
    rows = (base[:, None, None] + ii[None]).ravel()
    cols = (base[:, None, None] + jj[None]).ravel()
    return rows.astype(INT), cols.astype(INT), me.ravel()

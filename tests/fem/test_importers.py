"""Import of external mass and stiffness matrices (MatrixMarket, Harwell–Boeing, DMIG, Nastran
OP4 through pyyeti, ANSYS .full through ansys-mapdl-reader).

The OP4 and .full tests need the optional packages (``pip install pyyeti==1.4.7`` and
``pip install --no-deps ansys-mapdl-reader==0.56.0``); they fail, not skip, without them.
"""

from __future__ import annotations

import importlib.util
import re
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
import scipy.io as sio
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from flexride.errors import FEModelError
from flexride.fem import optional_readers
from flexride.fem.flexible import flexible_body_from_model
from flexride.fem.importers import import_fe_model, read_dmig, read_matrix
from flexride.fem.optional_readers import op4_directory, read_ansys_full, read_op4
from flexride.fem.vehicle_models import build_fe_model


@pytest.fixture(scope="module")
def source(vehicle):
    model, _ = build_fe_model("frame", vehicle, element_size=0.2)
    K, M = model.assemble()
    return model, K.tocsc(), M.tocsc()


def _write_nodes(path, nodes, ids):
    lines = ["id,x,y,z"] + [
        f"{i},{float(x)!r},{float(y)!r},{float(z)!r}"
        for i, (x, y, z) in zip(ids, nodes, strict=False)
    ]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def _write_hb_rsa(path, A):
    lower = sp.tril(A).tocsc()
    sio.hb_write(str(path), lower)
    lines = path.read_text().splitlines(keepends=True)
    lines[2] = "RSA" + lines[2][3:]
    path.write_text("".join(lines))


def _write_dmig(path, name, A, dof_nodes, dof_comp, ids):
    lower = sp.triu(A).tocsc()  # column j holds rows i <= j
    out = [f"DMIG,{name},0,6,1,,,,\n"]
    for j in range(A.shape[0]):
        lo, hi = lower.indptr[j], lower.indptr[j + 1]
        if hi == lo:
            continue
        gj, cj = ids[dof_nodes[j]], dof_comp[j] + 1
        fields = [f"DMIG,{name},{gj},{cj},"]
        for i, v in zip(lower.indices[lo:hi], lower.data[lo:hi], strict=False):
            fields.append(f",{ids[dof_nodes[i]]},{dof_comp[i] + 1},{v:.17e}")
        out.append(fields[0] + "".join(fields[1:]).replace(",,", ",", 0) + "\n")
    path.write_text("".join(out))


def _freqs(body):
    return body.body.elastic_frequencies


def test_matrix_market_roundtrip(source, tmp_path, cache_dir):
    model, K, M = source
    ids = np.arange(1, model.nodes.shape[0] + 1) * 10
    sio.mmwrite(str(tmp_path / "k.mtx"), K)
    sio.mmwrite(str(tmp_path / "m.mtx"), M)
    _write_nodes(tmp_path / "nodes.csv", model.nodes, ids)
    att = {
        n: int(ids[model.named_nodes[n]]) for n in ("ab1L", "ab1R", "ab2L", "ab2R", "asL", "asR")
    }
    imp = import_fe_model(
        "myframe",
        tmp_path / "k.mtx",
        tmp_path / "m.mtx",
        tmp_path / "nodes.csv",
        attachments=att,
        outputs={"centre": int(ids[model.named_nodes["centre"]])},
    )
    fb = flexible_body_from_model(imp, method="modal", cutoff_hz=100.0)
    ref = flexible_body_from_model(model, method="modal", cutoff_hz=100.0, use_cache=False)
    np.testing.assert_allclose(_freqs(fb), _freqs(ref), rtol=1e-9)
    assert fb.body.mass == pytest.approx(ref.body.mass)
    assert set(fb.body.elastic_shapes) == set(att) | {"centre"}
    cb = flexible_body_from_model(imp, method="craig-bampton", cutoff_hz=100.0)
    np.testing.assert_allclose(_freqs(cb)[:4], _freqs(ref)[:4], rtol=0.01)


def test_harwell_boeing_symmetric_and_dof_map(source, tmp_path):
    model, K, M = source
    _write_hb_rsa(tmp_path / "k.matrix", K)
    _write_hb_rsa(tmp_path / "m.matrix", M)
    Kr = read_matrix(tmp_path / "k.matrix")
    assert abs(Kr - K).max() < 1e-9 * abs(K).max()
    ids = np.arange(1, model.nodes.shape[0] + 1)
    _write_nodes(tmp_path / "nodes.csv", model.nodes, ids)
    # ANSYS .mapping style DOF map
    labels = ["UX", "UY", "UZ", "ROTX", "ROTY", "ROTZ"]
    rows = ["Matrix Eqn   Node   DOF"] + [
        f"{6 * i + c + 1} {ids[i]} {labels[c]}" for i in range(len(ids)) for c in range(6)
    ]
    (tmp_path / "k.mapping").write_text("\n".join(rows) + "\n")
    imp = import_fe_model(
        "hb",
        tmp_path / "k.matrix",
        tmp_path / "m.matrix",
        tmp_path / "nodes.csv",
        dof_map=tmp_path / "k.mapping",
    )
    assert abs(imp.K - K).max() < 1e-9 * abs(K).max()


def test_dmig_and_mm_t_s_units(source, tmp_path, cache_dir):
    model, K, M = source
    ids = np.arange(1, model.nodes.shape[0] + 1) + 100
    n = model.nodes.shape[0]
    dn, dc = np.repeat(np.arange(n), 6), np.tile(np.arange(6), n)
    # the same model in mm, tonne, s: translations scale by 1e3 (mm per m), energy by 1e3
    d = np.where(dc < 3, 1e-3, 1.0)
    D = sp.diags(d)
    K_mm, M_mm = (1e3 * (D @ K @ D)).tocsc(), (1e3 * (D @ M @ D)).tocsc()
    _write_dmig(tmp_path / "k.dmig", "KAAX", K_mm, dn, dc, ids)
    _write_dmig(tmp_path / "m.dmig", "MAAX", M_mm, dn, dc, ids)
    A, dofs = read_dmig(tmp_path / "k.dmig", "KAAX")
    assert A.shape == K.shape and dofs[0] == (101, 1)
    _write_nodes(tmp_path / "nodes.csv", model.nodes * 1e3, ids)
    imp = import_fe_model(
        "dmig", tmp_path / "k.dmig", tmp_path / "m.dmig", tmp_path / "nodes.csv", units="mm-t-s"
    )
    assert abs(imp.K - K).max() < 1e-7 * abs(K).max()
    assert abs(imp.M - M).max() < 1e-7 * abs(M).max()
    np.testing.assert_allclose(imp.nodes, model.nodes, atol=1e-12)


def test_three_dof_nodes_via_dof_map(cache_dir):
    # a spring-mass chain in 3D with translational DOFs only (no rotations)
    nodes = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    ids = np.array([1, 2, 3, 4])
    k = 1e6
    n = 12
    Kd = np.zeros((n, n))
    for a in range(4):
        for b in range(a + 1, 4):
            e = nodes[b] - nodes[a]
            e = e / np.linalg.norm(e)
            ke = k * np.outer(e, e)
            for i, j, s in ((a, a, 1), (b, b, 1), (a, b, -1), (b, a, -1)):
                Kd[3 * i : 3 * i + 3, 3 * j : 3 * j + 3] += s * ke
    Md = np.eye(n) * 10.0
    dmap = [(int(i), c) for i in ids for c in range(3)]
    imp = import_fe_model(
        "tet",
        sp.csc_matrix(Kd),
        sp.csc_matrix(Md),
        (ids, nodes),
        dof_map=dmap,
        attachments={"a": 1, "b": 2, "c": 3},
    )
    fb = flexible_body_from_model(imp, method="modal", cutoff_hz=1e4, use_cache=False)
    assert fb.body.n_elastic == 6
    assert fb.body.mass == pytest.approx(40.0)
    assert np.all(fb.body.elastic_shapes["a"][3:] == 0.0)  # no rotations in a 3-DOF model


@pytest.mark.parametrize("problem", ["nonsym", "size", "negmass", "missing", "attach"])
def test_bad_inputs_are_clear_errors(problem, source):
    model, K, M = source
    n = model.nodes.shape[0]
    ids, nodes = np.arange(1, n + 1), model.nodes
    Kb, Mb = K.copy().tolil(), M.copy().tolil()
    kwargs: dict = {}
    if problem == "nonsym":
        Kb[0, 7] = Kb[0, 7] + 1e9
    elif problem == "size":
        Mb = sp.csc_matrix(M[:-6][:, :-6])
    elif problem == "negmass":
        Mb[8, 8] = -1.0
    elif problem == "missing":
        ids, nodes = ids[:-1], nodes[:-1]
        kwargs["dof_map"] = [(int(i), c) for i in range(1, n + 1) for c in range(6)]
    elif problem == "attach":
        kwargs["attachments"] = {"x": 99999}
    with pytest.raises(FEModelError) as info:
        import_fe_model("bad", sp.csc_matrix(Kb), sp.csc_matrix(Mb), (ids, nodes), **kwargs)
    assert str(info.value)


def test_missing_file_and_unknown_format(tmp_path):
    with pytest.raises(FEModelError):
        read_matrix(tmp_path / "nope.mtx")
    (tmp_path / "a.xyz").write_text("1")
    with pytest.raises(FEModelError):
        read_matrix(tmp_path / "a.xyz")
    (tmp_path / "bad.mtx").write_text("not a matrix\n")
    with pytest.raises(FEModelError):
        read_matrix(tmp_path / "bad.mtx")


def test_complex_duplicate_and_empty_dofs_are_clear_errors(source):
    model, K, M = source
    n = model.nodes.shape[0]
    ids, nodes = np.arange(1, n + 1), model.nodes
    with pytest.raises(FEModelError, match="complex"):
        import_fe_model("c", sp.csc_matrix(K * (1 + 1j)), M, (ids, nodes))
    dmap = [(int(i), c) for i in ids for c in range(6)]
    dmap[7] = dmap[6]
    with pytest.raises(FEModelError, match="twice"):
        import_fe_model("d", K, M, (ids, nodes), dof_map=dmap)
    # a constrained DOF left in the matrices as a zero row and column
    Kz, Mz = K.tolil(), M.tolil()
    for A in (Kz, Mz):
        A[9, :] = 0.0
        A[:, 9] = 0.0
    with pytest.raises(FEModelError, match=r"no stiffness \(node 2 component 4\)"):
        import_fe_model("z", Kz.tocsc(), Mz.tocsc(), (ids, nodes))


# -- an analytic model: a free–free Euler–Bernoulli beam ------------------------------------------

E_STEEL, G_STEEL, RHO_STEEL = 210e9, 81e9, 7850.0
BEAM_L, BEAM_A, BEAM_IY, BEAM_IZ, BEAM_J = 10.0, 0.01, 2e-5, 8e-5, 5e-5  # m, m², m⁴
BEAM_BL = (4.730041, 7.853205, 10.995608, 14.137165, 17.278760)  # free–free βL


def _free_beam(n_el: int = 40) -> tuple[sp.csc_matrix, sp.csc_matrix, np.ndarray]:
    """K, M (SI) and nodes of a straight steel beam along x: bars for axial and torsion,
    Hermite cubics for bending (no shear, no rotary inertia), six DOFs per node in node order."""
    n = n_el + 1
    h = BEAM_L / n_el
    K = np.zeros((6 * n, 6 * n))
    M = np.zeros_like(K)
    bar_k = np.array([[1.0, -1.0], [-1.0, 1.0]]) / h
    bar_m = np.array([[2.0, 1.0], [1.0, 2.0]]) * h / 6
    hk = (
        np.array(
            [
                [12, 6 * h, -12, 6 * h],
                [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                [-12, -6 * h, 12, -6 * h],
                [6 * h, 2 * h * h, -6 * h, 4 * h * h],
            ]
        )
        / h**3
    )
    hm = np.array(
        [
            [156, 22 * h, 54, -13 * h],
            [22 * h, 4 * h * h, 13 * h, -3 * h * h],
            [54, 13 * h, 156, -22 * h],
            [-13 * h, -3 * h * h, -22 * h, 4 * h * h],
        ]
    ) * (h / 420)
    flip = np.diag([1.0, -1.0, 1.0, -1.0])  # w' = -ry
    rho_a, rho_ip = RHO_STEEL * BEAM_A, RHO_STEEL * (BEAM_IY + BEAM_IZ)
    for e in range(n_el):
        a, b = 6 * e, 6 * (e + 1)
        for dofs, ke, me in (
            ([a, b], E_STEEL * BEAM_A * bar_k, rho_a * bar_m),  # ux
            ([a + 3, b + 3], G_STEEL * BEAM_J * bar_k, rho_ip * bar_m),  # rx
            ([a + 1, a + 5, b + 1, b + 5], E_STEEL * BEAM_IZ * hk, rho_a * hm),  # uy, rz
            (
                [a + 2, a + 4, b + 2, b + 4],
                flip @ (E_STEEL * BEAM_IY * hk) @ flip,
                flip @ (rho_a * hm) @ flip,
            ),  # uz, ry
        ):
            ix = np.ix_(dofs, dofs)
            K[ix] += ke
            M[ix] += me
    nodes = np.column_stack([np.linspace(0.0, BEAM_L, n), np.zeros(n), np.full(n, 1.2)])
    return sp.csc_matrix(K), sp.csc_matrix(M), nodes


def _free_beam_frequencies(f_max: float) -> np.ndarray:
    """Analytic free–free frequencies (Hz) of the beam up to ``f_max``: bending in both planes,
    first axial and torsion modes."""
    f = [
        bl**2 / (2 * np.pi * BEAM_L**2) * np.sqrt(E_STEEL * inertia / (RHO_STEEL * BEAM_A))
        for inertia in (BEAM_IY, BEAM_IZ)
        for bl in BEAM_BL
    ]
    f.append(np.sqrt(E_STEEL / RHO_STEEL) / (2 * BEAM_L))
    f.append(np.sqrt(G_STEEL * BEAM_J / (RHO_STEEL * (BEAM_IY + BEAM_IZ))) / (2 * BEAM_L))
    f = np.sort(f)
    return f[f <= f_max]


@pytest.fixture(scope="module")
def free_beam():
    return _free_beam()


# -- Nastran OP4 (pyyeti) -------------------------------------------------------------------------


def _op4():
    from pyyeti.nastran import op4  # not a flexride dependency; the test needs it

    return op4


@pytest.mark.parametrize(
    "binary, layout", [(True, "bigmat"), (True, "dense"), (False, "nonbigmat"), (False, "dense")]
)
def test_op4_free_beam_matches_analytic_frequencies(binary, layout, free_beam, tmp_path, cache_dir):
    K, M, nodes = free_beam
    ids = np.arange(1, nodes.shape[0] + 1)
    path = tmp_path / "beam.op4"
    _op4().write(str(path), {"KGG": K, "MGG": M}, binary=binary, sparse=layout)
    assert [e[0] for e in op4_directory(path)] == ["kgg", "mgg"]
    _write_nodes(tmp_path / "nodes.csv", nodes, ids)
    imp = import_fe_model(
        "beam",
        path,
        None,
        tmp_path / "nodes.csv",
        op4_names=("kgg", "MGG"),
        attachments={"left": 1, "right": int(ids[-1])},
        outputs={"middle": 21},
    )
    assert imp.info["import"] == {"format": "op4"}
    fb = flexible_body_from_model(imp, method="modal", cutoff_hz=100.0, use_cache=False)
    ref = _free_beam_frequencies(100.0)
    assert ref.size == 7  # bending only: four about y, three about z (torsion 114 Hz)
    # Hermite elements: 40 per length are within 1e-5 of the analytic values
    np.testing.assert_allclose(_freqs(fb), ref, rtol=2e-5)
    assert fb.body.mass == pytest.approx(RHO_STEEL * BEAM_A * BEAM_L, rel=1e-12)


def test_op4_one_matrix_per_file_and_mm_t_s(free_beam, tmp_path):
    K, M, nodes = free_beam
    n = nodes.shape[0]
    ids = np.arange(1, n + 1) * 100
    # the same beam in mm, tonne, s
    d = np.tile(np.where(np.arange(6) < 3, 1e-3, 1.0), n)
    D = sp.diags(d)
    _op4().write(str(tmp_path / "k.op4"), {"KAA": (1e3 * (D @ K @ D)).tocsc()}, binary=False)
    _op4().write(str(tmp_path / "m.op4"), {"MAA": (1e3 * (D @ M @ D)).toarray()}, binary=True)
    assert read_matrix(tmp_path / "k.op4").shape == K.shape  # the only matrix: no name needed
    _write_nodes(tmp_path / "nodes.csv", nodes * 1e3, ids)
    imp = import_fe_model(
        "beam", tmp_path / "k.op4", tmp_path / "m.op4", tmp_path / "nodes.csv", units="mm-t-s"
    )
    assert abs(imp.K - K).max() < 1e-9 * abs(K).max()
    assert abs(imp.M - M).max() < 1e-9 * abs(M).max()
    np.testing.assert_allclose(imp.nodes, nodes, atol=1e-12)


def _pyyeti_test_file(*parts: str) -> Path:
    spec = importlib.util.find_spec("pyyeti")
    assert spec is not None and spec.origin, "pyyeti is not installed"
    path = Path(spec.origin).parent.joinpath("tests", *parts)
    assert path.is_file(), path
    return path


def test_op4_reads_a_nastran_written_file():
    """``inboard.op4`` ships with pyyeti: NX Nastran's (2015) binary OP4 of a Craig–Bampton
    superelement, four boundary grids (24 DOFs) and eight modal DOFs. The modal block of KXX is
    diagonal with the eigenvalues Nastran prints in ``inboard.out`` (after augmentation with
    residual vectors); MXX's modal block is the identity; the boundary block is free–free."""
    path = _pyyeti_test_file("nas2cam_csuper", "inboard.op4")
    with pytest.raises(FEModelError, match="holds the matrices"):
        read_op4(path)
    K, M = read_op4(path, "KXX"), read_op4(path, "mxx")
    assert K.shape == M.shape == (32, 32)
    nastran = [
        1.483160e03,
        1.483542e03,
        2.204734e04,
        1.962769e05,
        1.978438e05,
        4.336635e05,
        3.138347e06,
        7.124542e06,
    ]  # inboard.out, REAL EIGENVALUES, modes 1-8
    np.testing.assert_allclose(K.diagonal()[24:], nastran, rtol=1e-6)
    assert abs(K[24:, 24:] - sp.diags(K.diagonal()[24:])).max() == 0.0
    np.testing.assert_allclose(M[24:, 24:].toarray(), np.eye(8), atol=1e-12)
    w = sla.eigvalsh(K[:24, :24].toarray())  # the boundary stiffness: six rigid-body modes
    w = w / np.abs(w).max()
    assert np.all(np.abs(w[:6]) < 1e-12) and w[6] > 1e-6


def test_op4_bad_files_are_clear_errors(free_beam, tmp_path):
    K, M, nodes = free_beam
    n = nodes.shape[0]
    op4 = _op4()
    both = tmp_path / "both.op4"
    op4.write(str(both), {"KGG": K, "MGG": M})
    ids = np.arange(1, n + 1)

    def imp(stiffness, mass=None, **kw):
        return import_fe_model("b", stiffness, mass, (ids, nodes), **kw)

    with pytest.raises(FEModelError, match=r"holds both matrices: give their names"):
        imp(both)
    with pytest.raises(FEModelError, match=r"no matrix 'KAA' in OP4 file .* \['KGG', 'MGG'\]"):
        imp(both, op4_names=("KAA", "MAA"))
    with pytest.raises(FEModelError, match="stiffness matrix has 246 rows, the DOF map has 240"):
        import_fe_model("b", both, None, (ids[:-1], nodes[:-1]), op4_names=("KGG", "MGG"))
    op4.write(str(tmp_path / "sym.op4"), {"KGG": sp.triu(K).tocsc(), "MGG": M})
    with pytest.raises(FEModelError, match="stiffness matrix is not symmetric"):
        imp(tmp_path / "sym.op4", op4_names=("KGG", "MGG"))
    op4.write(str(tmp_path / "cplx.op4"), {"KGG": K.toarray() * (1 + 1j)})
    with pytest.raises(FEModelError, match="is complex"):
        read_op4(tmp_path / "cplx.op4")
    op4.write(str(tmp_path / "twice.op4"), ["KGG", "KGG"], [K, K])
    with pytest.raises(FEModelError, match="holds 2 matrices named 'KGG'"):
        read_op4(tmp_path / "twice.op4", "KGG")
    (tmp_path / "text.op4").write_text("this is not an OP4 file\n")
    (tmp_path / "empty.op4").write_bytes(b"")
    data = both.read_bytes()
    (tmp_path / "cut.op4").write_bytes(data[: len(data) // 2])
    for bad in ("text.op4", "empty.op4", "cut.op4"):
        with pytest.raises(FEModelError, match=r"OP4"):
            imp(tmp_path / bad, op4_names=("KGG", "MGG"))
    # a directory or a missing file: an error, never pyyeti's file dialog
    with pytest.raises(FEModelError, match="OP4 file not found"):
        read_op4(tmp_path)
    with pytest.raises(FEModelError, match="OP4 file not found"):
        imp(tmp_path / "nope.op4", op4_names=("KGG", "MGG"))


def test_op4_without_pyyeti_names_the_install_command(monkeypatch, tmp_path):
    (tmp_path / "k.op4").write_bytes(b"\0" * 64)
    monkeypatch.setitem(sys.modules, "pyyeti", None)
    monkeypatch.setitem(sys.modules, "pyyeti.nastran", None)
    with pytest.raises(FEModelError, match=re.escape("pip install pyyeti==1.4.7")):
        read_op4(tmp_path / "k.op4")


# -- ANSYS .full (ansys-mapdl-reader) -------------------------------------------------------------


def _ansys_examples() -> Path:
    """The example files of ansys-mapdl-reader (found without importing the package, whose
    ``__init__`` needs pyvista)."""
    spec = importlib.util.find_spec("ansys.mapdl")
    assert spec is not None and spec.submodule_search_locations, "ansys-mapdl-reader missing"
    return Path(next(iter(spec.submodule_search_locations))) / "reader" / "examples"


def _cdb_nodes(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Node numbers and coordinates of the NBLOCK of an ANSYS .cdb, format (3i9,6e21.13e3)
    (blank trailing coordinates are zero)."""
    lines = path.read_text().splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith("NBLOCK"))
    ids, xyz = [], []
    for line in lines[start + 2 :]:
        if line.startswith("N,") or line.strip() == "-1":
            break
        ids.append(int(line[:9]))
        xyz.append([float(line[27 + 21 * j : 48 + 21 * j].strip() or 0.0) for j in range(3)])
    return np.asarray(ids), np.asarray(xyz)


@pytest.fixture(scope="module")
def hexbeam():
    ex = _ansys_examples()
    ids, xyz = _cdb_nodes(ex / "HexBeam.cdb")
    assert ids.size == 321 and np.allclose(xyz.max(axis=0) - xyz.min(axis=0), [1.0, 1.0, 5.0])
    return ex / "file.full", ids, xyz


# the ansys-mapdl-reader documentation (README, "Reading a Full File"): the first four
# natural frequencies of this file, Hz
HEXBEAM_DOC_HZ = [1283.200, 1283.200, 5781.975, 6919.399]


def test_ansys_full_reads_the_reader_example(hexbeam):
    path, ids, xyz = hexbeam
    full = read_ansys_full(path)
    assert full.labels == (1, 2, 3) and full.ansys_version == "15.0"
    assert full.K.shape == (963, 963) and len(full.dofs) == 963
    assert full.dofs[:4] == [(1, 0), (1, 1), (1, 2), (2, 0)]
    for A in (full.K, full.M):
        assert abs(A - A.T).max() == 0.0 and sp.tril(A, -1).nnz == sp.triu(A, 1).nnz > 0
    # the constrained DOFs: all three at the 21 nodes of the clamped face z = 0, zero in K and M
    pos = {int(i): k for k, i in enumerate(ids)}
    cnodes = sorted({full.dofs[i][0] for i in np.flatnonzero(full.constrained)})
    assert full.constrained.sum() == 63 and len(cnodes) == 21
    assert np.all(xyz[[pos[c] for c in cnodes], 2] == 0.0)
    assert np.sum(xyz[:, 2] == 0.0) == 21
    empty = np.asarray(abs(full.K).sum(axis=0)).ravel() == 0.0
    assert np.array_equal(empty, full.constrained)


def test_ansys_full_with_constraints_is_an_error_by_default(hexbeam):
    path, ids, xyz = hexbeam
    with pytest.raises(FEModelError, match="63 DOFs at 21 nodes are constrained"):
        import_fe_model("hexbeam", path, None, (ids, xyz))
    with pytest.raises(FEModelError, match="carries its own DOF map"):
        import_fe_model("hexbeam", path, None, (ids, xyz), dof_map=[(1, 0)])
    with pytest.raises(FEModelError, match="holds both matrices"):
        import_fe_model("hexbeam", path, "m.mtx", (ids, xyz))


def test_ansys_full_dropped_constraints_match_documented_and_beam_frequencies(hexbeam, cache_dir):
    """Oracles: the reader's documented frequencies of this file, and hand formulas for the
    1 × 1 × 5 cantilever (material unknown: the axial mode gives the bar wave speed c)."""
    path, ids, xyz = hexbeam
    model = import_fe_model("hexbeam", path, None, (ids, xyz), constrained="drop")
    assert model.K.shape == (900, 900)
    assert model.info["import"]["dropped_constrained_dofs"] == 63
    w2, V = spla.eigsh(model.K, k=6, M=model.M, sigma=0.0)
    order = np.argsort(w2)
    f, V = np.sqrt(w2[order]) / (2 * np.pi), V[:, order]
    np.testing.assert_allclose(f[:4], HEXBEAM_DOC_HZ, atol=6e-4)
    # which way each mode moves (kinetic energy share of UX, UY, UZ; the beam axis is z)
    comp = model.info["dof_components"]
    MV = model.M @ V
    share = np.array([[V[comp == c, j] @ MV[comp == c, j] for c in range(3)] for j in range(6)])
    share /= share.sum(axis=1, keepdims=True)
    assert f[1] == pytest.approx(f[0], rel=1e-9)  # square section: a bending pair
    assert np.all(share[:2, 2] < 0.02) and np.all(share[3:5, 2] < 0.1)  # bending: lateral
    assert share[2, 2] < 1e-3 and share[2, 0] == pytest.approx(0.5, abs=0.01)  # torsion
    assert share[5, 2] > 0.99  # the axial mode
    length, side = 5.0, 1.0
    c = 4 * length * f[5]  # clamped–free bar: f = c / (4 L)
    f_bend = 1.875104**2 / (2 * np.pi * length**2) * c * side / np.sqrt(12.0)  # Euler–Bernoulli
    assert 0.95 < f[0] / f_bend < 1.0  # shear and rotary inertia (L/h = 5) lower it a little
    # torsion of a square section, J = 0.1406 a⁴, Ip = a⁴/6: f_t/f_axial = 0.9185/√(2(1 + ν))
    nu = (0.9185 / (f[2] / f[5])) ** 2 / 2 - 1
    assert 0.25 < nu < 0.35
    # ... and the clamped model cannot become a vehicle body
    with pytest.raises(FEModelError, match="does not move freely as a rigid body"):
        flexible_body_from_model(model, method="modal", cutoff_hz=20000.0, use_cache=False)


def _patched_full(src: Path, dst: Path, record: int, word: int, value: int) -> Path:
    """A copy of an ANSYS binary with one int32 data word of record ``record`` (0-based;
    records are [n, flags, n words, n]) replaced."""
    data = np.fromfile(src, dtype="<i4")
    at = 0
    for _ in range(record):
        at += int(data[at]) + 3
    data[at + 2 + word] = value
    data.tofile(dst)
    return dst


def test_ansys_full_unsupported_files_are_clear_errors(hexbeam, tmp_path):
    path, ids, xyz = hexbeam
    # DOF labels UX UY TEMP (record 3 holds the model's DOF reference numbers)
    temp = _patched_full(path, tmp_path / "temp.full", record=2, word=2, value=20)
    with pytest.raises(FEModelError, match=r"DOF labels \[20\]"):
        read_ansys_full(temp)
    # lumped mass (header item 11, lumpm) and unsymmetric matrices (item 14, keyuns)
    lumped = _patched_full(path, tmp_path / "lumped.full", record=1, word=10, value=1)
    with pytest.raises(FEModelError, match="lumped"):
        import_fe_model("x", lumped, None, (ids, xyz), constrained="drop")
    unsym = _patched_full(path, tmp_path / "unsym.full", record=1, word=13, value=1)
    with pytest.raises(FEModelError, match="unsymmetric"):
        read_ansys_full(unsym)
    (tmp_path / "junk.full").write_bytes(b"\1\2\3" * 100)
    with pytest.raises(FEModelError, match=r"cannot read ANSYS \.full file"):
        read_ansys_full(tmp_path / "junk.full")
    with pytest.raises(FEModelError, match="not found"):
        read_ansys_full(tmp_path / "nope.full")


def test_ansys_full_without_the_reader_names_the_install_command(monkeypatch, hexbeam):
    path, _, _ = hexbeam
    for key in [k for k in sys.modules if k.startswith("ansys.")]:
        monkeypatch.delitem(sys.modules, key)
    monkeypatch.setitem(sys.modules, "ansys", None)
    optional_readers._ansys_full_module.cache_clear()
    try:
        with pytest.raises(
            FEModelError, match=re.escape("pip install --no-deps ansys-mapdl-reader==0.56.0")
        ):
            read_ansys_full(path)
    finally:
        optional_readers._ansys_full_module.cache_clear()


def test_ansys_reader_loads_without_its_plotting_dependencies():
    """The .full reader works from a --no-deps install: pyvista/VTK are not imported."""
    import subprocess

    code = (
        "import sys; from flexride.fem.optional_readers import _ansys_full_module; "
        "m = _ansys_full_module(); "
        "print(m.__name__, 'ansys.mapdl.reader' in sys.modules, "
        "any(k.startswith(('pyvista', 'vtk')) for k in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    has_pyvista = importlib.util.find_spec("pyvista") is not None
    assert out.stdout.split() == ["ansys.mapdl.reader.full", str(has_pyvista), str(has_pyvista)]


# -- the worked examples of docs/fem.md, "Bring your own FE model" --------------------------------

DOCS_FEM = Path(__file__).resolve().parents[2] / "docs" / "fem.md"


def _byo_blocks() -> list[str]:
    text = DOCS_FEM.read_text(encoding="utf-8")
    section = text.split("## Bring your own FE model", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, flags=re.S)


def _numbers(text: str) -> list[float]:
    return [float(v) for v in re.findall(r"-?\d+(?:\.\d+)?", text)]


def test_docs_bring_your_own_examples_run(
    source, free_beam, hexbeam, tmp_path, monkeypatch, capsys, cache_dir
):
    """Every python block of the section runs, in a directory holding the files it names;
    the frequencies printed are the ones its comments give."""
    # the HBMAT example: a frame in mm, tonne, s with the node numbers of the example
    model, K, M = source
    n = model.nodes.shape[0]
    ids = np.arange(1, n + 1) + 10000
    for nid, key in zip(
        (1001, 1002, 2001, 2002, 5001, 5002),
        ("ab1L", "ab1R", "ab2L", "ab2R", "centre", "asL"),
        strict=True,
    ):
        ids[model.named_nodes[key]] = nid
    d = np.tile(np.where(np.arange(6) < 3, 1e-3, 1.0), n)
    D = sp.diags(d)
    _write_hb_rsa(tmp_path / "k.matrix", (1e3 * (D @ K @ D)).tocsc())
    _write_hb_rsa(tmp_path / "m.matrix", (1e3 * (D @ M @ D)).tocsc())
    _write_nodes(tmp_path / "nodes.csv", model.nodes * 1e3, ids)
    labels = ["UX", "UY", "UZ", "ROTX", "ROTY", "ROTZ"]
    (tmp_path / "k.mapping").write_text(
        "Matrix Eqn   Node   DOF\n"
        + "".join(f"{6 * i + c + 1} {ids[i]} {labels[c]}\n" for i in range(n) for c in range(6))
    )
    # the OP4 example: the free beam, grids 1..41
    Kb, Mb, nodes = free_beam
    _op4().write(str(tmp_path / "beam.op4"), {"KGG": Kb, "MGG": Mb})
    _write_nodes(tmp_path / "beam_nodes.csv", nodes, np.arange(1, nodes.shape[0] + 1))
    # the .full example: the reader's example file and the nodes of HexBeam.cdb
    full, hids, hxyz = hexbeam
    shutil.copy(full, tmp_path / "file.full")
    _write_nodes(tmp_path / "hexbeam_nodes.csv", hxyz, hids)

    blocks = _byo_blocks()
    assert len(blocks) == 3
    monkeypatch.chdir(tmp_path)
    for k, block in enumerate(blocks):
        ns: dict = {}
        exec(compile(block, f"docs/fem.md, block {k + 1}", "exec"), ns)
        printed = capsys.readouterr().out
        for line in block.splitlines():
            if line.startswith("print(") and "#" in line:
                claimed = _numbers(line.split("#", 1)[1])
                np.testing.assert_allclose(_numbers(printed), claimed, atol=6e-3)
        if k == 0:
            body = ns["fb"].body
            assert set(body.elastic_shapes) == {"as1L", "as1R", "as2L", "as2R", "PR", "PC"}
            assert body.mass == pytest.approx(model.mass_properties().mass, rel=1e-9)
        elif k == 1:
            np.testing.assert_allclose(_freqs(ns["fb"]), _free_beam_frequencies(50.0), rtol=4e-6)
        else:
            np.testing.assert_allclose(
                np.sort(np.sqrt(ns["w2"]) / (2 * np.pi)), HEXBEAM_DOC_HZ, atol=6e-4
            )

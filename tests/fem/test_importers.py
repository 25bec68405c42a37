"""Import of external mass and stiffness matrices (MatrixMarket, Harwell–Boeing, DMIG)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io as sio
import scipy.sparse as sp

from flexride.errors import FEModelError
from flexride.fem.flexible import build_fe_model, flexible_body_from_model
from flexride.fem.importers import import_fe_model, read_dmig, read_matrix


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

"""Import of external FE models: mass and stiffness matrices with a node/DOF map.

Supported matrix files:

* MatrixMarket (``.mtx``, ``scipy.io.mmread``), e.g. from any code or a script;
* Harwell–Boeing (ANSYS ``HBMAT`` export, ``scipy.io.hb_read``); ANSYS writes symmetric
  matrices as their lower triangle (type ``RSA``), which is expanded here;
* ANSYS ``.full`` binaries (stiffness, mass and DOF map in one file) through the optional
  package ``ansys-mapdl-reader`` (see :mod:`flexride.fem.optional_readers`);
* Nastran ``DMIG`` bulk-data entries (small or large fixed field, or free field; real, form 6
  symmetric or 1 square), read by :func:`read_dmig`;
* Nastran ``OP4`` files (binary or ASCII, dense or sparse; real) through the optional package
  ``pyyeti``; OP4 holds matrices only, the DOF map comes as for MatrixMarket.

The node file is CSV ``id, x, y, z`` (a header line is allowed). The DOF map says which node
and component every matrix row belongs to: a CSV ``row, node, component`` (component 1–6 or
``UX UY UZ ROTX ROTY ROTZ``), an ANSYS ``.mapping`` file from ``HBMAT`` (``eqn node label``), or
nothing, meaning six DOFs per node in node-file order (DMIG and ``.full`` files carry their own
map). Unit systems: ``SI`` (m, kg, N) or ``mm-t-s`` (mm, tonne, N), converted to SI on import.
"""

from __future__ import annotations

import io
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Literal

import numpy as np
import scipy.io as sio
import scipy.sparse as sp

from flexride.errors import FEModelError
from flexride.fem.model import FEModel
from flexride.fem.optional_readers import read_ansys_full, read_op4
from flexride.fem.pyfe3d_adapter import Mesh

_COMPONENTS = {
    "UX": 0,
    "UY": 1,
    "UZ": 2,
    "ROTX": 3,
    "ROTY": 4,
    "ROTZ": 5,
    "RX": 3,
    "RY": 4,
    "RZ": 5,
}
UNIT_SYSTEMS = ("SI", "mm-t-s")
FORMATS = ("mtx", "hb", "dmig", "op4", "ansys-full")


def read_matrix(path: str | Path, fmt: str | None = None, name: str | None = None) -> sp.csc_matrix:
    """Read one sparse matrix.

    Parameters
    ----------
    path : str or Path
        File.
    fmt : {"mtx", "hb", "op4"}, optional
        Format; guessed from the suffix when omitted (``.mtx``, ``.hb``/``.rsa``/``.rua``/
        ``.matrix``, ``.op4``). DMIG needs :func:`read_dmig`, ANSYS ``.full``
        :func:`flexride.fem.optional_readers.read_ansys_full`.
    name : str, optional
        OP4 matrix name (not needed when the file holds one matrix).

    Returns
    -------
    scipy.sparse.csc_matrix
    """
    p = Path(path)
    if not p.is_file():
        raise FEModelError(f"matrix file not found: {p}")
    fmt = (fmt or _guess_format(p)).lower()
    try:
        if fmt == "mtx":
            return sp.csc_matrix(sio.mmread(str(p)))
        if fmt == "hb":
            return _read_hb(p)
        if fmt == "op4":
            return read_op4(p, name)
    except FEModelError:
        raise
    except Exception as exc:
        raise FEModelError(f"cannot read {fmt} matrix {p}: {exc}") from exc
    if fmt in ("dmig", "ansys-full"):
        raise FEModelError(
            f"{p}: {fmt} files carry a DOF map: read them with "
            + ("read_dmig (with the matrix name)" if fmt == "dmig" else "read_ansys_full")
        )
    raise FEModelError(f"unknown matrix format {fmt!r} for {p} (use mtx, hb or op4)")


def _guess_format(p: Path) -> str:
    s = p.suffix.lower()
    if s == ".mtx":
        return "mtx"
    if s in (".hb", ".rsa", ".rua", ".matrix", ".hbmat"):
        return "hb"
    if s in (".dmig", ".bdf", ".pch", ".dat"):
        return "dmig"
    if s == ".op4":
        return "op4"
    if s == ".full":
        return "ansys-full"
    raise FEModelError(
        f"cannot tell the format of {p} from its suffix: give the format (one of {FORMATS})"
    )


def _read_hb(p: Path) -> sp.csc_matrix:
    lines = p.read_text(encoding="ascii", errors="replace").splitlines(keepends=True)
    if len(lines) < 4:
        raise FEModelError(f"{p} is not a Harwell–Boeing file (too short)")
    mxtype = lines[2][:3].upper()
    symmetric = mxtype[1] == "S"
    if mxtype[0] != "R" or mxtype[2] != "A" or mxtype[1] not in "SU":
        raise FEModelError(f"{p}: Harwell–Boeing type {mxtype} not supported (RSA or RUA)")
    if symmetric:
        lines[2] = "RUA" + lines[2][3:]
    A = sp.csc_matrix(sio.hb_read(io.StringIO("".join(lines))))
    if symmetric:
        A = (A + A.T - sp.diags(A.diagonal())).tocsc()
    return A


def read_dmig(path: str | Path, name: str) -> tuple[sp.csc_matrix, list[tuple[int, int]]]:
    """Read the Nastran DMIG matrix ``name`` (real; form 6 symmetric or 1 square).

    Returns
    -------
    matrix : scipy.sparse.csc_matrix
        The matrix in the order of its (grid, component) DOFs, sorted.
    dofs : list of (int, int)
        (grid id, component 1–6) of each row.
    """
    p = Path(path)
    if not p.is_file():
        raise FEModelError(f"DMIG file not found: {p}")
    cards = _dmig_cards(p.read_text(encoding="ascii", errors="replace"), name.upper())
    if not cards:
        raise FEModelError(f"no DMIG entries named {name!r} in {p}")
    header, columns = cards[0], cards[1:]
    try:
        form = int(header[3])
    except (IndexError, ValueError) as exc:
        raise FEModelError(f"{p}: bad DMIG header for {name!r}") from exc
    if form not in (1, 6):
        raise FEModelError(f"{p}: DMIG {name!r} has form {form}; only 1 and 6 are supported")
    entries: list[tuple[tuple[int, int], tuple[int, int], float]] = []
    for c in columns:
        try:
            gj, cj = int(c[2]), int(c[3])
            rest = c[5:]
            for k in range(0, len(rest) - 2, 3):
                if rest[k] == "":
                    continue
                entries.append(
                    ((int(rest[k]), int(rest[k + 1])), (gj, cj), float(_nas_float(rest[k + 2])))
                )
        except (IndexError, ValueError) as exc:
            raise FEModelError(f"{p}: unreadable DMIG column entry {c[:5]}") from exc
    dofs = sorted({e[0] for e in entries} | {e[1] for e in entries})
    index = {d: i for i, d in enumerate(dofs)}
    rows = [index[e[0]] for e in entries]
    cols = [index[e[1]] for e in entries]
    vals = [e[2] for e in entries]
    n = len(dofs)
    A = sp.coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsc()
    if form == 6:
        A = (A + A.T - sp.diags(A.diagonal())).tocsc()
    return A, dofs


def _nas_float(s: str) -> float:
    s = s.strip().upper().replace("D", "E")
    m = re.match(r"^([+-]?\d*\.\d*)([+-]\d+)$", s)  # Nastran 1.5-3 style
    if m:
        s = f"{m.group(1)}E{m.group(2)}"
    return float(s)


def _dmig_cards(text: str, name: str) -> list[list[str]]:
    """DMIG cards for ``name`` as lists of fields (continuations joined)."""
    cards: list[list[str]] = []
    current: list[str] | None = None
    for raw in text.splitlines():
        line = raw.split("$")[0].rstrip()
        if not line.strip():
            continue
        first = line[:8].strip()
        is_cont = line[:1] in ("+", "*", " ", ",") and not first.upper().startswith("DMIG")
        if not is_cont:
            if current is not None:
                cards.append(current)
            current = None
            if not line.upper().startswith("DMIG"):
                continue
            fields = _fields(line)
            if len(fields) < 2 or fields[1].strip().upper() != name:
                continue
            current = fields
        elif current is not None:
            current.extend(_fields(line)[1:])
    if current is not None:
        cards.append(current)
    # drop continuation markers of fixed format (the 10th field)
    out = []
    for c in cards:
        out.append([f.strip() for f in c])
    return out


def _fields(line: str) -> list[str]:
    if "," in line:
        return [f.strip() for f in line.split(",")]
    large = line[:8].strip().endswith("*") or line.startswith("*")
    w = 16 if large else 8
    fields = [line[:8]]
    body = line[8:]
    n = 4 if large else 8
    fields += [body[i * w : (i + 1) * w] for i in range(n)]
    return [f.strip() for f in fields]


def read_nodes(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Node ids and coordinates from a CSV ``id, x, y, z`` file."""
    p = Path(path)
    if not p.is_file():
        raise FEModelError(f"node file not found: {p}")
    ids, xyz = [], []
    for k, line in enumerate(p.read_text(encoding="utf-8").splitlines()):
        parts = [s for s in re.split(r"[,\s;]+", line.strip()) if s]
        if not parts or parts[0].startswith("#"):
            continue
        try:
            nid, pos = int(parts[0]), [float(v) for v in parts[1:4]]
            if len(pos) != 3:
                raise IndexError(line)
        except (ValueError, IndexError) as exc:
            if k == 0:
                continue  # header line
            raise FEModelError(f"{p}:{k + 1}: expected 'id, x, y, z', got {line!r}") from exc
        ids.append(nid)
        xyz.append(pos)
    if not ids:
        raise FEModelError(f"{p}: no nodes")
    ids_a = np.asarray(ids, dtype=np.int64)
    if np.unique(ids_a).size != ids_a.size:
        raise FEModelError(f"{p}: duplicate node ids")
    return ids_a, np.asarray(xyz, dtype=float).reshape(-1, 3)


def read_dof_map(path: str | Path) -> list[tuple[int, int]]:
    """(node id, component 0–5) of each matrix row from a CSV or ANSYS ``.mapping`` file."""
    p = Path(path)
    if not p.is_file():
        raise FEModelError(f"DOF map file not found: {p}")
    out: list[tuple[int, int, int]] = []
    for k, line in enumerate(p.read_text(encoding="utf-8", errors="replace").splitlines()):
        parts = [s for s in re.split(r"[,\s;]+", line.strip()) if s]
        if len(parts) < 3 or not parts[0].lstrip("-").isdigit():
            continue
        comp = parts[2].upper()
        if comp in _COMPONENTS:
            c = _COMPONENTS[comp]
        elif comp.isdigit() and 1 <= int(comp) <= 6:
            c = int(comp) - 1
        else:
            raise FEModelError(f"{p}:{k + 1}: unknown DOF component {parts[2]!r}")
        out.append((int(parts[0]), int(parts[1]), c))
    if not out:
        raise FEModelError(f"{p}: no DOF map entries (expected 'row, node, component')")
    out.sort()
    rows = [r for r, _, _ in out]
    base = rows[0]
    if rows != list(range(base, base + len(rows))):
        raise FEModelError(f"{p}: DOF map rows must be consecutive")
    return [(n, c) for _, n, c in out]


def _check_matrix(A: sp.spmatrix, what: str, n: int | None) -> sp.csc_matrix:
    if np.iscomplexobj(A.data if sp.issparse(A) else A):
        raise FEModelError(f"{what} matrix is complex; need a real matrix")
    A = sp.csc_matrix(A, dtype=float)
    if A.shape[0] != A.shape[1]:
        raise FEModelError(f"{what} matrix is not square: {A.shape}")
    if n is not None and A.shape[0] != n:
        raise FEModelError(f"{what} matrix has {A.shape[0]} rows, the DOF map has {n}")
    if not np.all(np.isfinite(A.data)):
        raise FEModelError(f"{what} matrix has NaN or infinite entries")
    scale = abs(A).max() if A.nnz else 0.0
    asym = abs(A - A.T).max() if A.nnz else 0.0
    if scale == 0.0:
        raise FEModelError(f"{what} matrix is zero")
    if asym > 1e-6 * scale:
        raise FEModelError(f"{what} matrix is not symmetric (max |A - Aᵀ| = {asym:.3g})")
    return ((A + A.T) * 0.5).tocsc()


def import_fe_model(
    name: str,
    stiffness: str | Path | sp.spmatrix,
    mass: str | Path | sp.spmatrix | None,
    nodes: str | Path | tuple[np.ndarray, np.ndarray],
    dof_map: str | Path | list[tuple[int, int]] | None = None,
    attachments: Mapping[str, int] | None = None,
    outputs: Mapping[str, int] | None = None,
    fmt: str | None = None,
    units: str = "SI",
    dmig_names: tuple[str, str] = ("KAAX", "MAAX"),
    op4_names: tuple[str, str] | None = None,
    constrained: Literal["error", "drop"] = "error",
) -> FEModel:
    """Build an :class:`FEModel` from external matrices.

    Parameters
    ----------
    name : str
        Model name.
    stiffness, mass : path or sparse matrix
        Matrix files (see module doc) or matrices. ``mass`` is None for an ANSYS ``.full``
        file (it holds both) and may be None for an OP4 file holding both matrices.
    nodes : path or (ids, coordinates)
        Node ids and coordinates (model axes; for vehicle bodies x forward, y left, z up
        from top of rail; length unit of ``units``).
    dof_map : path or list of (node id, component 0–5), optional
        Node and component of each matrix row; six per node in node order when omitted.
        DMIG files carry their own map (a given ``dof_map`` replaces it); ANSYS ``.full``
        files carry theirs and take none.
    attachments, outputs : dict of str to int, optional
        Named suspension-attachment and output nodes (node ids).
    fmt : {"mtx", "hb", "dmig", "op4", "ansys-full"}, optional
        File format (guessed from suffixes otherwise: ``.mtx``, ``.matrix``/``.hb``/``.rsa``,
        ``.dmig``/``.pch``/``.bdf``, ``.op4``, ``.full``).
    units : {"SI", "mm-t-s"}
        Unit system of the files (SI: m, kg, N; mm-t-s: mm, tonne, N).
    dmig_names : (str, str)
        DMIG names of the stiffness and mass matrices.
    op4_names : (str, str), optional
        OP4 names of the stiffness and mass matrices (e.g. ``("KGG", "MGG")``); may be omitted
        when each file holds a single matrix.
    constrained : {"error", "drop"}
        What to do with the DOFs an ANSYS ``.full`` file marks as constrained (their rows and
        columns are zero): ``"error"`` refuses the file, ``"drop"`` leaves them out (the model
        is then clamped, not free–free, and :func:`flexride.fem.flexible.flexible_body_from_model`
        rejects it; useful to check the matrices).

    Returns
    -------
    FEModel
        With ``K``, ``M`` (SI) set, ``info["dof_nodes"]``/``info["dof_components"]`` the node
        index and component (0–5) of each DOF.

    Raises
    ------
    FEModelError
        For unreadable, complex, non-symmetric, wrongly sized or inconsistent inputs, nodes
        missing from the node list, negative mass, DOFs without stiffness (constrained or
        unused DOFs) or a ``.full`` file with constrained DOFs (unless ``constrained="drop"``).
    """
    _check_options(units, constrained, fmt)
    if isinstance(nodes, tuple):
        ids, xyz = np.asarray(nodes[0], dtype=np.int64), np.asarray(nodes[1], dtype=float)
    else:
        ids, xyz = read_nodes(nodes)
    K, M, dmap, source = _read_matrices(stiffness, mass, dof_map, fmt, dmig_names, op4_names,
                                        constrained)
    dmap, pos = _resolve_dof_map(dmap, dof_map, ids)
    K, M = _checked_matrices(K, M, dmap)
    if units == "mm-t-s":
        xyz, K, M = _mm_t_s_to_si(xyz, K, M, dmap)
    return _fe_model(name, xyz, ids, K, M, dmap, pos, source, attachments, outputs)


def _resolve_dof_map(
    dmap: list[tuple[int, int]] | None,
    dof_map: str | Path | list[tuple[int, int]] | None,
    ids: np.ndarray,
) -> tuple[list[tuple[int, int]], dict[int, int]]:
    """The DOF map of the matrices: the given one, else the file's, else six per node.

    Parameters
    ----------
    dmap : list of (node id, component) or None
        DOF map carried by the matrix file.
    dof_map : path or list of (node id, component 0–5), optional
        DOF map given by the caller (replaces the file's).
    ids : numpy.ndarray
        Node ids in node-list order.

    Returns
    -------
    dmap : list of (node id, component 0–5)
        Node and component of each matrix row, checked against the node list.
    pos : dict of int to int
        Index of each node id in the node list.
    """
    if dof_map is not None:
        dmap = read_dof_map(dof_map) if isinstance(dof_map, (str, Path)) else list(dof_map)
    pos = {int(i): k for k, i in enumerate(ids)}
    if dmap is None:
        dmap = [(int(i), c) for i in ids for c in range(6)]
    _check_dof_map(dmap, pos)
    return dmap, pos


def _fe_model(
    name: str,
    xyz: np.ndarray,
    ids: np.ndarray,
    K: sp.csc_matrix,
    M: sp.csc_matrix,
    dmap: list[tuple[int, int]],
    pos: dict[int, int],
    source: dict,
    attachments: Mapping[str, int] | None,
    outputs: Mapping[str, int] | None,
) -> FEModel:
    """Assemble the imported :class:`FEModel` from checked SI inputs.

    Parameters
    ----------
    name : str
        Model name.
    xyz : numpy.ndarray
        (n, 3) node coordinates (m).
    ids : numpy.ndarray
        Node ids in node-list order.
    K, M : scipy.sparse.csc_matrix
        Stiffness (N/m, N·m/rad) and mass (kg, kg·m²).
    dmap : list of (node id, component 0–5)
        Node and component of each matrix row.
    pos : dict of int to int
        Index of each node id in the node list.
    source : dict
        Import metadata (``info["import"]``).
    attachments, outputs : dict of str to int, optional
        Named suspension-attachment and output nodes (node ids).

    Returns
    -------
    FEModel
        See :func:`import_fe_model`.
    """
    dof_nodes = np.array([pos[nid] for nid, _ in dmap], dtype=np.int64)
    dof_comp = np.array([c for _, c in dmap], dtype=np.int64)
    named = _named_nodes(attachments, outputs, pos)
    model = FEModel(
        name=name,
        mesh=Mesh(nodes=xyz),
        named_nodes=named,
        K=K,
        M=M,
        info={
            "source": "import",
            "import": source,
            "dof_nodes": dof_nodes,
            "dof_components": dof_comp,
            "attachments": list((attachments or {}).keys()),
            "outputs": list((outputs or {}).keys()),
            "node_ids": ids,
        },
    )
    return model


def _check_options(units: str, constrained: str, fmt: str | None) -> None:
    """Reject an unknown unit system, ``constrained`` policy or matrix format.

    Parameters
    ----------
    units : str
        Unit system name (see :data:`UNIT_SYSTEMS`).
    constrained : str
        ``"error"`` or ``"drop"``.
    fmt : str or None
        Matrix format (see :data:`FORMATS`) or None to guess it.
    """
    if units not in UNIT_SYSTEMS:
        raise FEModelError(f"unknown unit system {units!r}: use one of {UNIT_SYSTEMS}")
    if constrained not in ("error", "drop"):
        raise FEModelError(f"constrained must be 'error' or 'drop', not {constrained!r}")
    if fmt is not None and fmt not in FORMATS:
        raise FEModelError(f"unknown matrix format {fmt!r}: use one of {FORMATS}")


def _read_matrices(
    stiffness: str | Path | sp.spmatrix,
    mass: str | Path | sp.spmatrix | None,
    dof_map: str | Path | list[tuple[int, int]] | None,
    fmt: str | None,
    dmig_names: tuple[str, str],
    op4_names: tuple[str, str] | None,
    constrained: Literal["error", "drop"],
) -> tuple[sp.spmatrix, sp.spmatrix, list[tuple[int, int]] | None, dict]:
    """Read K and M (file units) in the format of the stiffness file, or take the matrices.

    Parameters
    ----------
    stiffness, mass, dof_map, fmt, dmig_names, op4_names, constrained
        As for :func:`import_fe_model`; ``dof_map`` is only checked here (none for ``.full``).

    Returns
    -------
    K, M : matrix
        Stiffness and mass in the units of the files, not yet checked.
    dmap : list of (node id, component) or None
        The DOF map the file carries (DMIG, ANSYS ``.full``), else None.
    source : dict
        Import metadata, at least ``{"format": kind}``.
    """
    is_file = isinstance(stiffness, (str, Path))
    kind = (fmt or _guess_format(Path(stiffness))) if is_file else "matrix"
    source: dict = {"format": kind}
    dmap: list[tuple[int, int]] | None = None
    if kind == "ansys-full":
        if mass is not None and Path(mass) != Path(stiffness):
            raise FEModelError("an ANSYS .full file holds both matrices: give mass=None")
        if dof_map is not None:
            raise FEModelError("an ANSYS .full file carries its own DOF map: give no dof_map")
        K, M, dmap, source = _ansys_full_matrices(Path(stiffness), constrained)
    elif kind == "op4":
        K, M = _op4_matrices(Path(stiffness), mass, op4_names)
    else:
        if mass is None:
            raise FEModelError("no mass matrix given")
        K, M, dmap = _read_pair(stiffness, mass, fmt, dmig_names)
    return K, M, dmap, source


def _check_dof_map(dmap: list[tuple[int, int]], pos: dict[int, int]) -> None:
    """Reject a DOF map naming unknown nodes or the same node and component twice.

    Parameters
    ----------
    dmap : list of (node id, component 0–5)
        Node and component of each matrix row.
    pos : dict of int to int
        Index of each node id in the node list.
    """
    missing = sorted({n for n, _ in dmap if n not in pos})
    if missing:
        raise FEModelError(
            f"the DOF map refers to nodes missing from the node list: {missing[:10]}"
            + (" ..." if len(missing) > 10 else "")
        )
    if len(set(dmap)) != len(dmap):
        raise FEModelError("the DOF map names the same node and component twice")


def _checked_matrices(K: sp.spmatrix, M: sp.spmatrix,
                      dmap: list[tuple[int, int]]) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    """Check K and M against the DOF map: size, symmetry, signs of the diagonals, empty rows.

    Parameters
    ----------
    K, M : matrix
        Stiffness and mass (file units).
    dmap : list of (node id, component 0–5)
        Node and component of each matrix row.

    Returns
    -------
    K, M : scipy.sparse.csc_matrix
        The checked matrices (units unchanged).
    """
    n = len(dmap)
    K = _check_matrix(K, "stiffness", n)
    M = _check_matrix(M, "mass", n)
    if np.any(M.diagonal() < 0):
        bad = int(np.argmin(M.diagonal()))
        raise FEModelError(
            f"negative mass on the diagonal of M (row {bad}: node {dmap[bad][0]}, "
            f"component {dmap[bad][1] + 1})"
        )
    if np.any(K.diagonal() < 0):
        raise FEModelError("negative stiffness on the diagonal of K")
    _check_no_empty_rows(K, dmap)
    return K, M


def _mm_t_s_to_si(xyz: np.ndarray, K: sp.csc_matrix, M: sp.csc_matrix,
                  dmap: list[tuple[int, int]]) -> tuple[np.ndarray, sp.csc_matrix, sp.csc_matrix]:
    """Convert nodes (mm → m), K (N/mm, N·mm/rad → N/m, N·m/rad) and M (t → kg) to SI.

    Parameters
    ----------
    xyz : numpy.ndarray
        Node coordinates (mm).
    K, M : scipy.sparse matrix
        Stiffness and mass in the mm-t-s system.
    dmap : list of (node id, component 0–5)
        Node and component of each matrix row (translations 0–2 scale, rotations do not).

    Returns
    -------
    xyz : numpy.ndarray
        Node coordinates (m).
    K, M : scipy.sparse.csc_matrix
        Stiffness and mass in SI units.
    """
    xyz = xyz * 1e-3
    d = np.array([1e3 if c < 3 else 1.0 for _, c in dmap])
    D = sp.diags(d)
    K = (1e-3 * (D @ K @ D)).tocsc()
    M = (1e-3 * (D @ M @ D)).tocsc()
    return xyz, K, M


def _named_nodes(attachments: Mapping[str, int] | None, outputs: Mapping[str, int] | None,
                 pos: dict[int, int]) -> dict[str, int]:
    """Node indices of the named attachment and output nodes.

    Parameters
    ----------
    attachments, outputs : dict of str to int or None
        Named node ids.
    pos : dict of int to int
        Index of each node id in the node list.

    Returns
    -------
    dict of str to int
        Node index of each name (outputs after attachments; a repeated name keeps the last).
    """
    named: dict[str, int] = {}
    for label, group in (("attachment", attachments), ("output", outputs)):
        for key, nid in (group or {}).items():
            if int(nid) not in pos:
                raise FEModelError(f"{label} node {key!r} = {nid} is not in the node list")
            named[key] = pos[int(nid)]
    return named


def _check_no_empty_rows(K: sp.csc_matrix, dmap: list[tuple[int, int]]) -> None:
    """Refuse DOFs whose stiffness row is zero (constrained, or not used by any element)."""
    empty = np.flatnonzero(np.asarray(abs(K).sum(axis=0)).ravel() == 0.0)
    if empty.size:
        where = ", ".join(f"node {dmap[i][0]} component {dmap[i][1] + 1}" for i in empty[:5])
        raise FEModelError(
            f"{empty.size} DOFs have no stiffness ({where}{' ...' if empty.size > 5 else ''}): "
            "they are constrained or not used by any element; flexride needs the free–free "
            "matrices of the DOFs the model uses (leave such DOFs out of the DOF map)"
        )


def _ansys_full_matrices(
    path: Path, constrained: str
) -> tuple[sp.csc_matrix, sp.csc_matrix, list[tuple[int, int]], dict]:
    full = read_ansys_full(path)
    K, M, dofs = full.K, full.M, full.dofs
    n_const = int(full.constrained.sum())
    if n_const and constrained == "error":
        nodes = sorted({dofs[i][0] for i in np.flatnonzero(full.constrained)})
        raise FEModelError(
            f"{path}: {n_const} DOFs at {len(nodes)} nodes are constrained (e.g. nodes "
            f"{nodes[:5]}); flexride needs the free–free matrices: remove the constraints (D) "
            "before writing the .full file, or pass constrained='drop' to leave these DOFs "
            "out (the model is then clamped and cannot become a flexible vehicle body)"
        )
    if n_const:
        keep = np.flatnonzero(~full.constrained)
        K, M = K[keep][:, keep].tocsc(), M[keep][:, keep].tocsc()
        dofs = [dofs[i] for i in keep]
    source = {
        "format": "ansys-full",
        "ansys_version": full.ansys_version,
        "dropped_constrained_dofs": n_const,
    }
    return K, M, dofs, source


def _op4_matrices(
    stiffness: Path, mass: str | Path | None, names: tuple[str, str] | None
) -> tuple[sp.csc_matrix, sp.csc_matrix]:
    mass_path = stiffness if mass is None else Path(mass)
    k_name, m_name = names if names is not None else (None, None)
    if names is None and mass_path == stiffness:
        raise FEModelError(
            f"{stiffness} holds both matrices: give their names, e.g. op4_names=('KGG', 'MGG')"
        )
    return read_op4(stiffness, k_name), read_op4(mass_path, m_name)


def _read_pair(stiffness, mass, fmt, dmig_names):
    if sp.issparse(stiffness) or isinstance(stiffness, np.ndarray):
        K = sp.csc_matrix(stiffness)
        M = sp.csc_matrix(mass)
        return K, M, None
    f = fmt or _guess_format(Path(stiffness))
    if f == "dmig":
        K, dk = read_dmig(stiffness, dmig_names[0])
        M, dm = read_dmig(mass, dmig_names[1])
        if dk != dm:
            # bring both onto the union of their DOFs
            alld = sorted(set(dk) | set(dm))
            K = _expand(K, dk, alld)
            M = _expand(M, dm, alld)
            dk = alld
        return K, M, [(g, c - 1) for g, c in dk]
    return read_matrix(stiffness, f), read_matrix(mass, f), None


def _expand(A: sp.spmatrix, dofs, alld) -> sp.csc_matrix:
    idx = {d: i for i, d in enumerate(alld)}
    P = sp.coo_matrix(
        (np.ones(len(dofs)), ([idx[d] for d in dofs], np.arange(len(dofs)))),
        shape=(len(alld), len(dofs)),
    )
    return (P @ A @ P.T).tocsc()

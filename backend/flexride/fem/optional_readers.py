"""Matrix readers that rely on optional packages: ANSYS ``.full`` and Nastran OP4.

Neither package is a flexride dependency; both are imported only when such a file is read, and
a missing package is an :class:`~flexride.errors.FEModelError` naming the pip command.

* ANSYS ``.full`` binaries through ``ansys-mapdl-reader`` (MIT). Its package ``__init__``
  imports pyvista and VTK (about 700 MB); the ``.full`` reader itself does not need them, so
  flexride supports ``pip install --no-deps ansys-mapdl-reader==0.56.0`` (4 MB): when the
  normal import fails, the submodule ``ansys.mapdl.reader.full`` is loaded without running the
  package ``__init__``.
* Nastran OP4 (binary or ASCII, dense or sparse) through ``pyyeti.nastran.op4`` (``pyyeti``,
  BSD-3); pyNastran's reader is not used because pyNastran requires NumPy < 2.
"""

from __future__ import annotations

import functools
import importlib
import importlib.util
import sys
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import numpy as np
import scipy.sparse as sp

from flexride.errors import FEModelError

ANSYS_READER_REQUIREMENT = "ansys-mapdl-reader==0.56.0"
ANSYS_READER_INSTALL = f"pip install --no-deps {ANSYS_READER_REQUIREMENT}"
PYYETI_REQUIREMENT = "pyyeti==1.4.7"
PYYETI_INSTALL = f"pip install {PYYETI_REQUIREMENT}"

#: ANSYS DOF reference numbers of the structural DOFs, to flexride components 0–5
ANSYS_DOF_LABELS = {1: "UX", 2: "UY", 3: "UZ", 4: "ROTX", 5: "ROTY", 6: "ROTZ"}


# -- ANSYS .full ---------------------------------------------------------------------------------


@functools.cache
def _ansys_full_module() -> ModuleType:
    """``ansys.mapdl.reader.full``, with or without the package's heavy dependencies."""
    try:
        return importlib.import_module("ansys.mapdl.reader.full")
    except Exception:  # ImportError, or e.g. a VTK that cannot load its libraries
        pass
    # Installed with --no-deps: the package __init__ fails on appdirs/pyvista. Load the submodule
    # under a bare package module with the right search path instead (the .full reader needs
    # only NumPy, SciPy and its own compiled helpers). Submodules the failed attempt imported
    # completely stay in sys.modules and are reused: compiled ones cannot be loaded twice.
    try:
        spec = importlib.util.find_spec("ansys.mapdl.reader")
    except Exception:  # a parent package missing or broken
        spec = None
    if spec is None or not spec.submodule_search_locations:
        raise FEModelError(
            "reading ANSYS .full files needs the optional package ansys-mapdl-reader: "
            f"{ANSYS_READER_INSTALL} (or export the matrices with HBMAT and read the .matrix "
            "files)"
        )
    stub = importlib.util.module_from_spec(spec)  # __path__ set, __init__ not executed
    sys.modules["ansys.mapdl.reader"] = stub
    try:
        return importlib.import_module("ansys.mapdl.reader.full")
    except Exception as exc:
        raise FEModelError(
            f"ansys-mapdl-reader {ansys_reader_version()} is installed but its .full reader "
            f"cannot be loaded ({exc}); flexride is tested with {ANSYS_READER_REQUIREMENT}"
        ) from exc
    finally:
        # leave no half-initialised package behind (a later normal import runs __init__)
        if sys.modules.get("ansys.mapdl.reader") is stub:
            del sys.modules["ansys.mapdl.reader"]


def ansys_reader_version() -> str | None:
    """Installed version of ``ansys-mapdl-reader`` (None if it is not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("ansys-mapdl-reader")
    except PackageNotFoundError:
        return None


@dataclass
class AnsysFull:
    """Matrices of an ANSYS ``.full`` file.

    Attributes
    ----------
    K, M : scipy.sparse.csc_matrix
        Symmetric stiffness and mass over all equations, in the units of the model (the file
        does not record them); rows and columns of constrained DOFs are zero.
    dofs : list of (int, int)
        (ANSYS node number, component 0–5 = UX UY UZ ROTX ROTY ROTZ) of each row, sorted by
        node then component.
    constrained : numpy.ndarray
        (n,) bool, True for the DOFs the analysis constrained (``D`` commands).
    labels : tuple of int
        The ANSYS DOF reference numbers of the model (1–6 = UX … ROTZ).
    ansys_version : str
        Version of ANSYS that wrote the file.
    """

    K: sp.csc_matrix
    M: sp.csc_matrix
    dofs: list[tuple[int, int]]
    constrained: np.ndarray
    labels: tuple[int, ...]
    ansys_version: str


def _full_triangle_to_symmetric(A: sp.spmatrix) -> sp.csc_matrix:
    """The symmetric matrix of the triangle the reader returns (a full matrix passes as is)."""
    A = sp.csc_matrix(A, dtype=float)
    if sp.tril(A, -1).nnz == 0:
        return (A + sp.triu(A, 1).T).tocsc()
    if sp.triu(A, 1).nnz == 0:
        return (A + sp.tril(A, -1).T).tocsc()
    return A


def read_ansys_full(path: str | Path) -> AnsysFull:
    """Read the stiffness and mass matrices of an ANSYS ``.full`` file.

    Parameters
    ----------
    path : str or Path
        The ``.full`` file (symmetric matrices, consistent mass), e.g. written by a modal
        analysis or by ``WRFULL``.

    Returns
    -------
    AnsysFull
        Matrices, DOF map and the constrained DOFs.

    Raises
    ------
    FEModelError
        If ``ansys-mapdl-reader`` is missing, the file cannot be read, holds a lumped or
        unsymmetric matrix or no mass matrix, or uses DOF labels other than UX … ROTZ, or nodes
        with only part of the model's DOF labels (their components cannot be told apart).
    """
    p = Path(path)
    if not p.is_file():
        raise FEModelError(f"ANSYS .full file not found: {p}")
    mod = _ansys_full_module()
    try:
        full = mod.FullFile(str(p))
    except NotImplementedError as exc:
        raise FEModelError(
            f"{p}: {exc} (ansys-mapdl-reader reads neither lumped mass nor unsymmetric "
            "matrices: export them with HBMAT in /AUX2 and read the .matrix files)"
        ) from exc
    except Exception as exc:
        raise FEModelError(f"cannot read ANSYS .full file {p}: {exc}") from exc
    try:
        dof_ref, k, m = full.load_km(sort=True)
        with open(p, "rb") as fh:  # record 3: the DOF reference numbers of the model
            mod.read_table(fh, skip=True)
            mod.read_table(fh, skip=True)
            labels = tuple(int(v) for v in np.asarray(mod.read_table(fh)).ravel())
        ndof = np.asarray(full.ndof)
        const = np.asarray(full.const).reshape(-1, 2)
    except FEModelError:
        raise
    except Exception as exc:
        raise FEModelError(f"cannot read the matrices of ANSYS .full file {p}: {exc}") from exc
    if k is None or m is None:
        raise FEModelError(
            f"{p} holds no {'stiffness' if k is None else 'mass'} matrix: write the .full file "
            "of a modal analysis"
        )
    if len(labels) != int(full._header["numdof"]):
        raise FEModelError(f"{p}: DOF label record does not match the header (numdof)")
    bad = [lab for lab in labels if lab not in ANSYS_DOF_LABELS]
    if bad:
        raise FEModelError(
            f"{p}: DOF labels {bad} (ANSYS DOF reference numbers) are not structural "
            "displacements or rotations; flexride reads UX UY UZ ROTX ROTY ROTZ (1–6) only"
        )
    if np.any(ndof != len(labels)):
        raise FEModelError(
            f"{p}: some nodes carry only part of the model's DOFs "
            f"{[ANSYS_DOF_LABELS[lab] for lab in labels]}; the .full file does not say which, "
            "so export with HBMAT and give the .mapping file as the DOF map"
        )
    comp_of = np.array([lab - 1 for lab in labels], dtype=np.int64)
    nodes = np.asarray(dof_ref[:, 0], dtype=np.int64)
    comps = comp_of[np.asarray(dof_ref[:, 1], dtype=np.int64)]
    dofs = [(int(n), int(c)) for n, c in zip(nodes, comps, strict=True)]
    const_set = {(int(n), int(comp_of[int(j)])) for n, j in const}
    constrained = np.array([d in const_set for d in dofs], dtype=bool)
    return AnsysFull(
        K=_full_triangle_to_symmetric(k),
        M=_full_triangle_to_symmetric(m),
        dofs=dofs,
        constrained=constrained,
        labels=labels,
        ansys_version=str(full._standard_header.get("verstring", "")),
    )


# -- Nastran OP4 ---------------------------------------------------------------------------------


def _op4_module() -> ModuleType:
    try:
        from pyyeti.nastran import op4
    except ImportError as exc:
        raise FEModelError(
            "reading Nastran OP4 files needs the optional package pyyeti: "
            f"{PYYETI_INSTALL} (or write the matrices as DMIG or MatrixMarket)"
        ) from exc
    return op4


def op4_directory(path: str | Path) -> list[tuple[str, tuple[int, int], int, int]]:
    """(name, (rows, columns), form, type) of each matrix in an OP4 file, in file order.

    Names as pyyeti gives them (lower case); the type is Nastran's (1, 2 real single/double,
    3, 4 complex single/double).
    """
    p = Path(path)
    if not p.is_file():  # pyyeti opens a file dialog for a directory or None
        raise FEModelError(f"OP4 file not found: {p}")
    op4 = _op4_module()
    try:
        names, sizes, forms, types = op4.dir(str(p), verbose=False)
    except Exception as exc:
        raise FEModelError(f"{p} is not a readable OP4 file: {exc}") from exc
    if not names:
        raise FEModelError(f"{p} holds no OP4 matrices")
    return [
        (str(n), (int(s[0]), int(s[1])), int(f), int(t))
        for n, s, f, t in zip(names, sizes, forms, types, strict=True)
    ]


_OP4_FACTOR_FORMS = {
    4: "lower triangular factor",
    5: "upper triangular factor",
    10: "Cholesky factor",
    11: "trapezoidal factor",
    13: "sparse lower triangular factor",
    15: "sparse upper triangular factor",
}


def read_op4(path: str | Path, name: str | None = None) -> sp.csc_matrix:
    """Read one real matrix from a Nastran OP4 file (binary or ASCII, dense or sparse).

    Parameters
    ----------
    path : str or Path
        The OP4 file.
    name : str, optional
        Matrix name (case does not matter); may be omitted when the file holds one matrix.

    Returns
    -------
    scipy.sparse.csc_matrix
        The matrix as stored in the file.

    Raises
    ------
    FEModelError
        If pyyeti is missing, the file is unreadable, the name is missing, ambiguous or occurs
        more than once, or the matrix is complex or a triangular factor.
    """
    p = Path(path)
    entries = op4_directory(p)
    names = [e[0].upper() for e in entries]
    if name is None:
        if len(entries) != 1:
            raise FEModelError(f"{p} holds the matrices {names}: say which one to read")
        index = 0
    else:
        hits = [i for i, n in enumerate(names) if n == name.upper()]
        if not hits:
            raise FEModelError(f"no matrix {name!r} in OP4 file {p} (it holds {names})")
        if len(hits) > 1:
            raise FEModelError(
                f"OP4 file {p} holds {len(hits)} matrices named {name!r} (e.g. one per "
                "superelement); write the one to import to a file of its own"
            )
        index = hits[0]
    key, shape, form, mtype = entries[index]
    if mtype not in (1, 2):
        raise FEModelError(
            f"OP4 matrix {key.upper()} in {p} is complex (type {mtype}); need a real matrix"
        )
    if form in _OP4_FACTOR_FORMS:
        raise FEModelError(
            f"OP4 matrix {key.upper()} in {p} is a {_OP4_FACTOR_FORMS[form]} (form {form}), not a "
            "mass or stiffness matrix"
        )
    op4 = _op4_module()
    try:
        _, mats, _, _ = op4.read(str(p), namelist=[key], into="list", sparse=True)
        (A,) = mats
    except Exception as exc:
        raise FEModelError(f"cannot read OP4 matrix {key.upper()} from {p}: {exc}") from exc
    A = sp.csc_matrix(A)
    if A.shape != shape:
        raise FEModelError(
            f"OP4 matrix {key.upper()} in {p}: read {A.shape}, the header says {shape}"
        )
    return sp.csc_matrix(A, dtype=float)

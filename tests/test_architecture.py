"""The layer map of docs/architecture.md ("Layers") and the import contract of .importlinter
say the same thing, cover the whole package, and their list of debts (the contracts'
ignore_imports, issue 27) holds only imports that still exist and are still debts.

``lint-imports`` (.ci/run) checks the contracts themselves; these tests read the contracts
with import-linter's own reader and the import graph with grimp (function-local and
``TYPE_CHECKING`` imports included, as the contracts see them).
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from pathlib import Path

import grimp
import pytest
from importlinter.api import read_configuration

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / ".importlinter"
DOC = ROOT / "docs" / "architecture.md"
PACKAGE = "flexride"

#: Modules in no layer: the root package (the public face above every layer, contract
#: ``root``) and a package ``__init__`` that holds only a docstring.
UNLAYERED = {PACKAGE, "flexride.study"}

Layer = tuple[str, tuple[str, ...]]
"""A layer: its separator (``"|"`` independent, ``":"`` not, ``""`` one module) and its
modules without the ``flexride.`` prefix."""


def _contracts() -> dict[str, dict]:
    """Contracts of .importlinter by id, as import-linter reads them.

    Returns
    -------
    dict
        Contract options (``type``, ``layers``, ``ignore_imports``, …) by contract id.
    """
    options = read_configuration(str(CONFIG))
    return {c["id"]: c for c in options["contracts_options"]}


def _as_list(value: str | list[str] | None) -> list[str]:
    """A contract option as a list (import-linter reads a one-line value as a string)."""
    if value is None:
        return []
    return [value] if isinstance(value, str) else list(value)


def _parse_layer(text: str, prefix: str = "") -> Layer:
    """One layer from its text, e.g. ``"solver | analysis"``.

    Parameters
    ----------
    text : str
        The layer as written: module names separated by ``|`` or ``:``.
    prefix : str
        Prefix removed from each module name (``"flexride."`` in the contract).

    Returns
    -------
    Layer
        The separator and the module names without the prefix.
    """
    sep = "|" if "|" in text else ":" if ":" in text else ""
    if sep == "|" and ":" in text:
        raise ValueError(f"layer mixes '|' and ':': {text!r}")
    names = [n.strip() for n in (text.split(sep) if sep else [text])]
    return sep, tuple(n.removeprefix(prefix) for n in names)


def _contract_layers() -> list[Layer]:
    """Layers of the contract ``layers``, highest first, without the ``flexride.`` prefix."""
    layers = _as_list(_contracts()["layers"]["layers"])
    return [_parse_layer(text, prefix=f"{PACKAGE}.") for text in layers]


def _doc_layers() -> list[Layer]:
    """Layers of the ```` ```text ```` block of docs/architecture.md's section "Layers".

    Comment lines (``#``) and blank lines are skipped; a line that starts with ``|`` or ``:``
    continues the layer above.

    Returns
    -------
    list of Layer
        The layers, highest first.
    """
    text = DOC.read_text(encoding="utf-8")
    section = re.search(r"^## Layers\n(.*?)(?=^## )", text, flags=re.S | re.M)
    assert section, "docs/architecture.md has no section '## Layers'"
    block = re.search(r"```text\n(.*?)```", section.group(1), flags=re.S)
    assert block, "the section 'Layers' has no ```text block"
    lines: list[str] = []
    for raw in block.group(1).splitlines():
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        if line[0] in "|:" and lines:
            lines[-1] = f"{lines[-1]} {line}"
        else:
            lines.append(line)
    return [_parse_layer(line) for line in lines]


def _split(expression: str) -> tuple[str, str]:
    """Importer and imported of an ignore_imports entry ``a.b -> c.d``."""
    importer, imported = (part.strip() for part in expression.split("->"))
    if "*" in importer or "*" in imported:
        raise ValueError(f"wildcards are not used in the debt list: {expression!r}")
    return importer, imported


def _ignored(contract_ids: Iterable[str] | None = None) -> list[tuple[str, str, str]]:
    """Ignored imports of the contracts, as (contract id, importer, imported).

    Parameters
    ----------
    contract_ids : iterable of str, optional
        The contracts to read; every contract when None.

    Returns
    -------
    list of tuple
        One entry per ignored import.
    """
    contracts = _contracts()
    ids = list(contracts) if contract_ids is None else list(contract_ids)
    return [(cid, *_split(entry))
            for cid in ids
            for entry in _as_list(contracts[cid].get("ignore_imports"))]


@pytest.fixture(scope="module")
def graph() -> grimp.ImportGraph:
    """The package's import graph with the external packages it imports (no cache)."""
    return grimp.build_graph(PACKAGE, include_external_packages=True, cache_dir=None)


def _layer_index(module: str, layers: list[Layer]) -> int | None:
    """Index (0 = highest) of the layer that holds ``module``, or None."""
    for index, (_, names) in enumerate(layers):
        for name in names:
            full = f"{PACKAGE}.{name}"
            if module == full or module.startswith(full + "."):
                return index
    return None


def _internal_imports(graph: grimp.ImportGraph) -> dict[str, set[str]]:
    """The package's modules and, for each, the package's modules it imports directly."""
    internal = {m for m in graph.modules if m == PACKAGE or m.startswith(PACKAGE + ".")}
    return {m: graph.find_modules_directly_imported_by(m) & internal for m in internal}


def _reaches(imports: dict[str, set[str]], start: str, goal: str,
             without: set[tuple[str, str]]) -> bool:
    """Whether an import chain leads from ``start`` to ``goal``.

    Parameters
    ----------
    imports : dict
        Each module's direct imports (:func:`_internal_imports`).
    start, goal : str
        Module names; ``start == goal`` counts as a chain.
    without : set of tuple
        Imports (importer, imported) left out.

    Returns
    -------
    bool
        True when a chain exists.
    """
    seen, todo = {start}, [start]
    while todo:
        module = todo.pop()
        if module == goal:
            return True
        for imported in imports[module]:
            if imported not in seen and (module, imported) not in without:
                seen.add(imported)
                todo.append(imported)
    return False


def test_the_docs_layer_section_is_the_contracts_layers():
    doc, contract = _doc_layers(), _contract_layers()
    assert doc == contract, (
        "docs/architecture.md 'Layers' and .importlinter's layers differ:\n"
        f"doc:      {doc}\ncontract: {contract}")


def _short(module: str) -> str:
    """A module's name without the ``flexride.`` prefix, as the doc writes it."""
    return module.removeprefix(f"{PACKAGE}.")


def _doc_debt_table() -> tuple[set[tuple[str, str]], set[str]]:
    """The table of ignored imports in docs/architecture.md's section "Layers".

    Returns
    -------
    pairs : set of tuple
        Every ``importer → imported`` the table names (short module names).
    root_importers : set of str
        The modules its row "a public face" names as importers of the root package.
    """
    text = DOC.read_text(encoding="utf-8")
    table = re.search(r"^\| Issue-27 item \|.*?\n((?:\|.*\n)+)", text, flags=re.M)
    assert table, "the section 'Layers' has no table of ignored imports"
    pairs: set[tuple[str, str]] = set()
    root_importers: set[str] = set()
    for row in table.group(1).splitlines():
        if set(row) <= set("|- "):
            continue
        pairs |= set(re.findall(r"`([\w.]+) → ([\w.]+)`", row))
        if row.startswith("| a public face |"):
            root_importers = {n for n in re.findall(r"`([\w.]+)`", row)
                              if not n.startswith("__")}
    return pairs, root_importers


def test_the_docs_debt_table_is_the_contracts_ignore_list():
    pairs, root_importers = _doc_debt_table()
    expected = {(_short(a), _short(b)) for cid, a, b in _ignored()
                if cid != "root" and a != PACKAGE}
    assert pairs == expected, (f"only in the doc: {sorted(pairs - expected)}; "
                               f"only in .importlinter: {sorted(expected - pairs)}")
    assert root_importers == {_short(a) for _, a, _ in _ignored(["root"])}


def test_every_module_of_the_package_is_in_a_layer(graph):
    layers = _contract_layers()
    internal = {m for m in graph.modules if m == PACKAGE or m.startswith(PACKAGE + ".")}
    unplaced = {m for m in internal if _layer_index(m, layers) is None}
    assert unplaced == UNLAYERED, f"modules in no layer: {sorted(unplaced - UNLAYERED)}"
    # the unlayered package __init__ imports nothing of the package (it would escape the check)
    for module in UNLAYERED - {PACKAGE}:
        assert not {m for m in graph.find_modules_directly_imported_by(module)
                    if m.startswith(PACKAGE)}, module


def test_every_ignored_import_still_exists(graph):
    stale = [f"[{cid}] {a} -> {b}" for cid, a, b in _ignored()
             if not graph.direct_import_exists(importer=a, imported=b)]
    assert not stale, ("debt paid: delete these entries from .importlinter (and the "
                       "docs/architecture.md table): " + "; ".join(stale))


def test_every_ignored_layer_import_still_points_up(graph):
    layers = _contract_layers()
    paid = []
    for _, importer, imported in _ignored(["layers"]):
        low, high = _layer_index(importer, layers), _layer_index(imported, layers)
        if low is None:
            # the root package (above every layer): its import of a layer is a debt only
            # while a module below that layer imports the root (a chain up through it)
            assert importer == PACKAGE, importer
            needed = any((i := _layer_index(m, layers)) is not None and i > high
                         for m in graph.find_modules_that_directly_import(PACKAGE))
        else:
            sep = layers[low][0]
            needed = high is not None and (high < low or (high == low and sep == "|"))
        if not needed:
            paid.append(f"{importer} -> {imported}")
    assert not paid, f"no longer upward: delete from the layers contract: {paid}"


def test_the_graph_has_no_cycle_outside_the_listed_debt(graph):
    imports = _internal_imports(graph)
    debt = {(a, b) for _, a, b in _ignored()}
    # a cycle exists iff some import a -> b has a chain back from b to a
    cycles = [f"{a} -> {b}" for a in sorted(imports) for b in sorted(imports[a])
              if (a, b) not in debt and _reaches(imports, b, a, debt)]
    assert not cycles, f"imports on a cycle: {cycles}"


def test_every_ignored_cycle_import_still_closes_a_cycle(graph):
    imports = _internal_imports(graph)
    debt = {(a, b) for _, a, b in _ignored()}
    paid = [f"{a} -> {b}" for _, a, b in _ignored(["acyclic"])
            if b not in imports.get(a, set()) or not _reaches(imports, b, a, debt - {(a, b)})]
    assert not paid, f"on no cycle any more: delete from the acyclic contract: {paid}"

"""Terminal output of the CLI: tables fitted to the terminal's width and the legend of the
measuring points.

:func:`fit_table` lets a :class:`rich.table.Table` wrap its cells at word boundaries instead of
cutting words (``excell…``): every column is at least as wide as its longest word, and a table
wider than the terminal drops its vertical rules and outer padding. :func:`points_legend` is the
line under a comfort table that says what and where each point is, read from the run's recorded
points (the one list, :data:`flexride.vehicle.topology.PAPER_POINTS`, and the user's points).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

from rich import box
from rich.console import Console
from rich.table import Column, Table
from rich.text import Text

__all__ = ["fit_table", "points_legend"]


def _plain(cell: Any) -> str:
    """The text of a cell without its markup."""
    return cell.plain if isinstance(cell, Text) else Text.from_markup(str(cell)).plain


def _column_range(col: Column) -> tuple[int, int]:
    """(longest word, longest line) of a column's header and cells, in characters."""
    texts = [_plain(col.header), *(_plain(c) for c in col.cells)]
    word = max((len(w) for s in texts for w in s.split()), default=0)
    line = max((len(ln) for s in texts for ln in s.splitlines() or [""]), default=0)
    return word, line


def _natural_width(console: Console, table: Table) -> int:
    """Width (characters) the table takes without any wrapping."""
    return console.measure(table, options=console.options.update_width(10_000)).maximum


def _share(widths: list[int], wants: list[int], extra: int) -> list[int]:
    """``widths`` plus ``extra`` characters shared in proportion to what each still wants."""
    total = sum(wants)
    if total <= 0 or extra <= 0:
        return widths
    add = [extra * w // total for w in wants]
    for i in sorted(range(len(wants)), key=lambda i: -wants[i])[: extra - sum(add)]:
        add[i] += 1
    return [w + a for w, a in zip(widths, add, strict=True)]


def fit_table(table: Table, console: Console) -> Table:
    """Fit ``table`` to the width of ``console`` without cutting words.

    A table wider than the terminal becomes compact (no vertical rules, no outer padding) and
    its columns get fixed widths: each at least its longest word (header included), the rest
    of the terminal's width shared in proportion to how much wider each column would like to
    be. rich then wraps cells between words rather than ending a word with an ellipsis
    (``excell…``). A table that fits is left as it is.

    Parameters
    ----------
    table : rich.table.Table
        A filled table (changed in place).
    console : rich.console.Console
        The console it is printed on (its ``width`` in characters).

    Returns
    -------
    rich.table.Table
        ``table`` itself.
    """
    if _natural_width(console, table) <= console.width:
        return table
    table.box = box.SIMPLE_HEAD
    table.padding = (0, 1)
    table.pad_edge = False
    table.show_edge = False
    ranges = [_column_range(col) for col in table.columns]
    lines = [line for _, line in ranges]
    overhead = _natural_width(console, table) - sum(lines)
    words = [word for word, _ in ranges]
    widths = _share(words, [line - word for word, line in ranges],
                    console.width - overhead - sum(words))
    for col, width in zip(table.columns, widths, strict=True):
        col.width = max(width, 1)
        col.overflow = "fold"
    return table


def points_legend(points: Iterable[Mapping[str, Any]], names: Iterable[str]) -> Text:
    """One line naming each point of a table: what it is and where it sits.

    Parameters
    ----------
    points : iterable of mapping
        The run's recorded points (``Results.recorded_points``: ``body``, ``name``,
        ``description``, ``x``, ``y``, ``z`` in m).
    names : iterable of str
        The points the table shows, in its order.

    Returns
    -------
    rich.text.Text
        ``Points: PR roof above the front bogie centre (x 6.3, y 0, z 3.8 m) · …``; empty when
        no point is known.
    """
    known = {p["name"]: p for p in points if p.get("body", "carbody") == "carbody"}
    parts = []
    for name in names:
        p = known.get(name)
        if p is None:
            continue
        desc = str(p.get("description") or "")
        desc = desc.removeprefix(f"{name}: ")
        parts.append(f"{name} {desc} (x {p['x']:g}, y {p['y']:g}, z {p['z']:g} m)")
    if not parts:
        return Text("")
    text = Text("Points: ", style="bold")
    text.append(" · ".join(parts) + " — car-body coordinates: x forward from the centre, "
                "y left, z above top of rail.")
    return text

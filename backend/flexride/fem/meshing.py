"""Small structured-meshing helpers: mesh lines through key points, a node registry, the
lists of elements being generated.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Iterable

import numpy as np


def mesh_lines(lo: float, hi: float, size: float, keys: tuple[float, ...] = ()) -> np.ndarray:
    """Coordinates from ``lo`` to ``hi`` through every key point, spaced at most ``size``.

    Each interval between consecutive key points is divided into equal parts.
    """
    pts = sorted({round(float(k), 9) for k in (lo, hi, *keys) if lo - 1e-9 <= k <= hi + 1e-9})
    out = [pts[0]]
    for a, b in itertools.pairwise(pts):
        if b - a < 1e-9:
            continue
        n = max(1, int(np.ceil((b - a) / size - 1e-6)))
        out.extend(np.linspace(a, b, n + 1)[1:].tolist())
    return np.asarray(out)


class NodeRegistry:
    """Creates nodes, merging coincident ones (within ``tol`` m)."""

    def __init__(self, tol: float = 1e-6):
        self.tol = tol
        self._index: dict[tuple[int, int, int], int] = {}
        self.coords: list[tuple[float, float, float]] = []
        self.region: list[int] = []

    def node(self, x: float, y: float, z: float, region: int = 0) -> int:
        """Index of the node at (x, y, z), created with ``region`` when new."""
        key = (round(x / self.tol), round(y / self.tol), round(z / self.tol))
        i = self._index.get(key)
        if i is None:
            i = len(self.coords)
            self._index[key] = i
            self.coords.append((float(x), float(y), float(z)))
            self.region.append(region)
        return i

    def array(self) -> np.ndarray:
        """(n, 3) coordinates."""
        return np.asarray(self.coords, dtype=float).reshape(-1, 3)


class ElementLists:
    """Quads and beams collected while a structured mesh is generated, with their groups.

    Attributes
    ----------
    quads : list of (int, int, int, int)
        Node indices of each four-node shell.
    quad_group : list of int
        Shell section of each quad.
    beams : list of (int, int)
        Node indices of each beam.
    beam_group : list of int
        Beam section of each beam.
    beam_vxy : list of (float, float, float)
        A vector in each beam's local x–y plane (section orientation).
    """

    def __init__(self) -> None:
        self.quads: list[tuple[int, int, int, int]] = []
        self.quad_group: list[int] = []
        self.beams: list[tuple[int, int]] = []
        self.beam_group: list[int] = []
        self.beam_vxy: list[tuple[float, float, float]] = []

    def add_grid(self, grid: np.ndarray, group: int,
                 skip: Callable[[int, int], bool] | None = None) -> None:
        """A quad on every cell of a (rows, columns) grid of node indices, row by row, except
        the cells ``(i, j)`` for which ``skip(i, j)`` is true.
        """
        for i in range(grid.shape[0] - 1):
            for j in range(grid.shape[1] - 1):
                if skip is not None and skip(i, j):
                    continue
                self.quads.append(
                    (grid[i, j], grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1]))
                self.quad_group.append(group)

    def add_line(self, nodes: Iterable[int], group: int,
                 vxy: tuple[float, float, float]) -> None:
        """A beam between each pair of consecutive nodes, oriented by ``vxy``."""
        for a, b in itertools.pairwise(nodes):
            self.beams.append((int(a), int(b)))
            self.beam_group.append(group)
            self.beam_vxy.append(vxy)

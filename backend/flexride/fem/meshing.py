"""Small structured-meshing helpers: mesh lines through key points, a node registry."""

from __future__ import annotations

import itertools

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

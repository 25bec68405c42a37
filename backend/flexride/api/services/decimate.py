"""Server-side decimation of long records for plotting.

* ``minmax`` — per bucket of consecutive samples, the smallest and the largest sample in time
  order: every peak survives, so the plotted envelope is exact (the default);
* ``lttb`` — Largest-Triangle-Three-Buckets (Steinarsson 2013): one sample per bucket chosen to
  keep the visual shape; compiled with numba (cached on disk like the solver's kernels, in the
  directory that importing :mod:`flexride` configures).

Both return *indices* into the record, sorted, so time, distance and values stay aligned.
"""

from __future__ import annotations

import numpy as np
from numba import njit


def minmax_indices(y: np.ndarray, max_points: int) -> np.ndarray:
    """Indices of the min and max sample of each of ``max_points // 2`` buckets.

    Parameters
    ----------
    y : numpy.ndarray
        Record, shape ``(n,)``.
    max_points : int
        Most indices returned (≥ 2).
    """
    n = int(y.size)
    if n <= max_points:
        return np.arange(n)
    n_buckets = max(1, max_points // 2)
    size = -(-n // n_buckets)  # ceil
    n_buckets = -(-n // size)
    padded = np.empty(n_buckets * size, dtype=np.float64)
    padded[:n] = y
    padded[n:] = y[-1]
    rows = padded.reshape(n_buckets, size)
    base = np.arange(n_buckets) * size
    i_min = np.minimum(base + np.argmin(rows, axis=1), n - 1)
    i_max = np.minimum(base + np.argmax(rows, axis=1), n - 1)
    idx = np.sort(np.concatenate([i_min, i_max]))
    return np.unique(idx)


@njit(cache=True)
def _lttb(x: np.ndarray, y: np.ndarray, n_out: int) -> np.ndarray:  # pragma: no cover - numba
    n = x.size
    out = np.empty(n_out, dtype=np.int64)
    out[0] = 0
    out[n_out - 1] = n - 1
    every = (n - 2) / (n_out - 2)
    a = 0
    for i in range(n_out - 2):
        s0 = int(np.floor((i + 1) * every)) + 1
        s1 = int(np.floor((i + 2) * every)) + 1
        if s1 > n:
            s1 = n
        if s0 >= s1:
            s0 = n - 1
            s1 = n
        ax = 0.0
        ay = 0.0
        for k in range(s0, s1):
            ax += x[k]
            ay += y[k]
        ax /= s1 - s0
        ay /= s1 - s0
        r0 = int(np.floor(i * every)) + 1
        r1 = int(np.floor((i + 1) * every)) + 1
        if r1 > n - 1:
            r1 = n - 1
        best = r0
        best_area = -1.0
        for j in range(r0, r1):
            area = abs((x[a] - ax) * (y[j] - y[a]) - (x[a] - x[j]) * (ay - y[a]))
            if area > best_area:
                best_area = area
                best = j
        out[i + 1] = best
        a = best
    return out


def lttb_indices(x: np.ndarray, y: np.ndarray, max_points: int) -> np.ndarray:
    """Indices chosen by Largest-Triangle-Three-Buckets (first and last sample included)."""
    n = int(y.size)
    if n <= max_points or max_points < 3:
        return np.arange(n) if n <= max_points else np.array([0, n - 1])
    idx = _lttb(_writable(x), _writable(y), int(max_points))
    return np.unique(idx)


def _writable(a: np.ndarray) -> np.ndarray:
    """``a`` as a contiguous, writable float64 array (copied only if needed): cached result
    arrays are read-only, and numba would compile a second LTTB for read-only arrays.
    """
    a = np.ascontiguousarray(a, dtype=np.float64)
    return a if a.flags.writeable else a.copy()


def decimate_indices(x: np.ndarray, y: np.ndarray, max_points: int, method: str) -> np.ndarray:
    """Indices of the samples to plot (all of them when the record is short enough)."""
    if method == "none" or y.size <= max_points:
        return np.arange(y.size)
    if method == "lttb":
        return lttb_indices(x, y, max_points)
    if method == "minmax":
        return minmax_indices(y, max_points)
    raise ValueError(f"unknown decimation method {method!r}")

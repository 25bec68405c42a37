"""Discretisation error of a quantity computed on three meshes: observed order of convergence,
Richardson extrapolation and Roache's grid convergence index (GCI).

The procedure is that of Celik, Ghia, Roache, Freitas, Coleman and Raad, "Procedure for
estimation and reporting of uncertainty due to discretization in CFD applications", J. Fluids
Eng. 130 (2008) 078001, which holds for any discretisation whose error behaves as C·hᵖ:

* element sizes h₁ < h₂ < h₃ (fine to coarse), ratios r₂₁ = h₂/h₁, r₃₂ = h₃/h₂ (any, not
  necessarily equal), values φ₁, φ₂, φ₃, differences ε₂₁ = φ₂ − φ₁, ε₃₂ = φ₃ − φ₂;
* the observed order p solves p = |ln|ε₃₂/ε₂₁| + q(p)| / ln r₂₁ with
  q(p) = ln((r₂₁ᵖ − s)/(r₃₂ᵖ − s)), s = sign(ε₃₂/ε₂₁) (fixed-point iteration; q = 0 for equal
  ratios);
* the extrapolated value φ_ext = (r₂₁ᵖ φ₁ − φ₂)/(r₂₁ᵖ − 1);
* the fine mesh's GCI = 1.25 |(φ₁ − φ₂)/φ₁| / (r₂₁ᵖ − 1), a band expected to hold the
  converged value (the factor 1.25 is the three-mesh safety factor).

Oscillatory convergence (s < 0: the differences change sign) is flagged: the order and the
extrapolation then do not describe the error, only the spread of the values bounds it.

With two meshes only, the order is the discretisation's theoretical one and the safety factor
3 (Roache 1994): :func:`two_mesh_estimate`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from flexride.errors import FEModelError

#: Safety factor of the GCI with three meshes (Roache; Celik et al. 2008).
SAFETY_FACTOR = 1.25
#: Safety factor of the GCI with two meshes and an assumed order (Roache, "Perspective: a
#: method for uniform reporting of grid refinement studies", J. Fluids Eng. 116 (1994) 405).
TWO_MESH_SAFETY_FACTOR = 3.0
#: Order of the FE bodies' elements, assumed where only two meshes are known: the bilinear
#: shells' (and the lower of the beams' orders), observed on the plate of
#: tests/fem/test_convergence.py.
ELEMENT_ORDER = 2.0
#: Iterations and tolerance of the fixed-point solution for the order.
_MAX_ITERATIONS = 200
_ORDER_TOL = 1.0e-10


@dataclass(frozen=True)
class ConvergenceEstimate:
    """What three meshes say about a quantity's discretisation error.

    Attributes
    ----------
    sizes : tuple of float
        Element sizes h₁ < h₂ (< h₃) (m), fine to coarse.
    values : tuple of float
        The quantity on them (any unit).
    order : float
        Observed order of convergence p (-), or the assumed one (``order_assumed``); NaN when
        the two finer values are equal.
    extrapolated : float
        Richardson-extrapolated value (the quantity's unit); the finest value when the order
        is undefined.
    gci_fine : float
        Grid convergence index of the finest mesh (-, relative to its value): the converged
        value is expected within ±``gci_fine`` of it.
    error_fine : float
        Relative difference of the finest value from the extrapolated one (-).
    oscillatory : bool
        The differences between successive meshes change sign.
    order_assumed : bool
        Two meshes only: the order is the discretisation's theoretical one, not observed, and
        the GCI's safety factor :data:`TWO_MESH_SAFETY_FACTOR`.
    """

    sizes: tuple[float, ...]
    values: tuple[float, ...]
    order: float
    extrapolated: float
    gci_fine: float
    error_fine: float
    oscillatory: bool
    order_assumed: bool = False

    def to_dict(self) -> dict:
        """JSON-able dict (NaN and infinity as None)."""
        def num(v: float) -> float | None:
            return v if math.isfinite(v) else None

        return {"sizes_m": list(self.sizes), "values": list(self.values),
                "order": num(self.order), "order_assumed": self.order_assumed,
                "extrapolated": num(self.extrapolated), "gci_fine": num(self.gci_fine),
                "error_fine": num(self.error_fine), "oscillatory": self.oscillatory}


def three_mesh_estimate(sizes: Sequence[float], values: Sequence[float]
                        ) -> ConvergenceEstimate:
    """Observed order, Richardson extrapolation and GCI from three meshes (module docs).

    Parameters
    ----------
    sizes : sequence of three float
        Element sizes (m) in any order; they must differ.
    values : sequence of three float
        The quantity on each mesh, in the order of ``sizes``.

    Returns
    -------
    ConvergenceEstimate

    Raises
    ------
    FEModelError
        Not three sizes and values, sizes not positive and distinct, or values not finite.
    """
    h, phi = _sorted_fine_to_coarse(sizes, values)
    e21, e32 = phi[1] - phi[0], phi[2] - phi[1]
    if e21 == 0.0:
        return ConvergenceEstimate(h, phi, math.nan, phi[0], 0.0, 0.0, False)
    r21, r32 = h[1] / h[0], h[2] / h[1]
    s = 1.0 if e32 / e21 >= 0.0 else -1.0
    p = observed_order(e21, e32, r21, r32)
    if r21**p - 1.0 <= _ORDER_TOL:  # no observable convergence: no extrapolation, no band
        return ConvergenceEstimate(h, phi, p, math.nan, math.inf, math.nan, s < 0.0)
    extrapolated = (r21**p * phi[0] - phi[1]) / (r21**p - 1.0)
    gci = SAFETY_FACTOR * abs(e21 / phi[0]) / (r21**p - 1.0) if phi[0] else math.inf
    error = abs((extrapolated - phi[0]) / extrapolated) if extrapolated else math.inf
    return ConvergenceEstimate(h, phi, p, extrapolated, gci, error, s < 0.0)


def two_mesh_estimate(sizes: Sequence[float], values: Sequence[float], order: float
                      ) -> ConvergenceEstimate:
    """Richardson extrapolation and GCI from two meshes with an assumed ``order`` (-): the
    estimate of one build and a cheap coarser companion, where a third mesh would cost more
    than the build (safety factor :data:`TWO_MESH_SAFETY_FACTOR`).

    Raises
    ------
    FEModelError
        Not two distinct positive sizes and two finite values, or an order that is not
        positive.
    """
    if len(sizes) != 2 or len(values) != 2:
        raise FEModelError("a two-mesh estimate needs two element sizes and two values")
    if not (math.isfinite(order) and order > 0.0):
        raise FEModelError(f"the assumed order must be positive, got {order}")
    (h1, f1), (h2, f2) = sorted(zip(map(float, sizes), map(float, values), strict=True))
    if not all(math.isfinite(v) for v in (h1, h2, f1, f2)) or h1 <= 0.0 or h1 == h2:
        raise FEModelError(f"two distinct positive element sizes and finite values needed, "
                           f"got {list(sizes)} and {list(values)}")
    factor = (h2 / h1) ** order - 1.0
    extrapolated = f1 + (f1 - f2) / factor
    gci = TWO_MESH_SAFETY_FACTOR * abs((f1 - f2) / f1) / factor if f1 else math.inf
    error = abs((extrapolated - f1) / extrapolated) if extrapolated else math.inf
    return ConvergenceEstimate((h1, h2), (f1, f2), float(order), extrapolated, gci, error,
                               False, order_assumed=True)


def observed_order(e21: float, e32: float, r21: float, r32: float) -> float:
    """The observed order p (-) from the differences of the fine pair ``e21`` and the coarse
    pair ``e32`` and the refinement ratios ``r21``, ``r32`` (> 1), by fixed-point iteration
    of Celik et al.'s equation (module docs).
    """
    s = 1.0 if e32 / e21 >= 0.0 else -1.0
    ratio = abs(e32 / e21)
    p = abs(math.log(ratio)) / math.log(r21)
    for _ in range(_MAX_ITERATIONS):
        num, den = r21**p - s, r32**p - s
        if num <= 0.0 or den <= 0.0:  # p → 0: the values do not converge
            return p
        q = math.log(num / den) if r21 != r32 else 0.0
        nxt = abs(math.log(ratio) + q) / math.log(r21)
        if abs(nxt - p) <= _ORDER_TOL * max(1.0, p):
            return nxt
        p = nxt
    return p


def _sorted_fine_to_coarse(sizes: Sequence[float], values: Sequence[float]
                           ) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """``(h₁, h₂, h₃), (φ₁, φ₂, φ₃)`` fine to coarse, after checking them."""
    if len(sizes) != 3 or len(values) != 3:
        raise FEModelError("a three-mesh estimate needs three element sizes and three values, "
                           f"got {len(sizes)} and {len(values)}")
    pairs = sorted(zip(map(float, sizes), map(float, values), strict=True))
    h = tuple(p[0] for p in pairs)
    phi = tuple(p[1] for p in pairs)
    if not all(math.isfinite(v) for v in (*h, *phi)) or h[0] <= 0.0:
        raise FEModelError(f"element sizes must be positive and values finite, got {sizes} "
                           f"and {values}")
    if h[0] == h[1] or h[1] == h[2]:
        raise FEModelError(f"the three element sizes must differ, got {sorted(sizes)}")
    return (h[0], h[1], h[2]), (phi[0], phi[1], phi[2])

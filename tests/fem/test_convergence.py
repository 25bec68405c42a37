"""Three-mesh convergence estimates (Celik et al. 2008) against exact cases: a quantity that
follows f₀ + C·hᵖ exactly gives back p and f₀ for equal and unequal refinement ratios, and the
fundamental frequency of a simply supported thin plate meshed with the shell elements the car
body is built of converges at the elements' second order to Navier's closed form, inside the
fine mesh's GCI band."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexride.errors import FEModelError
from flexride.fem.convergence import three_mesh_estimate
from flexride.fem.eigen import solve_modes
from flexride.fem.pyfe3d_adapter import ALUMINIUM, Mesh, ShellSection, assemble


@pytest.mark.parametrize("sizes", [(0.1, 0.2, 0.4), (0.1, 0.15, 0.3), (0.3, 0.1, 0.17)])
@pytest.mark.parametrize(("p", "c"), [(2.0, 3.0), (1.0, -0.5), (4.0, 10.0)])
def test_an_exact_power_law_gives_its_order_and_limit(sizes, p, c):
    f0 = 7.5
    est = three_mesh_estimate(sizes, [f0 + c * h**p for h in sizes])
    assert est.order == pytest.approx(p, rel=1e-8)
    assert est.extrapolated == pytest.approx(f0, rel=1e-10)
    assert not est.oscillatory and est.sizes == tuple(sorted(sizes))
    h1 = min(sizes)
    assert est.error_fine == pytest.approx(abs(c * h1**p / f0), rel=1e-8)
    # the band: 1.25 x the fine mesh's error (relative to its own value) when the order is right
    assert est.gci_fine == pytest.approx(1.25 * abs(c * h1**p) / est.values[0], rel=1e-8)


def test_oscillating_values_are_flagged():
    est = three_mesh_estimate([0.1, 0.2, 0.4], [1.00, 1.01, 0.99])
    assert est.oscillatory


def test_equal_fine_values_mean_converged_and_bad_input_is_refused():
    est = three_mesh_estimate([0.1, 0.2, 0.4], [2.0, 2.0, 2.1])
    assert math.isnan(est.order) and est.extrapolated == 2.0 and est.gci_fine == 0.0
    with pytest.raises(FEModelError, match="differ"):
        three_mesh_estimate([0.1, 0.1, 0.4], [1, 2, 3])
    with pytest.raises(FEModelError, match="three"):
        three_mesh_estimate([0.1, 0.2], [1, 2])
    with pytest.raises(FEModelError, match="positive"):
        three_mesh_estimate([0.0, 0.2, 0.4], [1, 2, 3])


def _plate_fundamental(n: int, a: float = 1.0, b: float = 0.8, h: float = 0.002) -> float:
    """First frequency (Hz) of a simply supported aluminium plate a × b × h (m) meshed with
    n × round(0.8 n) shell elements.

    Navier's solution is that of the "hard" simple support: w = 0 and no rotation about the
    edge's normal (the Kirchhoff edge w = 0 has ∂w/∂s = 0 along it). The shell elements follow
    first-order shear deformation, where leaving that rotation free (the "soft" support) adds
    a boundary layer that lowers the frequency by O(h/a) — 0.46 % at h/a = 0.01, measured — so
    the hard support is imposed (r_x on the edges x = const, r_y on y = const); in-plane and
    drilling DOFs are held.
    """
    nx, ny = n, round(n * b / a)
    xs, ys = np.linspace(0, a, nx + 1), np.linspace(0, b, ny + 1)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    nodes = np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)])
    idx = np.arange(X.size).reshape(X.shape)
    quads = np.column_stack(
        [idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()])
    mesh = Mesh(nodes=nodes, quads=quads, quad_group=np.zeros(len(quads), dtype=np.int64))
    K, M = assemble(mesh, [ShellSection(h, material=ALUMINIUM)], [])
    x_edge = np.flatnonzero((np.isclose(X, 0) | np.isclose(X, a)).ravel())
    y_edge = np.flatnonzero((np.isclose(Y, 0) | np.isclose(Y, b)).ravel())
    fixed = np.zeros(K.shape[0], dtype=bool)
    fixed[6 * np.union1d(x_edge, y_edge) + 2] = True  # w
    fixed[6 * x_edge + 3] = fixed[6 * y_edge + 4] = True  # no rotation about the edge normal
    fixed[0::6] = fixed[1::6] = fixed[5::6] = True
    free = np.flatnonzero(~fixed)
    return float(solve_modes(K[free][:, free], M[free][:, free], n_modes=1,
                             sigma_hz=0.0).frequencies[0])


def test_shell_plate_converges_at_second_order_to_navier():
    """Bilinear shells converge at second order in frequency; the extrapolation from 1/15,
    1/20 and 1/30 m elements lies much nearer Navier's value than the finest mesh (the
    remaining difference, shear deformation and rotary inertia of the 2 mm plate, is 2e-5),
    and the fine mesh's GCI band holds it."""
    a, b, h = 1.0, 0.8, 0.002
    m = ALUMINIUM
    d = m.E * h**3 / (12 * (1 - m.nu**2))
    exact = np.pi / 2 * (1 / a**2 + 1 / b**2) * np.sqrt(d / (m.rho * h))
    ns = (15, 20, 30)
    est = three_mesh_estimate([a / n for n in ns], [_plate_fundamental(n) for n in ns])
    assert 1.8 < est.order < 2.2, est
    assert not est.oscillatory
    finest = est.values[0]
    assert abs(est.extrapolated / exact - 1) < 0.1 * abs(finest / exact - 1), est
    assert abs(exact / finest - 1) <= est.gci_fine, est


def test_two_meshes_at_the_right_order_extrapolate_exactly():
    """f₀ + C·h² on two meshes with order 2 assumed gives f₀; the GCI is Roache's two-mesh
    band, 3 |ε|/(r² − 1) relative to the fine value; a wrong assumed order is not exact."""
    from flexride.fem.convergence import two_mesh_estimate

    f0, c = 6.0, 4.0
    est = two_mesh_estimate([0.3, 0.2], [f0 + c * 0.09, f0 + c * 0.04], 2.0)
    assert est.extrapolated == pytest.approx(f0, rel=1e-12) and est.order_assumed
    eps = abs(c * (0.09 - 0.04) / (f0 + c * 0.04))
    assert est.gci_fine == pytest.approx(3.0 * eps / (1.5**2 - 1), rel=1e-12)
    assert abs(two_mesh_estimate([0.3, 0.2], [f0 + c * 0.09, f0 + c * 0.04], 1.0)
               .extrapolated - f0) > 0.01
    with pytest.raises(FEModelError, match="order"):
        two_mesh_estimate([0.3, 0.2], [1.0, 1.1], 0.0)

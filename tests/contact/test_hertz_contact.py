"""Hertz normal contact constant of :func:`flexride.contact.hertz.hertz_contact`.

Oracles: Hertz's closed form for a circular contact, δ = (9N²/(16E*²R))^(1/3); for elliptic
contacts the approach computed here by quadrature of the Boussinesq kernel over the Hertz
pressure p0·√(1 − x²/a² − y²/b²) at the centre of the ellipse (the semi-axes from the existing
:func:`hertz_ellipse`), which does not use the elliptic-integral formula under test.
"""

from __future__ import annotations

import math

import pytest
from scipy.integrate import quad

from flexride.contact.hertz import hertz_constant, hertz_contact, hertz_ellipse

E, NU = 2.1e11, 0.28
E_STAR = E / (2.0 * (1.0 - NU * NU))


@pytest.mark.parametrize("radius", [0.05, 0.2, 0.46])
def test_circle_matches_hertz(radius: float) -> None:
    ca, cb, g = hertz_contact(0.5 / radius, 0.5 / radius, E, NU)
    assert ca == pytest.approx(cb, rel=1e-9)
    for n in (1e3, 5e4):
        delta = (9.0 * n * n / (16.0 * E_STAR**2 * radius)) ** (1.0 / 3.0)
        assert g * n ** (2.0 / 3.0) == pytest.approx(delta, rel=1e-9)


@pytest.mark.parametrize(("A", "B"), [(1.09, 1.67), (1.09, 0.3), (0.36, 40.0), (5.0, 0.05)])
def test_ellipse_centre_displacement_by_quadrature(A: float, B: float) -> None:
    n = 5.0e4
    ca, cb, g = hertz_contact(A, B, E, NU)
    ea, eb = hertz_ellipse(A, B, E, NU)
    assert (ca, cb) == pytest.approx((ea, eb), rel=1e-12)
    a, b = ca * n ** (1 / 3), cb * n ** (1 / 3)
    p0 = 3.0 * n / (2.0 * math.pi * a * b)

    # centre displacement of both bodies: (1/(πE*))∬ p/r dA; in polar coordinates the radial
    # integral of √(1 − ρ²/ρe²) is π·ρe/4, ρe(θ) the ellipse radius
    def rho(theta: float) -> float:
        return a * b / math.sqrt((b * math.cos(theta)) ** 2 + (a * math.sin(theta)) ** 2)

    ring, _ = quad(rho, 0.0, 2.0 * math.pi, limit=400, epsabs=0.0, epsrel=1e-12)
    delta = p0 * (math.pi / 4.0) * ring / (math.pi * E_STAR)
    assert g * n ** (2.0 / 3.0) == pytest.approx(delta, rel=1e-8)


def test_order_of_zhai_constants_on_a_tread() -> None:
    # S1002-like tread (r0 = 0.46 m) on an R300 crown: Hertz vs Zhai's empirical fits
    _, _, g = hertz_contact(0.5 / 0.46, 0.5 / 0.3, E, NU)
    assert 0.8 < g / hertz_constant(0.46, "conical") < 1.2
    assert 0.9 < g / hertz_constant(0.46, "worn") < 1.4

"""Tests of Kalker's linear creep coefficients.

Oracle: the reference table (Kalker 1990, Table E.3) pasted below verbatim from
``reference/kalker-coefficients.md`` and parsed here independently of the module's own
transcription, plus Kalker's slender-ellipse asymptotes typed from the same file.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexride.contact import creep_coefficients, kalker_coefficients, kalker_from_axes
from flexride.contact.kalker import _asymptote
from flexride.errors import ScenarioError

_A_LE_B = """
| 0.1 | 2.51 / 3.31 / 4.85 | 2.51 / 2.52 / 2.53 | 0.334 / 0.473 / 0.731 | 6.42 / 8.28 / 11.7 |
| 0.2 | 2.59 / 3.37 / 4.81 | 2.59 / 2.63 / 2.66 | 0.483 / 0.603 / 0.809 | 3.46 / 4.27 / 5.66 |
| 0.3 | 2.68 / 3.44 / 4.80 | 2.68 / 2.75 / 2.81 | 0.607 / 0.715 / 0.889 | 2.49 / 2.96 / 3.72 |
| 0.4 | 2.78 / 3.53 / 4.82 | 2.78 / 2.88 / 2.98 | 0.720 / 0.823 / 0.977 | 2.02 / 2.32 / 2.77 |
| 0.5 | 2.88 / 3.62 / 4.83 | 2.88 / 3.01 / 3.14 | 0.827 / 0.929 / 1.07 | 1.74 / 1.93 / 2.22 |
| 0.6 | 2.98 / 3.72 / 4.91 | 2.98 / 3.14 / 3.31 | 0.930 / 1.03 / 1.18 | 1.56 / 1.68 / 1.86 |
| 0.7 | 3.09 / 3.81 / 4.97 | 3.09 / 3.28 / 3.48 | 1.03 / 1.14 / 1.29 | 1.43 / 1.50 / 1.60 |
| 0.8 | 3.19 / 3.91 / 5.05 | 3.19 / 3.41 / 3.65 | 1.13 / 1.25 / 1.40 | 1.34 / 1.37 / 1.42 |
| 0.9 | 3.29 / 4.01 / 5.12 | 3.29 / 3.54 / 3.82 | 1.23 / 1.36 / 1.51 | 1.27 / 1.27 / 1.27 |
| 1.0 | 3.40 / 4.12 / 5.20 | 3.40 / 3.67 / 3.98 | 1.33 / 1.47 / 1.63 | 1.21 / 1.19 / 1.16 |
"""

_A_GT_B = """
| 0.9 | 3.51 / 4.22 / 5.30 | 3.51 / 3.81 / 4.16 | 1.44 / 1.59 / 1.77 | 1.16 / 1.11 / 1.06 |
| 0.8 | 3.65 / 4.36 / 5.42 | 3.65 / 3.99 / 4.39 | 1.58 / 1.75 / 1.94 | 1.10 / 1.04 / 0.954 |
| 0.7 | 3.82 / 4.54 / 5.58 | 3.82 / 4.21 / 4.67 | 1.76 / 1.95 / 2.18 | 1.05 / 0.965 / 0.852 |
| 0.6 | 4.06 / 4.78 / 5.80 | 4.06 / 4.50 / 5.04 | 2.01 / 2.23 / 2.50 | 1.01 / 0.892 / 0.751 |
| 0.5 | 4.37 / 5.10 / 6.11 | 4.37 / 4.90 / 5.56 | 2.35 / 2.62 / 2.96 | 0.958 / 0.819 / 0.650 |
| 0.4 | 4.84 / 5.57 / 6.57 | 4.84 / 5.48 / 6.31 | 2.88 / 3.24 / 3.70 | 0.912 / 0.747 / 0.549 |
| 0.3 | 5.57 / 6.34 / 7.34 | 5.57 / 6.40 / 7.51 | 3.79 / 4.32 / 5.01 | 0.868 / 0.674 / 0.446 |
| 0.2 | 6.96 / 7.78 / 8.82 | 6.96 / 8.14 / 9.79 | 5.72 / 6.63 / 7.89 | 0.828 / 0.601 / 0.341 |
| 0.1 | 10.7 / 11.7 / 12.9 | 10.7 / 12.8 / 16.0 | 12.2 / 14.6 / 18.0 | 0.795 / 0.526 / 0.228 |
"""

NUS = (0.0, 0.25, 0.5)


def _parse(text: str) -> dict[tuple[float, float], tuple[float, float, float, float]]:
    """{(g, ν): (C11, C22, C23, C33)} from markdown rows ``| g | c/c/c | … |``."""
    out: dict[tuple[float, float], tuple[float, float, float, float]] = {}
    for line in text.strip().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        g = float(cells[0])
        per_coef = [[float(v) for v in cell.split("/")] for cell in cells[1:]]
        for j, nu in enumerate(NUS):
            out[(g, nu)] = tuple(per_coef[c][j] for c in range(4))  # type: ignore[assignment]
    return out


TAB_LE = _parse(_A_LE_B)
TAB_GT = _parse(_A_GT_B)
TAB_GT.update({(1.0, nu): TAB_LE[(1.0, nu)] for nu in NUS})  # a = b: same circle


@pytest.mark.parametrize(("key", "expected"), sorted(TAB_LE.items()))
def test_table_a_le_b_reproduced_exactly_at_grid_points(key, expected) -> None:
    g, nu = key
    assert kalker_coefficients(g, nu, a_le_b=True) == expected


@pytest.mark.parametrize(("key", "expected"), sorted(TAB_GT.items()))
def test_table_a_gt_b_reproduced_exactly_at_grid_points(key, expected) -> None:
    g, nu = key
    assert kalker_coefficients(g, nu, a_le_b=False) == expected


@pytest.mark.parametrize("a_le_b", [True, False])
@pytest.mark.parametrize(("g_lo", "g_hi"), [(0.1, 0.2), (0.5, 0.6), (0.9, 1.0)])
@pytest.mark.parametrize(("nu_lo", "nu_hi"), [(0.0, 0.25), (0.25, 0.5)])
def test_bilinear_midpoint_is_mean_of_the_four_corners(a_le_b, g_lo, g_hi, nu_lo, nu_hi) -> None:
    tab = TAB_LE if a_le_b else TAB_GT
    corners = np.array([tab[(g, nu)] for g in (g_lo, g_hi) for nu in (nu_lo, nu_hi)])
    got = kalker_coefficients(0.5 * (g_lo + g_hi), 0.5 * (nu_lo + nu_hi), a_le_b)
    assert got == pytest.approx(tuple(corners.mean(axis=0)), rel=1e-12)


def test_linear_in_nu_at_steel_value() -> None:
    # ν = 0.28 lies 12 % of the way from 0.25 to 0.5.
    lo, hi = np.array(TAB_LE[(0.5, 0.25)]), np.array(TAB_LE[(0.5, 0.5)])
    expected = lo + 0.12 * (hi - lo)
    assert kalker_coefficients(0.5, 0.28, True) == pytest.approx(tuple(expected), rel=1e-12)


@pytest.mark.parametrize("g", [0.1, 0.37, 0.5, 0.93, 1.0, 0.05])
@pytest.mark.parametrize("a_le_b", [True, False])
def test_c22_equals_c11_at_nu_zero(g: float, a_le_b: bool) -> None:
    # With ν = 0 the longitudinal and lateral problems are the same (table and asymptotes).
    c11, c22, _, _ = kalker_coefficients(g, 0.0, a_le_b)
    assert c22 == pytest.approx(c11, rel=1e-12)


def test_c22_equals_c11_at_nu_zero_in_the_reference_table() -> None:
    for tab in (TAB_LE, TAB_GT):
        for (_, nu), (c11, c22, _, _) in tab.items():
            if nu == 0.0:
                assert c11 == c22


def _asym_oracle(g: float, nu: float, a_le_b: bool) -> tuple[float, float, float]:
    """C11, C22, C23 asymptotes as printed in the reference (no C33 given for a ≫ b)."""
    pi = math.pi
    if a_le_b:
        return (
            pi**2 / (4 * (1 - nu)),
            pi**2 / 4,
            pi * math.sqrt(g) / (3 * (1 - nu)) * (1 + nu * (math.log(16 / g) - 5)),
        )
    al = math.log(16 / g**2)
    den = (1 - nu) * al + 2 * nu
    return (
        2 * pi / ((al - 2 * nu) * g) * (1 + (3 - math.log(4)) / (al - 2 * nu)),
        2 * pi / g * (1 + (1 - nu) * (3 - math.log(4)) / den) / den,
        2 * pi / (3 * g**1.5 * ((1 - nu) * al - 2 + 4 * nu)),
    )


@pytest.mark.parametrize("nu", (*NUS, 0.28))
@pytest.mark.parametrize("a_le_b", [True, False])
def test_asymptotes_match_the_reference_formulas(nu: float, a_le_b: bool) -> None:
    for g in (0.001, 0.03, 0.1):
        assert tuple(_asymptote(g, nu, a_le_b)[:3]) == pytest.approx(
            _asym_oracle(g, nu, a_le_b), rel=1e-12
        )
    if a_le_b:
        assert _asymptote(0.02, nu, True)[3] == pytest.approx(
            math.pi**2 / (16 * (1 - nu) * 0.02), rel=1e-12
        )


@pytest.mark.parametrize("nu", NUS)
@pytest.mark.parametrize("a_le_b", [True, False])
def test_asymptotes_agree_with_table_at_g_point_one(nu: float, a_le_b: bool) -> None:
    # The asymptotes are the leading terms of expansions in g (and 1/ln g for a ≫ b), exact
    # only as g → 0; at g = 0.1 they are still within 6 % of the table (largest: C23 at
    # ν = 0.5, a ≪ b). 8 % leaves margin without hiding a wrong formula (a typo in a factor
    # or exponent moves them by tens of %).
    tab = TAB_LE if a_le_b else TAB_GT
    assert _asymptote(0.1, nu, a_le_b) == pytest.approx(tab[(0.1, nu)], rel=0.08)


@pytest.mark.parametrize("nu", [0.0, 0.28, 0.5])
@pytest.mark.parametrize("a_le_b", [True, False])
def test_coefficients_continuous_at_g_point_one(nu: float, a_le_b: bool) -> None:
    inside = kalker_coefficients(0.1, nu, a_le_b)
    below = kalker_coefficients(0.1 - 1e-9, nu, a_le_b)
    assert below == pytest.approx(inside, rel=1e-6)


@pytest.mark.parametrize("nu", [0.0, 0.28, 0.5])
def test_coefficients_tend_to_asymptotes_as_g_vanishes(nu: float) -> None:
    g = 1e-4
    assert kalker_coefficients(g, nu, True) == pytest.approx(
        (*_asym_oracle(g, nu, True), math.pi**2 / (16 * (1 - nu) * g)), rel=2e-3
    )
    c = kalker_coefficients(g, nu, False)
    assert c[:3] == pytest.approx(_asym_oracle(g, nu, False), rel=2e-3)
    # No spin asymptote for a ≫ b in the reference: C33 is held at its g = 0.1 table value.
    assert c[3] == pytest.approx(np.interp(nu, NUS, [TAB_GT[(0.1, v)][3] for v in NUS]))


def test_kalker_from_axes_picks_the_branch() -> None:
    assert kalker_from_axes(3e-3, 6e-3, 0.25) == TAB_LE[(0.5, 0.25)]
    assert kalker_from_axes(6e-3, 3e-3, 0.25) == TAB_GT[(0.5, 0.25)]
    assert kalker_from_axes(4e-3, 4e-3, 0.5) == TAB_LE[(1.0, 0.5)]


def test_kalker_from_axes_continuous_across_a_equals_b() -> None:
    just_le = kalker_from_axes(1.0, 1.0 + 1e-9, 0.28)
    just_gt = kalker_from_axes(1.0 + 1e-9, 1.0, 0.28)
    assert just_le == pytest.approx(just_gt, rel=1e-7)


def test_creep_coefficients_by_hand() -> None:
    # a/b = 0.5, ν = 0.25: C = 3.62, 3.01, 0.929, 1.93; ab = 1.8e-5 m².
    a, b, shear = 3e-3, 6e-3, 8e10
    f11, f22, f23, f33 = creep_coefficients(a, b, shear, 0.25)
    assert f11 == pytest.approx(8e10 * 1.8e-5 * 3.62, rel=1e-12)
    assert f22 == pytest.approx(8e10 * 1.8e-5 * 3.01, rel=1e-12)
    assert f23 == pytest.approx(8e10 * 1.8e-5**1.5 * 0.929, rel=1e-12)
    assert f33 == pytest.approx(8e10 * 1.8e-5**2 * 1.93, rel=1e-12)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: kalker_coefficients(0.0, 0.28, True), "axis ratio"),
        (lambda: kalker_coefficients(1.2, 0.28, True), "axis ratio"),
        (lambda: kalker_coefficients(math.nan, 0.28, True), "axis ratio"),
        (lambda: kalker_coefficients(0.5, 0.51, True), "Poisson"),
        (lambda: kalker_coefficients(0.5, -0.01, False), "Poisson"),
        (lambda: kalker_from_axes(-1e-3, 1e-3, 0.28), "semi-axis a"),
        (lambda: kalker_from_axes(1e-3, 0.0, 0.28), "semi-axis b"),
        (lambda: creep_coefficients(1e-3, 1e-3, 0.0, 0.28), "shear modulus"),
    ],
)
def test_rejects_bad_inputs(call, match: str) -> None:
    with pytest.raises(ScenarioError, match=match):
        call()

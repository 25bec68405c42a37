"""Statistical (quasi-) linearisation of the wheel–rail contact
(:mod:`flexride.frequency.quasilinear`): the Gaussian-equivalent gain against closed forms,
the conical tread (linear in Δy) unchanged, the profiles' iteration and its flags.

The comparison with the time-domain solver is in test_against_time_domain.py (slow).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import erf

from conftest import CONICAL, preset
from flexride.frequency import LinearisationError, comfort, estimate, linear_model, response
from flexride.frequency import quasilinear as ql
from flexride.frequency.model import LINEARISATIONS

SIGMA = 2.0e-3  # m, a wheelset's lateral motion on the rail


@pytest.mark.parametrize("a", [-3.5, 0.0, 2.0e6])
def test_gain_of_a_linear_function_is_its_slope(a):
    assert ql.gaussian_gain(lambda y: a * y + 7.0, SIGMA) == pytest.approx(a, rel=1e-13,
                                                                           abs=1e-13)


def test_weights_add_up_to_one():
    _h, c = ql.hermite_differences(SIGMA)
    assert c.sum() == pytest.approx(1.0, rel=1e-13)


def test_gain_of_a_cube_is_three_sigma_squared():
    """E[y⁴]/σ² = 3σ² (Gauss–Hermite is exact for polynomials)."""
    assert ql.gaussian_gain(lambda y: y**3, SIGMA) == pytest.approx(3.0 * SIGMA**2, rel=1e-12)
    # about an operating point y0: E[y·(y0 + y)³]/σ² = 3y0² + 3σ²
    y0 = 0.7e-3
    assert ql.gaussian_gain(lambda y: y**3, SIGMA, center=y0) == pytest.approx(
        3.0 * y0**2 + 3.0 * SIGMA**2, rel=1e-12)


def test_gain_of_a_sign_and_of_a_saturation_against_closed_forms():
    """sign(y): k = E|y|/σ² = √(2/π)/σ; a unit-slope saturation at ±a: k = erf(a/(√2σ)).
    Discontinuous and kinked functions converge slowly under Gauss–Hermite (error ~ 1/n): the
    default 20 nodes are within 3 % (sign: +2.1 %) and 2 % (saturation: −1.6 %), 200 nodes
    within 0.3 %."""
    sign_exact = math.sqrt(2.0 / math.pi) / SIGMA
    a = 1.5e-3
    sat_exact = erf(a / (math.sqrt(2.0) * SIGMA))
    for n, rel_sign, rel_sat in ((ql.N_NODES, 0.03, 0.02), (200, 0.003, 0.003)):
        assert ql.gaussian_gain(np.sign, SIGMA, n) == pytest.approx(sign_exact, rel=rel_sign)
        assert ql.gaussian_gain(lambda y: np.clip(y, -a, a), SIGMA, n) == pytest.approx(
            sat_exact, rel=rel_sat)


@pytest.fixture(scope="module")
def cone():
    return preset("paper-random-straight-80", **CONICAL)


def test_cone_jacobians_are_the_local_ones(cone):
    """The machinery on a contact linear in Δy: with σ small enough to stay off the flange
    and out of the creep saturation (whose cubic term is the only nonlinearity of the cone's
    contact: it shows as 10⁻⁵ of B0 at σ = 0.5 mm, growing as σ²), the statistical K, C, B0
    are the local ones to round-off of the differences (the creep columns are plain central
    differences with h = 10⁻⁶ at two states: rounding ε·|A|/h, 2·10⁻⁷ of C's largest entry)."""
    lin = linear_model(cone, linearisation="local").linearisation
    stat = ql.statistical_linearisation(lin, np.full((4, 2), 1e-5))
    for name in ("K", "C", "B0"):
        a, b = getattr(stat.full, name), getattr(lin.full, name)
        assert np.abs(a - b).max() <= 1e-6 * np.abs(b).max(), name
    assert np.abs(stat.daux_dX - lin.daux_dX).max() <= 1e-6 * np.abs(lin.daux_dX).max()


def test_cone_estimate_is_the_same_with_either_linearisation(cone):
    """The default (statistical) leaves a contact linear in Δy exactly as it was."""
    tables = {m: estimate(cone, linearisation=m).comfort.to_dict() for m in LINEARISATIONS}
    for t in tables.values():
        t.pop("method")
    assert tables["statistical"] == tables["local"]


@pytest.fixture(scope="module")
def profiles():
    sc = preset("paper-random-straight-80")
    return {m: linear_model(sc, linearisation=m) for m in LINEARISATIONS}


def test_profiles_iteration_converges_and_replaces_the_conicity_flag(profiles):
    model = profiles["statistical"]
    q = model.quasi_linear
    assert q.applied and q.converged and 1 <= q.iterations <= ql.MAX_ITERATIONS
    assert q.history[-1] < ql.SIGMA_RTOL
    summary = model.to_dict()["linearisation"]
    assert summary["method"] == "statistical" and summary["converged"]
    # the σ the gains were made at is the response's own (within the tolerance)
    sigma = ql.wheel_sigma(*_wheel_variance(model), 4)
    used = np.array(list(q.sigma.values())).reshape(4, 2)
    np.testing.assert_allclose(sigma, used, rtol=ql.SIGMA_RTOL)
    # 1.5–3 mm: the wheelsets move over the contact-point jump and the kink of Δr
    assert np.all((used > 1.0e-3) & (used < 3.0e-3))
    flags = {m: comfort(response(mod)).flags for m, mod in profiles.items()}
    assert not any("contact geometry not linear" in f for f in flags["statistical"])
    assert sum("contact geometry not linear" in f for f in flags["local"]) == 4
    # the model the flags read is still the local one (what sweeps reuse)
    assert model.linearisation is not q.linearisation


def _wheel_variance(model):
    resp = response(model, points=["PC"])
    return resp.wheel_channels, resp.variance(resp.wheel_psd)


def test_profiles_quasi_linear_contact_is_stiffer_laterally(profiles):
    """The Gaussian-equivalent lateral stiffness of the contact over millimetres is above its
    slope about the centre (the contact-point jump and the rising Δr): the lateral car-body
    response falls, the vertical one does not change."""
    q = profiles["statistical"].quasi_linear
    assert all(g > 1.0 for g in q.lateral_gain.values())
    pc = {m: comfort(response(mod, points=["PC"])).point("PC") for m, mod in profiles.items()}
    assert pc["statistical"].directions["y"].rms < 0.9 * pc["local"].directions["y"].rms
    assert pc["statistical"].directions["z"].rms == pytest.approx(
        pc["local"].directions["z"].rms, rel=0.01)


def test_gains_are_continuous_across_a_rung_of_the_sampling_ladder(profiles):
    """Just below and just above a rung the blended gains differ by O(ε) (they jump with the
    nearest rung alone); at a rung they are the rung's own Gauss–Hermite sums."""
    lin = profiles["local"].linearisation
    samples = ql.PathSamples()
    rung = ql.rung_sigma(ql.ladder(1.7e-3)[0])
    eps = 1e-6
    below, at, above = (samples.gains(lin, 0, 0, rung * (1.0 + d)) for d in (-eps, 0.0, eps))
    scale = np.abs(at[0]).max()
    assert np.abs(below[0] - above[0]).max() <= 1e-4 * scale
    own = ql.sample_wheel(lin, 0, 0, rung)
    h, c = ql.hermite_differences(rung)
    np.testing.assert_allclose(own.steps, h, rtol=1e-12)
    np.testing.assert_allclose(at[0], c @ own.diff_acc, rtol=1e-9, atol=1e-9 * scale)


def test_iteration_converges_near_the_stability_limit():
    """A soft primary lateral suspension (100 kN/m per axle box at 80 km/h, just above the
    hunting limit of the quasi-linear model) makes g(σ) fall steeply: the secant relaxation
    converges where a fixed one cycled (σ changing by 40–100 % after 8 iterations), and the
    σ the gains were made at is the response's own."""
    model = linear_model(preset("paper-random-straight-80", vehicle__primary__ky=1.0e5))
    q = model.quasi_linear
    assert q.converged and q.history[-1] < ql.SIGMA_RTOL
    sigma = ql.wheel_sigma(*_wheel_variance(model), 4)
    used = np.array(list(q.sigma.values())).reshape(4, 2)
    np.testing.assert_allclose(sigma, used, rtol=ql.SIGMA_RTOL)


def test_no_convergence_is_refused_or_flagged(monkeypatch):
    monkeypatch.setattr(ql, "MAX_ITERATIONS", 1)
    sc = preset("paper-random-straight-80")
    with pytest.raises(LinearisationError) as err:
        linear_model(sc)
    assert err.value.reason == "quasi_linear"
    model = linear_model(sc, strict=False)
    assert not model.quasi_linear.converged
    assert any("did not converge" in f for f in model.flags)
    assert "NOT converged" in comfort(response(model, points=["PC"])).method


def test_unknown_linearisation_is_refused():
    with pytest.raises(LinearisationError) as err:
        linear_model(preset("paper-random-straight-80"), linearisation="linear")
    assert err.value.reason == "linearisation"

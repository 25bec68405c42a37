"""A user's tabulated track spectrum (``spectrum: table``): the oracle is the German spectrum
itself, tabulated at log-spaced points. Its log–log interpolation, the realisation the
generator draws from it (the same random streams as the German one, so the same profile up to
the interpolation) and the frequency-domain estimate must all be the German spectrum's."""

from __future__ import annotations

import numpy as np
import pytest

from flexride.errors import ScenarioError
from flexride.scenario.excitation import IRREGULARITY_COMPONENTS, SpectrumTable
from flexride.scenario.presets import CONICAL_TREAD, load_preset
from flexride.track.excitation import build_profile
from flexride.track.spectra import GERMAN_HALF_GAUGE, german_psd, random_profile, table_psd

OMEGA = np.geomspace(2.0 * np.pi / 200.0, 2.0 * np.pi / 0.5, 400)


def german_table(components=IRREGULARITY_COMPONENTS) -> dict:
    """The German high spectra at 400 log-spaced Ω over 0.5–200 m wavelength."""
    return {"omega_rad_per_m": OMEGA.tolist(),
            **{c: german_psd(OMEGA, c, "high", GERMAN_HALF_GAUGE).tolist() for c in components}}


@pytest.mark.parametrize("component", IRREGULARITY_COMPONENTS)
def test_the_interpolated_table_is_the_spectrum_between_its_points(component):
    table = SpectrumTable(**german_table())
    mid = np.sqrt(OMEGA[:-1] * OMEGA[1:])  # halfway on the log scale, the worst place
    got = table_psd(mid, table, component)
    assert got == pytest.approx(german_psd(mid, component, "high"), rel=2e-3)
    outside = table_psd(np.array([OMEGA[0] / 2, OMEGA[-1] * 2]), table, component)
    assert outside.tolist() == [0.0, 0.0]


def test_the_generator_draws_the_german_realisation_from_its_table():
    """Same seed, same streams: the realisation from the table equals the German one within
    the interpolation's error (well below 1 % of the rms)."""
    table = SpectrumTable(**german_table())
    a = random_profile(600.0, "high", IRREGULARITY_COMPONENTS, 1.0, 120.0, seed=4)
    b = random_profile(600.0, "table", IRREGULARITY_COMPONENTS, 1.0, 120.0, seed=4, table=table)
    for ra, rb in zip(a.rails(), b.rails(), strict=True):
        assert np.sqrt(np.mean((ra - rb) ** 2)) < 2e-3 * np.sqrt(np.mean(ra**2))


def test_a_scenario_runs_and_estimates_its_table_as_the_german_spectrum():
    """Through the scenario: the solver's irregularity and the frequency-domain estimate."""
    from flexride.frequency import estimate

    exc = {"kind": "random", "spectrum": "table", "table": german_table(), "seed": 1}
    tab = load_preset("paper-random-straight-80", {**CONICAL_TREAD, "excitation": [exc]})
    ger = load_preset("paper-random-straight-80", CONICAL_TREAD)
    pa = build_profile(ger.excitation, 300.0, half_gauge=ger.track.rail_centre_half_distance)
    pb = build_profile(tab.excitation, 300.0, half_gauge=tab.track.rail_centre_half_distance)
    assert np.sqrt(np.mean((pa.z_left - pb.z_left) ** 2)) < 2e-3 * np.sqrt(
        np.mean(pa.z_left**2))
    ea, eb = estimate(ger, ["PC"]), estimate(tab, ["PC"])
    for d in ("y", "z"):
        da, db = ea.comfort.points[0].directions[d], eb.comfort.points[0].directions[d]
        assert db.rms == pytest.approx(da.rms, rel=2e-3) and db.sperling == pytest.approx(
            da.sperling, rel=1e-3)


@pytest.mark.parametrize(("exc", "words"), [
    ({"spectrum": "table"}, "give 'table' exactly when spectrum is 'table'"),
    ({"table": {"omega_rad_per_m": [1.0, 2.0], "vertical": [1e-6, 1e-7]}},
     "give 'table' exactly when spectrum is 'table'"),
    ({"spectrum": "table", "table": {"omega_rad_per_m": [2.0, 1.0], "vertical": [1e-6, 1e-7]}},
     "strictly increasing"),
    ({"spectrum": "table", "table": {"omega_rad_per_m": [1.0, 2.0], "vertical": [1e-6]}},
     "1 values for 2 frequencies"),
    ({"spectrum": "table", "table": {"omega_rad_per_m": [1.0, 2.0], "vertical": [1e-6, -1.0]}},
     ">= 0"),
    ({"spectrum": "table", "table": {"omega_rad_per_m": [1.0, 2.0], "vertical": [1e-6, 1e-7]}},
     "no spectrum of alignment, cross_level, gauge"),
])
def test_bad_tables_are_refused_at_the_excitation(exc, words):
    with pytest.raises(ScenarioError, match=words) as err:
        load_preset("paper-random-straight-80",
                    {"excitation": [{"kind": "random", **exc}]})
    assert any(i.loc[:2] == ("excitation", 0) for i in err.value.items), err.value.items
